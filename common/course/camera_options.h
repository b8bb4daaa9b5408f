// The camera's command-line options of the chapters where the user places the camera by
// hand (later, the scene frames it). The chapter turns them into its basis with
// its own makeCamera; that part is the lesson, this is only the reading of numbers.
#pragma once
#include <glm/vec3.hpp>

#include "course/cli.h"

namespace course {

// --camera-eye, --camera-look, --camera-up, --focal-length, --sensor-width, read into
// these by the command line (which refuses anything but finite numbers).
struct CameraOptions {
    glm::vec3 eye{0.0f, 1.0f, 4.0f};
    glm::vec3 look{0.0f, -0.25f, -1.0f};
    glm::vec3 up{0.0f, 1.0f, 0.0f};
    float focalLength = 0.035f;  // a 35 mm lens ...
    float sensorWidth = 0.036f;  // ... on a 36 mm wide "full frame" sensor

    void declare(CommandLine& cli);
};

}  // namespace course
