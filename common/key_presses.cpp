#include "course/key_presses.h"

#include <GLFW/glfw3.h>

namespace course {

bool KeyPresses::pressed(GLFWwindow* window, Key key) {
    if (!window) return false;
    static const int codes[] = {GLFW_KEY_MINUS, GLFW_KEY_EQUAL, GLFW_KEY_T};
    const bool down = glfwGetKey(window, codes[int(key)]) == GLFW_PRESS;
    const bool wasDown = wasDown_[int(key)];
    wasDown_[int(key)] = down;
    return down && !wasDown;
}

}  // namespace course
