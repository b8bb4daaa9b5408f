// Specialisation: the host writes part of the shader for the scene it is about to
// render, scene_code.glsl, which the path tracer's shaders include. It holds the
// scene's counts, the features it uses (material kinds, textures, environment,
// triangles, a lens) as numbers the
// compiler folds, and which way the shaders read the scene (scene_memory.glsl); for a
// small scene, the scene itself as constant arrays.
#pragma once
#include <cstdint>
#include <string>

#include "course/cli.h"
#include "course/stats.h"
#include "gpu_scene.h"

// --8<-- [start:limits]
// The limits of writing a scene into the shader. Each shape written out costs compile
// time (llvmpipe: 0.04 to 0.06 s a shape) and saves less the more there are (the
// Cornell box's 18 quads run 2.0x faster than through buffer textures, the sky
// showcase's 51 spheres and quads 1.2x): past these, the automatic choice reads the
// scene through buffer textures instead (./course bench speed; the chapter's page).
constexpr size_t kMostShapesInCode = 32;     // spheres and quads
constexpr size_t kMostMaterialsInCode = 64;
constexpr size_t kMostEmittersInCode = 64;
// By hand (--scene-memory constants), up to four times as many: beyond, the shader
// would take minutes to compile.
constexpr size_t kMostInCodeByHand = 4;
// --8<-- [end:limits]

// How the shaders read the scene, from the command line.
struct SceneCodeOptions {
    std::string sceneMemory = "auto";  // --scene-memory: auto, storage, uniform, texture,
                                       // constants
    std::string bvhMemory = "texture";  // --bvh-memory: storage or texture
    bool generic = false;  // --generic: one shader for every scene, as chapter 18's
    BvhOptions tree;       // --bvh-leaves-by-count: tree.leavesByCount
};
void declareSceneCodeOptions(course::CommandLine& cli, SceneCodeOptions& options);

// What was chosen: MEMORY_STORAGE, _UNIFORM, _TEXTURE or _CONSTANTS (shared.h).
struct SceneCodeChoice {
    int sceneMemory = MEMORY_STORAGE;
    int bvhMemory = MEMORY_TEXTURE;
    bool specialised = true;
};

// Resolves "auto" (constants within the limits above, else buffer textures) and checks
// a choice made by hand: constants past kMostInCodeByHand times the limits is exit
// code 2, naming the scene file. (Uniform blocks larger than the GL allows are exit
// code 4, when they are bound.)
SceneCodeChoice chooseSceneCode(const SceneCodeOptions& options, const GpuScene& scene,
                                const std::string& scenePath);

// A bit for each kind of material the scene's materials have (1 << MATERIAL_DIFFUSE,
// ...): MATERIAL_KINDS in scene_code.glsl, and the wavefront's shading kernels.
uint32_t materialKindBits(const GpuScene& scene);

// The text of scene_code.glsl for this scene. `hasEnvironment`: an environment map
// lights it; `hasLens`: its camera has a lens (else a pinhole: no depth of field).
std::string writeSceneCode(const GpuScene& scene, const SceneCodeChoice& choice,
                           bool hasEnvironment, bool hasLens);

// "constants", "texture", ...: for --json and messages.
std::string memoryName(int memory);
// The choice in --json: scene_memory, bvh_memory, specialised.
void recordSceneCode(const SceneCodeChoice& choice, course::Stats& stats);
