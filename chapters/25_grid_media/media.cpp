#include "media.h"

#include <algorithm>
#include <cstdio>
#include <string>

#include <glm/glm.hpp>

#include "course/text_file.h"
#include "course/volume_grid.h"

namespace {

// --8<-- [start:grid]
// A grid medium: its densities appended to `densities`, its box, its albedo, and the
// majorant that delta and ratio tracking step by: the largest sigma_t anywhere in it
// (trilinear interpolation never exceeds the largest value it mixes).
gpu::Medium gridMedium(const course::SceneFile& scene, const course::SceneMedium& medium,
                       std::vector<float>& densities) {
    const course::VolumeGrid grid = course::readVolumeGrid(medium.path);
    gpu::Medium packed{};
    packed.kind = MEDIUM_GRID;
    packed.g = medium.g;
    packed.boxMin = grid.boxMin;
    packed.boxMax = grid.boxMax;
    packed.scale = medium.scale;
    packed.resolution = glm::uvec3(grid.resolution);
    packed.firstValue = uint32_t(densities.size());
    packed.albedo = medium.albedo;
    const float densest = *std::max_element(grid.density.begin(), grid.density.end());
    packed.majorant = std::max(medium.scale * densest, 1e-6f);  // an empty grid: 1 step
    // The mean number of steps along the box's longest chord: beyond the bound, a walk
    // could run out of steps (MAX_TRACKING_STEPS) more often than never.
    const float steps = packed.majorant * glm::length(grid.boxMax - grid.boxMin);
    if (steps > MAX_EXPECTED_TRACKING_STEPS) {
        char text[240];
        std::snprintf(text, sizeof text,
                      "medium '%s': its densest sigma_t (%g per metre) across its box's "
                      "diagonal means %.0f tracking steps, more than this program's %.0f: "
                      "a smaller scale fits",
                      medium.name.c_str(), double(packed.majorant), double(steps),
                      double(MAX_EXPECTED_TRACKING_STEPS));
        course::failAtLine(scene.path, medium.line, text);
    }
    densities.insert(densities.end(), grid.density.begin(), grid.density.end());
    return packed;
}
// --8<-- [end:grid]

}  // namespace

// --8<-- [start:media]
std::vector<float> addMedia(const course::SceneFile& scene, gpu::PathParameters& parameters) {
    if (scene.media.size() > MAX_MEDIA)
        course::failAtLine(scene.path, scene.media[MAX_MEDIA].line,
                           "more than " + std::to_string(MAX_MEDIA) +
                               " media: this program's table holds " +
                               std::to_string(MAX_MEDIA));
    std::vector<float> densities;
    for (size_t i = 0; i < scene.media.size(); ++i) {
        const course::SceneMedium& medium = scene.media[i];
        if (medium.kind == course::MediumKind::Grid) {
            parameters.media[i] = gridMedium(scene, medium, densities);
        } else {
            parameters.media[i] = {};
            parameters.media[i].kind = MEDIUM_HOMOGENEOUS;
            parameters.media[i].sigmaA = medium.sigmaA;
            parameters.media[i].sigmaS = medium.sigmaS;
            parameters.media[i].g = medium.g;
        }
    }
    parameters.mediumCount = uint32_t(scene.media.size());
    parameters.cameraMedium =
        scene.camera.medium < 0 ? NO_MEDIUM : uint32_t(scene.camera.medium);
    densities.resize(std::max<size_t>(4, (densities.size() + 3) / 4 * 4), 0.0f);
    return densities;
}
// --8<-- [end:media]

size_t trackingSteps(const course::SceneFile& scene, size_t segments) {
    const bool grids = std::any_of(scene.media.begin(), scene.media.end(), [](const auto& m) {
        return m.kind == course::MediumKind::Grid;
    });
    return grids ? (1 + segments) * MAX_TRACKING_STEPS : 0;
}
