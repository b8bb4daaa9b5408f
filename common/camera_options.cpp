#include "course/camera_options.h"

namespace course {

void CameraOptions::declare(CommandLine& cli) {
    // Typed options: the command line reads the numbers and refuses what is not one.
    cli.option("--camera-eye", "X,Y,Z", "camera position", &eye);
    cli.option("--camera-look", "X,Y,Z", "viewing direction", &look);
    cli.option("--camera-up", "X,Y,Z", "roughly upwards", &up);
    cli.option("--focal-length", "M", "metres", &focalLength);
    cli.option("--sensor-width", "M", "metres", &sensorWidth);
}

}  // namespace course
