// The environment light on the host: the radiance map read and checked, and the two
// tables that let the shader pick its bright pixels often (importance sampling):
// python_prototypes/environment_sampling.py in C++.
#pragma once
#include <vector>

#include <glm/glm.hpp>

#include "course/scene_file.h"
#include "shared.h"  // gpu::PathParameters

struct EnvironmentMap {
    int width = 0, height = 0;        // 0 x 0: the scene has no environment
    std::vector<glm::vec4> radiance;  // row 0 the map's top (the zenith); w unused
    // The marginal CDF over rows (height + 1 numbers from 0 to 1), then each row's
    // conditional CDF over its columns (width + 1 numbers each): one buffer.
    std::vector<float> distributions;
};

// Reads the scene's map (exit code 3 at its line for a NaN, an infinity or a negative
// value), scales it, and builds the tables.
EnvironmentMap loadEnvironment(const course::SceneFile& scene);

// Appends the map's radiance to the texels (after the images') and fills the
// environment's fields of the uniform block: where the map is, its size (0 x 0 without
// one), its turn, and next-event estimation's chance of sampling it.
void addEnvironment(EnvironmentMap& map, const course::SceneFile& scene,
                    bool hasEmittingShapes, std::vector<glm::vec4>& texels,
                    gpu::PathParameters& parameters);
