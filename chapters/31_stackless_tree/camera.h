// The camera on the host side: the basis the shader needs, computed once per image
// instead of once per pixel, and the thin lens round the eye.
#pragma once
#include <glm/glm.hpp>

#include "shared.h"  // gpu::ThinLensCamera

// Where the camera is and how it is built: the conventions of
// python_prototypes/camera_rays.py, which the chapter 03 check compares ray by ray.
struct Camera {
    glm::vec3 eye;
    glm::vec3 forward, right, up;  // orthonormal and right-handed
    float focalLength;             // metres from the eye to the sensor
    float sensorWidth;             // metres
};

// Builds the basis: forward along `look`, right perpendicular to `up`, and up
// recomputed so the three are at right angles. Bad vectors are exit code 2.
Camera makeCamera(glm::vec3 eye, glm::vec3 look, glm::vec3 up, float focalLength,
                  float sensorWidth);

// The camera as the PathParameters uniform block holds it (shared.h), with a lens of
// that radius (0: a pinhole) focused at that distance along `forward`.
gpu::ThinLensCamera thinLensCamera(const Camera& camera, float lensRadius,
                                   float focusDistance);
