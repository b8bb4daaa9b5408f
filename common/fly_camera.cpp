#include "course/fly_camera.h"

#include <algorithm>
#include <cmath>

#include <GLFW/glfw3.h>

namespace course {

FlyCamera FlyCamera::looking(glm::vec3 eye, glm::vec3 look, float speed) {
    FlyCamera camera;
    camera.eye = eye;
    glm::vec3 direction = glm::normalize(look);
    // forward() below, solved for the angles: y = sin(pitch), x = -sin(yaw) cos(pitch).
    camera.pitch = std::asin(std::clamp(direction.y, -1.0f, 1.0f));
    camera.yaw = std::atan2(-direction.x, -direction.z);
    camera.speed = speed;
    return camera;
}

glm::vec3 FlyCamera::forward() const {
    float horizontal = std::cos(pitch);
    return {-std::sin(yaw) * horizontal, std::sin(pitch), -std::cos(yaw) * horizontal};
}

glm::vec3 FlyCamera::right() const { return {std::cos(yaw), 0.0f, -std::sin(yaw)}; }

bool FlyCamera::update(const FlyInput& input) {
    bool changed = false;
    if (input.turn != glm::vec2(0.0f)) {
        // Dragging right turns right (yaw decreases); dragging down looks down.
        yaw -= input.turn.x * radiansPerPixel;
        const float limit = glm::radians(89.0f);  // straight up has no "right"
        pitch = std::clamp(pitch - input.turn.y * radiansPerPixel, -limit, limit);
        changed = true;
    }
    if (input.move != glm::vec3(0.0f)) {
        glm::vec3 step = input.move.x * right() + input.move.y * glm::vec3(0, 1, 0) +
                         input.move.z * forward();
        eye += step * (speed * input.seconds);
        changed = true;
    }
    return changed;
}

FlyInput readFlyInput(GLFWwindow* window, glm::dvec2& lastCursor, float seconds) {
    FlyInput input;
    input.seconds = seconds;
    auto key = [&](int k) { return glfwGetKey(window, k) == GLFW_PRESS ? 1.0f : 0.0f; };
    input.move = {key(GLFW_KEY_D) - key(GLFW_KEY_A), key(GLFW_KEY_E) - key(GLFW_KEY_Q),
                  key(GLFW_KEY_W) - key(GLFW_KEY_S)};
    glm::dvec2 cursor;
    glfwGetCursorPos(window, &cursor.x, &cursor.y);
    bool dragging = glfwGetMouseButton(window, GLFW_MOUSE_BUTTON_LEFT) == GLFW_PRESS;
    if (dragging && lastCursor.x >= 0.0) input.turn = glm::vec2(cursor - lastCursor);
    lastCursor = cursor;
    return input;
}

}  // namespace course
