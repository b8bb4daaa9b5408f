// Numbers and structs the C++ host and the GLSL shaders must agree on. Both sides read
// this one file: GLSL sees the structs as they are, C++ sees them in namespace gpu with
// glm's vector types. (C++ files include <glm/glm.hpp> and <cstddef> first: this file
// may not #include anything, because the shader loader looks for includes in this folder.)
#ifndef COURSE_SHARED_H
#define COURSE_SHARED_H

// GLSL 3.30 has no layout(binding = N): the host connects samplers to texture units and
// the uniform block to its binding point by name, after every (re)link.
#define PRIMITIVES_UNIT 0       // the buffer texture of shapes (samplerBuffer)
#define PREVIOUS_MEAN_UNIT 1    // the last pass's running mean, linear RGB
#define PREVIOUS_RANDOM_UNIT 2  // the last pass's generator states, one uvec4 a pixel
#define PREVIOUS_RAYS_UNIT 3    // the last pass's ray counts, for the --json stats
#define SCENE_BLOCK_BINDING 0   // materials and emitters (uniform buffer)

// What one pass writes per pixel: the colour attachments of an accumulation
// framebuffer, each one a fragment shader output (layout(location = N) out).
#define MEAN_OUTPUT 0    // GL_RGBA32F
#define RANDOM_OUTPUT 1  // GL_RGBA32UI
#define RAYS_OUTPUT 2    // GL_R32UI

// Which estimator of the light arriving at a surface (--estimator).
#define ESTIMATOR_NEE 0   // sample the lights only (next-event estimation)
#define ESTIMATOR_BSDF 1  // sample the BSDF only; light counts when a ray hits it
#define ESTIMATOR_MIS 2   // both, weighted by multiple importance sampling

// What kind of shape an emitter is.
#define SHAPE_SPHERE 0
#define SHAPE_QUAD 1
#define SHAPE_TRIANGLE 2
#define NO_EMITTER 0xFFFFFFFFu  // a shape's `emitter` when its material does not emit

// --8<-- [start:texels]
// Shapes live in one buffer texture of RGBA32F texels, read with texelFetch: spheres
// first, then quads, then triangles, each a run of texels. A texel holds four floats,
// so a shape's material and emitter indices are stored as float numbers (exact below
// 2^24), the emitter as -1 when the shape does not glow.
//   sphere    centre and radius; (material, emitter, 0, 0)
//   quad      origin; edge1; edge2; (material, emitter, 0, 0)
//   triangle  p0; p1; p2; (material, emitter, 0, 0)
#define SPHERE_TEXELS 2
#define QUAD_TEXELS 4
#define TRIANGLE_TEXELS 4
// --8<-- [end:texels]

// A uniform block has a fixed size: these many materials and emitters, 12 KiB with the
// counts, below the 16 KiB that every GL 3.3 guarantees (GL_MAX_UNIFORM_BLOCK_SIZE).
#define MAX_MATERIALS 256
#define MAX_EMITTERS 256

// New rays start RAY_OFFSET * (1 + the hit's largest |coordinate|) off the surface,
// along its normal, so that float32 rounding does not make them find the surface they
// leave (chapter 05). Relative, like float32's precision: 0.2 mm in the 2 m Cornell box.
#define RAY_OFFSET 1e-4

// Russian roulette starts after this many bounces: the first few are cheap and carry
// most of the light, so every path makes them.
#define ROULETTE_AFTER 3

#ifdef __cplusplus
namespace gpu {
using uint = glm::uint;
using uvec4 = glm::uvec4;
using vec4 = glm::vec4;
#endif

// --8<-- [start:structs]
// std140, the layout of uniform blocks, aligns a struct and an array element to 16
// bytes: built from vec4s and four 4-byte numbers, these need no padding.
struct Material {
    vec4 albedo;    // rgb: the reflected fraction of the light (Lambertian)
    vec4 emission;  // rgb: the radiance it gives out from its front; zero if none
};
struct Emitter {
    uint shape;   // SHAPE_SPHERE, SHAPE_QUAD or SHAPE_TRIANGLE
    uint index;   // into the spheres, quads or triangles
    float area;   // its surface area: uniform sampling has the density 1 / area
    float power;  // unused; room for picking bright lights more often
};

// The same bytes are a C++ struct and a GLSL uniform block, whose members GLSL sees as
// global names (materials[i], emitters[i], shapeCounts).
#ifdef __cplusplus
struct SceneBlock {
#else
layout(std140) uniform SceneBlock {
#endif
    uvec4 shapeCounts;  // x spheres, y quads, z triangles, w emitters
    uvec4 firstTexel;   // where the spheres (x), quads (y), triangles (z) begin
    Material materials[MAX_MATERIALS];
    Emitter emitters[MAX_EMITTERS];
};
// --8<-- [end:structs]

#ifdef __cplusplus
static_assert(sizeof(Material) == 32 && offsetof(Material, emission) == 16, "std140 Material");
static_assert(sizeof(Emitter) == 16 && offsetof(Emitter, area) == 8, "std140 Emitter");
static_assert(offsetof(SceneBlock, materials) == 32 &&
                  offsetof(SceneBlock, emitters) == 32 + 32 * MAX_MATERIALS &&
                  sizeof(SceneBlock) == 32 + 32 * MAX_MATERIALS + 16 * MAX_EMITTERS,
              "std140 SceneBlock");
}  // namespace gpu
#endif

#endif
