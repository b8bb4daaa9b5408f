// Numbers and structs the C++ host and the GLSL shaders must agree on. Both sides read
// this one file: GLSL sees the structs as they are, C++ sees them in namespace gpu with
// glm's vector types. The lines only C++ reads, its #includes among them, stand inside
// `#ifdef __cplusplus`, which the course's shader loader passes over.
#ifndef COURSE_SHARED_H
#define COURSE_SHARED_H

// GLSL 3.30 has no layout(binding = N): the host connects samplers to texture units and
// uniform blocks to their binding points by name, after every (re)link.
#define PRIMITIVES_UNIT 0       // the buffer texture of shapes (samplerBuffer)
#define PREVIOUS_MEAN_UNIT 1    // the last pass's running mean, linear RGB
#define PREVIOUS_RANDOM_UNIT 2  // the last pass's generator states, one uvec4 a pixel
#define PREVIOUS_RAYS_UNIT 3    // the last pass's ray counts, for the --json stats
#define SCENE_BLOCK_BINDING 0   // materials and emitters (uniform buffer)
#define PARAMETERS_BINDING 1    // PathParameters below: what a pass reads besides those

// What one pass writes per pixel: the colour attachments of an accumulation
// framebuffer, each one a fragment shader output (layout(location = N) out).
#define MEAN_OUTPUT 0    // GL_RGBA32F
#define RANDOM_OUTPUT 1  // GL_RGBA32UI
#define RAYS_OUTPUT 2    // GL_R32UI

// Which estimator of the light arriving at a surface (--estimator).
#define ESTIMATOR_NEE 0   // sample the lights only (next-event estimation)
#define ESTIMATOR_BSDF 1  // sample the BSDF only; light counts when a ray hits it
#define ESTIMATOR_MIS 2   // both, weighted by multiple importance sampling

// The kinds of shape, for the nearest hit and the emitters to say which.
#define SHAPE_SPHERE 0
#define SHAPE_QUAD 1
#define SHAPE_TRIANGLE 2
#define NO_EMITTER 0xFFFFFFFFu  // a shape's `emitter` when its material does not emit

// --8<-- [start:texels]
// Shapes live in one buffer texture of RGBA32F texels, read with texelFetch: spheres
// first, then quads, then triangles, each a run of texels; then the two runs the
// triangles point into, chapter 12's positions and normals. A texel holds four floats,
// so indices are stored as float numbers (exact up to 2^24), the emitter as -1 when the
// shape does not glow.
//   sphere    centre and radius; (material, emitter, 0, 0)
//   quad      origin; edge1; edge2; (material, emitter, 0, 0)
//   triangle  (corners, material); (cornerNormals, emitter): chapter 12's Triangle,
//             its corners' indices into the positions and theirs into the normals
//   position  a triangle corner, in the world (w unused)
//   normal    the unit normal at a corner (w unused)
#define SPHERE_TEXELS 2
#define QUAD_TEXELS 4
#define TRIANGLE_TEXELS 2
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
#include <cstddef>      // offsetof, for the static_asserts
#include <glm/glm.hpp>  // the vector types
namespace gpu {
using uint = glm::uint;
using uvec2 = glm::uvec2;
using vec3 = glm::vec3;
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
// global names (sphereCount, materials[i], emitters[i], ...).
#ifdef __cplusplus
struct SceneBlock {
#else
layout(std140) uniform SceneBlock {
#endif
    uint sphereCount;
    uint quadCount;
    uint triangleCount;
    uint emitterCount;
    uint firstSphereTexel;  // where each run of texels begins in the buffer texture
    uint firstQuadTexel;
    uint firstTriangleTexel;
    uint firstPositionTexel;
    uint firstNormalTexel;
    uint padding0, padding1, padding2;  // std140 starts an array of structs at 16n bytes
    Material materials[MAX_MATERIALS];
    Emitter emitters[MAX_EMITTERS];
};
// --8<-- [end:structs]

// --8<-- [start:parameters]
// The pinhole camera of chapter 03: eye, forward, right and up (unit vectors at right
// angles), as the host computes them once per image (camera.cpp).
struct PinholeCamera {
    vec3 eye;
    float focalLength;  // eye to sensor, in metres
    vec3 forward;
    float sensorWidth;  // in metres; the height follows from the image's shape
    vec3 right;
    uint unused0;
    vec3 up;
    uint unused1;
};

// What a pass reads besides the textures and the scene, as one std140 uniform block:
// the host fills this struct and uploads it before each pass, and GLSL sees its members
// as global names (camera, imageSize, ...). A misspelt name fails to compile on either
// side, where a misspelt glUniform name would set nothing and say nothing.
#ifdef __cplusplus
struct PathParameters {
#else
layout(std140) uniform PathParameters {
#endif
    PinholeCamera camera;
    uvec2 imageSize;
    uint seed;         // --seed, for seed.frag
    uint sampleIndex;  // how many samples the image's mean holds already
    int maxBounces;    // --depth: 1 is direct light only
    int estimator;     // ESTIMATOR_NEE, ESTIMATOR_BSDF or ESTIMATOR_MIS
    uint unused2;      // std140 rounds a block up to 16 bytes as well
    uint unused3;
};
// --8<-- [end:parameters]

#ifdef __cplusplus
// The offsets GLSL's std140 rules give; a C++ struct that differs would scramble the
// scene or the camera silently, so the compiler checks.
static_assert(sizeof(Material) == 32 && offsetof(Material, emission) == 16, "std140 Material");
static_assert(sizeof(Emitter) == 16 && offsetof(Emitter, area) == 8, "std140 Emitter");
static_assert(offsetof(SceneBlock, emitterCount) == 12 &&
                  offsetof(SceneBlock, firstSphereTexel) == 16 &&
                  offsetof(SceneBlock, firstNormalTexel) == 32 &&
                  offsetof(SceneBlock, materials) == 48 &&
                  offsetof(SceneBlock, emitters) == 48 + 32 * MAX_MATERIALS &&
                  sizeof(SceneBlock) == 48 + 32 * MAX_MATERIALS + 16 * MAX_EMITTERS,
              "std140 SceneBlock");
static_assert(sizeof(PinholeCamera) == 64 && offsetof(PinholeCamera, focalLength) == 12 &&
                  offsetof(PinholeCamera, forward) == 16 &&
                  offsetof(PinholeCamera, sensorWidth) == 28 &&
                  offsetof(PinholeCamera, right) == 32 && offsetof(PinholeCamera, up) == 48,
              "std140 PinholeCamera: each number fills the fourth slot of a vec3");
static_assert(offsetof(PathParameters, imageSize) == 64 &&
                  offsetof(PathParameters, seed) == 72 &&
                  offsetof(PathParameters, sampleIndex) == 76 &&
                  offsetof(PathParameters, maxBounces) == 80 &&
                  offsetof(PathParameters, estimator) == 84 && sizeof(PathParameters) == 96,
              "std140 PathParameters");
}  // namespace gpu
#endif

#endif
