// Numbers and structs the C++ host and the GLSL shaders must agree on. Both sides read
// this one file: GLSL sees the struct as it is, C++ sees it in namespace gpu with glm's
// vector types. The lines only C++ reads, its #includes among them, stand inside
// `#ifdef __cplusplus`, which the course's shader loader passes over.
#ifndef COURSE_SHARED_H
#define COURSE_SHARED_H

#define PIXELS_BINDING 0   // the image: one vec4 per pixel, row 0 at the top
#define SPHERES_BINDING 1  // the scene's spheres
#define PLANES_BINDING 2   // the scene's infinite planes

// Shadow rays start this far (in metres) off the surface, along its normal: float32
// rounding puts a hit point slightly inside or outside the surface, and a shadow ray
// that starts inside would find its own surface (shadow acne).
#define SHADOW_OFFSET 1e-3

// 8x8 tiles of invocations: neighbouring rays run together (chapter 02).
#define TILE_SIZE 8

#ifdef __cplusplus
#include <cstddef>      // offsetof, for the static_asserts
#include <glm/glm.hpp>  // the vector types
namespace gpu {
using vec3 = glm::vec3;
#endif

// --8<-- [start:sphere]
// One sphere in a std430 storage buffer: 32 bytes. In std430 a vec3 takes the space
// of a vec4, so the float after it fills the fourth slot (chapter 07 tells that story).
struct Sphere {
    vec3 center;
    float radius;
    vec3 albedo;    // the fraction of red, green and blue light the surface reflects
    float unused;   // fills albedo's fourth slot, so C++ sees the same 32 bytes
};
// --8<-- [end:sphere]

// --8<-- [start:plane]
// An infinite plane: the points p with dot(normal, p) == offset. 32 bytes.
struct Plane {
    vec3 normal;    // unit length; the side the plane is lit from
    float offset;
    vec3 albedo;
    float unused;
};
// --8<-- [end:plane]

#ifdef __cplusplus
// The offsets GLSL's std430 rules give; a C++ struct that differs would scramble the
// scene silently, so the compiler checks.
static_assert(sizeof(Sphere) == 32 && offsetof(Sphere, radius) == 12 &&
                  offsetof(Sphere, albedo) == 16,
              "std430 Sphere");
static_assert(sizeof(Plane) == 32 && offsetof(Plane, offset) == 12 &&
                  offsetof(Plane, albedo) == 16,
              "std430 Plane");
}  // namespace gpu
#endif

#endif
