// Everything a path tracing kernel includes, in the order the files need each other:
// the megakernel (path.comp) and each wavefront kernel (wavefront_*.comp) alike.
#include "shared.h"
// Written by the host for this scene (scene_code.cpp): its counts, its features, how
// the shaders read it (scene_memory.glsl) and, for a small scene, the scene itself.
#include "scene_code.glsl"
#ifdef SHADE_KIND
// A wavefront shading kernel, compiled for one kind of material: its queue holds only
// hits on that kind, so the other kinds' code is left out (isKind, bsdf.glsl).
#undef MATERIAL_KINDS
#define MATERIAL_KINDS (1u << SHADE_KIND)
#endif
#include "random.glsl"
#include "camera.glsl"
#include "scene.glsl"
#include "sampling.glsl"
#include "environment.glsl"
#include "microfacet.glsl"
#include "dielectric.glsl"
#include "bsdf.glsl"
#include "path_steps.glsl"
