// Numbers and structs the C++ host and the GLSL shaders must agree on. Both sides read
// this one file: GLSL sees the struct as it is, C++ sees it in namespace gpu with glm's
// vector types. The lines only C++ reads, its #includes among them, stand inside
// `#ifdef __cplusplus`, which the course's shader loader passes over.
#ifndef COURSE_SHARED_H
#define COURSE_SHARED_H

#define PIXELS_BINDING 0     // the image: one vec4 per pixel, row 0 at the top
#define POSITIONS_BINDING 1  // the vertices' positions: one vec4 each, w unused
#define TRIANGLES_BINDING 2  // the triangles: three indices into the positions each

// Shadow rays start SHADOW_OFFSET * (1 + radius) off the surface, along its normal:
// float32 rounding puts a hit point slightly inside or outside the surface, and a shadow
// ray that starts inside would find its own surface (shadow acne). A mesh may be in
// millimetres or in kilometres, so the offset grows with the mesh's bounding radius.
#define SHADOW_OFFSET 1e-4

// What a triangle is made of: its `material` picks the albedo.
#define MATERIAL_MESH 0   // the OBJ file's triangles
#define MATERIAL_FLOOR 1  // the two the floor is made of

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

// --8<-- [start:triangle]
// One triangle: the indices of its corners in the positions buffer, and its material.
// 16 bytes: std430 aligns the uvec3 to 16 bytes and gives it 12, so the uint after it
// fills the fourth slot, exactly where C++ puts it after a 12-byte glm::uvec3. Each
// triangle is one aligned 16-byte load for the GPU, and the slot is not wasted.
struct Triangle {
    uvec3 corners;  // 0-based indices into the positions (OBJ files count from 1)
    uint material;  // MATERIAL_MESH or MATERIAL_FLOOR
};
// --8<-- [end:triangle]

#ifdef __cplusplus
// The offsets GLSL's std430 rules give; a C++ struct that differs would scramble the
// mesh silently, so the compiler checks.
static_assert(sizeof(Triangle) == 16 && offsetof(Triangle, material) == 12, "std430 Triangle");
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
