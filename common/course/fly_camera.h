// A fly-through camera for window mode: W A S D move, Q E go down and up, dragging with
// the left mouse button turns the view. The math (FlyCamera::update) knows nothing of
// GLFW, so it can be tested without a window; readFlyInput() is the GLFW side.
#pragma once
#include <glm/glm.hpp>

struct GLFWwindow;

namespace course {

// What the user asks for during one frame.
struct FlyInput {
    glm::vec3 move{0.0f};  // x right, y up, z forward; each -1, 0 or 1
    glm::vec2 turn{0.0f};  // mouse movement in pixels while the button is held
    float seconds = 0.0f;  // how long the frame lasted
};

struct FlyCamera {
    glm::vec3 eye{0.0f};
    float yaw = 0.0f;    // radians about +y; 0 looks along -z, positive turns to the left
    float pitch = 0.0f;  // radians above the horizon, kept within +-89 degrees
    float speed = 1.0f;  // metres per second
    float radiansPerPixel = 0.003f;

    // From a viewing direction (any length); y is up.
    static FlyCamera looking(glm::vec3 eye, glm::vec3 look, float speed);
    glm::vec3 forward() const;  // unit length
    glm::vec3 right() const;    // unit length, horizontal
    // Applies one frame's input; true when the camera moved or turned (a progressive
    // renderer then starts its picture over).
    bool update(const FlyInput& input);
};

// This frame's keys and mouse movement. `lastCursor` remembers the cursor between
// frames (negative x: not yet known); `seconds` is the frame's duration.
FlyInput readFlyInput(GLFWwindow* window, glm::dvec2& lastCursor, float seconds);

}  // namespace course
