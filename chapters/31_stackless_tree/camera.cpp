#include "camera.h"

#include "course/error.h"

namespace {

[[noreturn]] void badCamera(const std::string& message) {
    course::fail(course::ExitCode::BadUsage, "camera: " + message);
}

}  // namespace

// --8<-- [start:basis]
Camera makeCamera(glm::vec3 eye, glm::vec3 look, glm::vec3 up, float focalLength,
                  float sensorWidth) {
    if (glm::length(look) == 0.0f) badCamera("the look direction must not be zero");
    if (glm::length(up) == 0.0f) badCamera("the up direction must not be zero");
    if (!(focalLength > 0.0f) || !(sensorWidth > 0.0f))
        badCamera("focal length and sensor width must be positive");
    glm::vec3 forward = glm::normalize(look);
    glm::vec3 side = glm::cross(forward, up);
    // Looking straight along `up` leaves no way to tell right from left.
    if (glm::length(side) < 1e-6f * glm::length(up))
        badCamera("up must not be parallel to the look direction");
    glm::vec3 right = glm::normalize(side);
    // `up` only had to point roughly upwards; this one is exactly perpendicular to
    // forward and right, and of unit length because they are.
    glm::vec3 trueUp = glm::cross(right, forward);
    return Camera{eye, forward, right, trueUp, focalLength, sensorWidth};
}
// --8<-- [end:basis]

gpu::ThinLensCamera thinLensCamera(const Camera& camera, float lensRadius,
                                   float focusDistance) {
    gpu::ThinLensCamera lens{};
    lens.eye = camera.eye;
    lens.forward = camera.forward;
    lens.right = camera.right;
    lens.up = camera.up;
    lens.focalLength = camera.focalLength;
    lens.sensorWidth = camera.sensorWidth;
    lens.lensRadius = lensRadius;
    lens.focusDistance = focusDistance;
    return lens;
}
