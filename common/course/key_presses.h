// Keys a chapter's window reacts to once per press (not once per frame while held),
// without the chapter including GLFW (an exposure and a tone mapping changed by keys).
#pragma once

struct GLFWwindow;

namespace course {

enum class Key { Minus, Equal, T, Count };

class KeyPresses {
public:
    // True in the first frame the key is down after being up; false without a window.
    bool pressed(GLFWwindow* window, Key key);

private:
    bool wasDown_[int(Key::Count)] = {};
};

}  // namespace course
