// Numbers and structs the C++ host and the GLSL shaders must agree on. Both sides read
// this one file: GLSL sees the structs as they are, C++ sees them in namespace gpu with
// glm's vector types. The lines only C++ reads, its #includes among them, stand inside
// `#ifdef __cplusplus`, which the course's shader loader passes over.
#ifndef COURSE_SHARED_H
#define COURSE_SHARED_H

#define SPHERES_BINDING 1    // the scene's spheres
#define TRIANGLES_BINDING 2  // its triangles, meshes included: indices of their corners
#define QUADS_BINDING 3      // its parallelograms (walls, lights)
#define MATERIALS_BINDING 5  // albedo and emission, picked by each shape's `material`
#define POSITIONS_BINDING 7  // the triangles' corners, in the world: one vec4 each
#define NORMALS_BINDING 8    // the normals at those corners, unit: one vec4 each
#define EMITTERS_BINDING 9   // the shapes that emit: what next-event estimation samples

// What chapter 12 kept per pixel in storage buffers between dispatches lives in
// textures now: the previous pass's, on these texture units, read with texelFetch.
#define PREVIOUS_MEAN_UNIT 1    // the last pass's running mean, linear RGB
#define PREVIOUS_RANDOM_UNIT 2  // the last pass's generator states, one uvec4 a pixel
#define PREVIOUS_RAYS_UNIT 3    // the last pass's ray counts, for the --json stats
// Uniform buffers have binding points of their own, apart from storage buffers'.
#define PARAMETERS_BINDING 0    // PathParameters below: what a pass reads besides those

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
using uvec3 = glm::uvec3;
using vec3 = glm::vec3;
using vec4 = glm::vec4;
#endif

// --8<-- [start:structs]
// std430 aligns a vec3 to 16 bytes but gives it only 12, so the number after each vec3
// fills its fourth slot: exactly where C++ puts it after a 12-byte glm::vec3. Each shape
// names its material (an index into the materials) and its emitter (its index in the
// emitter list, or NO_EMITTER).
struct Sphere {
    vec3 center;
    float radius;
    uint material;
    uint emitter;
    uint unused0;  // std430 rounds the struct up to a multiple of 16 bytes, its
    uint unused1;  // alignment: these give C++ the same 32
};
struct Quad {  // corners origin, origin + edge1, origin + edge1 + edge2, origin + edge2
    vec3 origin;
    uint material;
    vec3 edge1;
    uint emitter;
    vec3 edge2;  // the front is the side cross(edge1, edge2) points to
    uint unused;
};
struct Triangle {  // chapter 09's: the front is where the corners run counter-clockwise
    uvec3 corners;        // indices into the positions
    uint material;
    uvec3 cornerNormals;  // indices into the normals, in the corners' order
    uint emitter;
};
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

// What a pass reads besides the buffers, as one std140 uniform block: the host
// fills this struct and uploads it before each pass, and GLSL sees its members as
// global names (camera, imageSize, ...). A misspelt name fails to compile on either
// side, where a misspelt glUniform name would set nothing and say nothing.
#ifdef __cplusplus
struct PathParameters {
#else
layout(std140, binding = PARAMETERS_BINDING) uniform PathParameters {
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
// The offsets GLSL's std430 (buffers) and std140 (the block) rules give; a C++ struct
// that differs would scramble the scene or the camera silently, so the compiler checks.
static_assert(sizeof(Sphere) == 32 && offsetof(Sphere, radius) == 12 &&
                  offsetof(Sphere, material) == 16 && offsetof(Sphere, emitter) == 20,
              "std430 Sphere");
static_assert(sizeof(Quad) == 48 && offsetof(Quad, material) == 12 &&
                  offsetof(Quad, edge1) == 16 && offsetof(Quad, emitter) == 28 &&
                  offsetof(Quad, edge2) == 32 && offsetof(Quad, unused) == 44,
              "std430 Quad: each uint fills the fourth slot of the vec3 before it");
static_assert(sizeof(Triangle) == 32 && offsetof(Triangle, material) == 12 &&
                  offsetof(Triangle, cornerNormals) == 16 && offsetof(Triangle, emitter) == 28,
              "std430 Triangle: each uint fills the fourth slot of the uvec3 before it");
static_assert(sizeof(Material) == 32 && offsetof(Material, emission) == 16, "std430 Material");
static_assert(sizeof(Emitter) == 16 && offsetof(Emitter, area) == 8, "std430 Emitter");
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
