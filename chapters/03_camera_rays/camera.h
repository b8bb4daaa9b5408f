// The pinhole camera on the host side: its options on the command line, and the basis
// the shader needs, computed once per image instead of once per pixel.
#pragma once
#include <glm/glm.hpp>

#include "course/cli.h"
#include "course/shader_program.h"

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

// --camera-eye, --camera-look, --camera-up, --focal-length, --sensor-width, read into
// these by the command line (which refuses anything but finite numbers).
struct CameraOptions {
    glm::vec3 eye{0.0f, 1.0f, 4.0f};
    glm::vec3 look{0.0f, -0.25f, -1.0f};
    glm::vec3 up{0.0f, 1.0f, 0.0f};
    float focalLength = 0.035f;  // a 35 mm lens ...
    float sensorWidth = 0.036f;  // ... on a 36 mm wide "full frame" sensor

    void declare(course::CommandLine& cli);
    Camera camera() const;  // builds and checks the basis; exit code 2 if it cannot
};

// Sets the `camera` uniform struct of camera.glsl.
void setCamera(const course::ShaderProgram& program, const Camera& camera);
