// Everything the path tracing kernel (path.comp) includes, in the order the files need
// each other.
#include "shared.h"
// Written by the host for this scene (scene_code.cpp): its counts, its features, how
// the shaders read it (scene_memory.glsl) and, for a small scene, the scene itself.
#include "scene_code.glsl"
#include "random.glsl"
#include "camera.glsl"
#include "scene.glsl"
#include "sampling.glsl"
#include "environment.glsl"
#include "microfacet.glsl"
#include "dielectric.glsl"
#include "bsdf.glsl"
#include "path_steps.glsl"
