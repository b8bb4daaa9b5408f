// Numbers and structs the C++ host and the GLSL shaders must agree on. Both sides read
// this one file: GLSL sees the structs as they are, C++ sees them in namespace gpu with
// glm's vector types. The lines only C++ reads, its #includes among them, stand inside
// `#ifdef __cplusplus`, which the course's shader loader passes over.
#ifndef COURSE_SHARED_H
#define COURSE_SHARED_H

#define PIXELS_BINDING 0     // the image: the running mean of the samples, linear RGB
#define SPHERES_BINDING 1    // the scene's spheres
#define TRIANGLES_BINDING 2  // its triangles, meshes included: indices of their corners
#define QUADS_BINDING 3      // its parallelograms (walls, lights)
#define RANDOM_BINDING 4     // each pixel's generator state: one uvec4, kept all along
#define MATERIALS_BINDING 5  // albedo and emission, picked by each shape's `material`
#define DUMP_BINDING 6       // --dump-random: the numbers drawn, one uint each
#define POSITIONS_BINDING 7  // the triangles' corners, in the world: one vec4 each
#define NORMALS_BINDING 8    // the normals at those corners, unit: one vec4 each

// --view: what a sample of a pixel is.
#define VIEW_SHADED 0  // the surface's glow, plus its albedo times ambient occlusion
#define VIEW_NOISE 1   // the pixel's next random number, as grey
#define VIEW_AO 2      // ambient occlusion: one random ray above the hit point per sample

// The kinds of shape, for the nearest hit to say which it found.
#define SHAPE_SPHERE 0
#define SHAPE_QUAD 1
#define SHAPE_TRIANGLE 2

// New rays start RAY_OFFSET * (1 + the hit's largest |coordinate|) off the surface,
// along its normal, so that float32 rounding does not make them find the surface they
// leave (chapter 05). Relative, like float32's precision: 0.2 mm in the 2 m Cornell box.
#define RAY_OFFSET 1e-4

// 8x8 tiles of invocations: neighbouring rays run together (chapter 02).
#define TILE_SIZE 8

#ifdef __cplusplus
#include <cstddef>      // offsetof, for the static_asserts
#include <glm/glm.hpp>  // the vector types
namespace gpu {
using uint = glm::uint;
using uvec3 = glm::uvec3;
using vec3 = glm::vec3;
using vec4 = glm::vec4;
#endif

// --8<-- [start:structs]
// std430 aligns a vec3 to 16 bytes but gives it only 12, so the number after each vec3
// fills its fourth slot: exactly where C++ puts it after a 12-byte glm::vec3. Each shape
// names its material (an index into the materials).
struct Sphere {
    vec3 center;
    float radius;
    uint material;
    uint unused0;  // std430 rounds the struct up to a multiple of 16 bytes, its
    uint unused1;  // alignment: these give C++ the same 32
    uint unused2;
};
struct Quad {  // corners origin, origin + edge1, origin + edge1 + edge2, origin + edge2
    vec3 origin;
    uint material;
    vec3 edge1;
    uint unused0;
    vec3 edge2;  // the front is the side cross(edge1, edge2) points to
    uint unused1;
};
// Chapter 09's triangle: the front is the side where its corners run counter-clockwise.
// 16 bytes: std430 aligns the uvec3 to 16 bytes and gives it 12, so the uint after it
// fills the fourth slot, exactly where C++ puts it after a 12-byte glm::uvec3. Each
// triangle is one aligned 16-byte load for the GPU, and the slot is not wasted.
// Then the indices of its corners' normals in the normals buffer: an OBJ file numbers
// normals apart from positions (`f 7//2`), so a corner has one index for each.
struct Triangle {
    uvec3 corners;        // 0-based indices into the positions (OBJ files count from 1)
    uint material;        // an index into the materials, like every shape's
    uvec3 cornerNormals;  // 0-based indices into the normals, in the corners' order
    uint unused;          // fills the fourth slot, so C++ sees the same 32 bytes
};
struct Material {
    vec4 albedo;    // rgb: the reflected fraction of the light (Lambertian)
    vec4 emission;  // rgb: the radiance it gives out from its front; zero if none
};
// --8<-- [end:structs]

#ifdef __cplusplus
// The offsets GLSL's std430 rules give; a C++ struct that differs would scramble the
// scene silently, so the compiler checks.
static_assert(sizeof(Sphere) == 32 && offsetof(Sphere, radius) == 12 &&
                  offsetof(Sphere, material) == 16,
              "std430 Sphere");
static_assert(sizeof(Quad) == 48 && offsetof(Quad, material) == 12 &&
                  offsetof(Quad, edge1) == 16 && offsetof(Quad, unused0) == 28 &&
                  offsetof(Quad, edge2) == 32 && offsetof(Quad, unused1) == 44,
              "std430 Quad: each uint fills the fourth slot of the vec3 before it");
static_assert(sizeof(Triangle) == 32 && offsetof(Triangle, material) == 12 &&
                  offsetof(Triangle, cornerNormals) == 16 && offsetof(Triangle, unused) == 28,
              "std430 Triangle");
static_assert(sizeof(Material) == 32 && offsetof(Material, emission) == 16, "std430 Material");
// --8<-- [start:positions]
// Positions are a plain array, `vec4 positions[]` in GLSL. In a std430 array a vec3
// takes 16 bytes like a vec4 (its alignment), but a glm::vec3 takes 12: uploading
// glm::vec3s would shift vertex i by 4 * i bytes (--packed-vec3 shows the picture).
// Uploading glm::vec4s, w unused, makes both sides 16 bytes per vertex.
static_assert(sizeof(vec4) == 16, "a std430 vec4 array has a 16-byte stride");
static_assert(sizeof(vec3) == 12, "glm::vec3 is packed: not the stride of a std430 vec3[]");
// --8<-- [end:positions]
}  // namespace gpu
#endif

#endif
