// Numbers and structs the C++ host and the GLSL shaders must agree on. Both sides read
// this one file: GLSL sees the struct as it is, C++ sees it in namespace gpu with glm's
// vector types. The lines only C++ reads, its #includes among them, stand inside
// `#ifdef __cplusplus`, which the course's shader loader passes over.
#ifndef COURSE_SHARED_H
#define COURSE_SHARED_H

#define PIXELS_BINDING 0     // the image: one vec4 per pixel, row 0 at the top
#define SPHERES_BINDING 1    // the scene's spheres
#define TRIANGLES_BINDING 2  // the scene's triangles

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
using vec4 = glm::vec4;
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

// --8<-- [start:triangle]
// One triangle: three corners and a colour, 64 bytes. Every member is a vec4 (w unused)
// on purpose: std430 aligns a vec3 to 16 bytes, so "vec3 p0, p1, p2;" would put p1 at
// byte 16 in GLSL but at byte 12 in a C++ struct of glm::vec3. With vec4 both sides
// agree without padding members to remember. (Chapter 07 tells the whole story.)
struct Triangle {
    vec4 p0, p1, p2;  // corners; xyz used
    vec4 albedo;      // rgb used
};
// --8<-- [end:triangle]

#ifdef __cplusplus
// The offsets GLSL's std430 rules give; a C++ struct that differs would scramble the
// scene silently, so the compiler checks.
static_assert(sizeof(Sphere) == 32 && offsetof(Sphere, radius) == 12 &&
                  offsetof(Sphere, albedo) == 16,
              "std430 Sphere");
static_assert(sizeof(Triangle) == 64 && offsetof(Triangle, p1) == 16 &&
                  offsetof(Triangle, p2) == 32 && offsetof(Triangle, albedo) == 48,
              "std430 Triangle");
}  // namespace gpu
#endif

#endif
