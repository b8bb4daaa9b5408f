#include "display.h"

#include <algorithm>
#include <vector>

namespace {

// In the order of the TONE_MAP_ numbers (shared.h).
const std::vector<std::string> kToneMaps = {"clamp", "reinhard", "aces", "false-colour"};

}  // namespace

void declareDisplayOptions(course::CommandLine& cli, DisplayOptions& options) {
    cli.option("--exposure", "EV", "brighten the displayed picture (window, PNG) by 2^EV; "
               "PFM and EXR stay radiance", &options.exposure);
    cli.choice("--tone-map", "how radiance becomes a displayed value (window, PNG): "
               "clip at 1, extended Reinhard, the ACES filmic fit, or luminance in "
               "false colour (keys in the window: - and = for exposure, T for the next)",
               kToneMaps, &options.toneMap);
}

int toneMapCode(const std::string& name) {
    return int(std::find(kToneMaps.begin(), kToneMaps.end(), name) - kToneMaps.begin());
}

void adjustDisplay(GLFWwindow* window, course::KeyPresses& keys,
                   gpu::PathParameters& parameters) {
    if (keys.pressed(window, course::Key::Minus)) parameters.exposure -= 0.5f;
    if (keys.pressed(window, course::Key::Equal)) parameters.exposure += 0.5f;
    if (keys.pressed(window, course::Key::T))
        parameters.toneMap = (parameters.toneMap + 1) % int(kToneMaps.size());
}

void declareViewOption(course::CommandLine& cli, std::string& view) {
    cli.choice("--view", "what the image shows: the path traced light, what the camera "
               "rays hit (normals, distance in metres, albedo with textures, texture "
               "coordinates uv), the traversal's work per pixel (cost) or random bounce "
               "rays (bounce: ambient occlusion)",
               {"radiance", "normals", "distance", "albedo", "uv", "cost", "bounce"}, &view);
}

int viewCode(const std::string& name) {
    return name == "normals"    ? VIEW_NORMALS
           : name == "distance" ? VIEW_DISTANCE
           : name == "cost"     ? VIEW_COST
           : name == "bounce"   ? VIEW_BOUNCE
           : name == "albedo"   ? VIEW_ALBEDO
           : name == "uv"       ? VIEW_UV
                                : VIEW_RADIANCE;
}
