// Numbers and structs the C++ host and the GLSL shaders must agree on. Both sides read
// this one file: GLSL sees the structs as they are, C++ sees them in namespace gpu with
// glm's vector types. The lines only C++ reads, its #includes among them, stand inside
// `#ifdef __cplusplus`, which the course's shader loader passes over.
#ifndef COURSE_SHARED_H
#define COURSE_SHARED_H

// The tree's node, as bvh.cpp writes it and the traversal reads it.
#include "bvh_layout.h"

#define PIXELS_BINDING 0     // the image: the running mean of the samples, linear RGB
#define SPHERES_BINDING 1    // the scene's spheres
#define TRIANGLES_BINDING 2  // its triangles, meshes included: indices of their corners
#define QUADS_BINDING 3      // its parallelograms (walls, lights)
#define RANDOM_BINDING 4     // each pixel's generator state: one uvec4, kept all along
#define MATERIALS_BINDING 5  // how surfaces reflect and glow, by each shape's `material`
#define RAY_COUNT_BINDING 6  // rays traced by each pixel so far, for the --json stats
#define POSITIONS_BINDING 7  // the triangles' corners, in the world: one vec4 each
#define NORMALS_BINDING 8    // the normals at those corners, unit: one vec4 each
#define EMITTERS_BINDING 9   // the shapes that emit: what next-event estimation samples
#define BVH_NODES_BINDING 10  // the bounding volume hierarchy over the triangles
#define BOUNCE_START_BINDING 11  // --view bounce: each pixel's first hit, found once
#define UVS_BINDING 12       // the meshes' texture coordinates (OBJ vt): one vec2 each
#define TEXTURES_BINDING 13  // the scene's textures: Texture below
#define TEXELS_BINDING 14    // every image texture's texels, linear RGB, one after another,
                             // then the environment's radiance
#define ENVIRONMENT_CDF_BINDING 16  // the environment's sampling tables (environment.cpp);
                                    // 15 is the window's (course/display.h)
#define DISPLAY_BINDING 17   // the image as the eye sees it: exposed, tone mapped (display.comp)

// Uniform buffers have binding points of their own, apart from storage buffers'.
#define PARAMETERS_BINDING 0  // PathParameters below: what a dispatch reads besides buffers
// So do atomic counter buffers: path.comp counts the invocations whose loops the GL cut
// short in one, which takes none of the storage blocks (16 on llvmpipe, all in use).
#define CUT_SHORT_BINDING 0
// --8<-- [start:memory]
// The ways the shaders can read the scene (scene_memory.glsl), for SCENE_MEMORY (the
// spheres, quads, materials, emitters) and BVH_MEMORY (nodes, triangles, corners).
#define MEMORY_STORAGE 0    // storage buffers, as before
#define MEMORY_UNIFORM 1    // uniform blocks (the small arrays only)
#define MEMORY_TEXTURE 2    // buffer textures over the storage buffers' bytes
#define MEMORY_CONSTANTS 3  // constant arrays in the generated shader code (small arrays)
#define SPHERES_BLOCK_BINDING 1    // MEMORY_UNIFORM: the uniform blocks' binding points
#define QUADS_BLOCK_BINDING 2
#define MATERIALS_BLOCK_BINDING 3
#define EMITTERS_BLOCK_BINDING 4
#define SPHERES_UNIT 1     // MEMORY_TEXTURE: the buffer textures' texture units (unit 0
#define QUADS_UNIT 2       // is the window's picture)
#define MATERIALS_UNIT 3
#define EMITTERS_UNIT 4
#define TRIANGLES_UNIT 5
#define POSITIONS_UNIT 6
#define BVH_NODES_UNIT 7
#define LEAF_CORNERS_UNIT 8  // each triangle's 3 corners again, in the tree's leaf
                             // order: what the traversal tests, without indices
// --8<-- [end:memory]

// What the image shows (--view). Everything but the radiance uses one ray through each
// pixel's centre and no randomness, so that two runs can be compared pixel by pixel.
#define VIEW_RADIANCE 0  // the path tracer's estimate of the light (the default)
#define VIEW_NORMALS 1   // the normal of the surface hit, 0.5 + 0.5 n; black for no hit
#define VIEW_DISTANCE 2  // how far along the ray the hit is (PFM: metres); 0 for no hit
#define VIEW_COST 3      // traversal steps for the ray, as a heat map (bvh_traversal.glsl)
#define VIEW_BOUNCE 4    // random diffuse rays from the first hit: the share that travel
                         // over a quarter of the scene (ambient occlusion); a benchmark
#define VIEW_ALBEDO 5    // the albedo at the hit, textures looked up (PFM: exact values)
#define VIEW_UV 6        // the texture coordinates at the hit: (fract(u), fract(v), 0)

// Which estimator of the light arriving at a surface (--estimator).
#define ESTIMATOR_NEE 0   // sample the lights only (next-event estimation)
#define ESTIMATOR_BSDF 1  // sample the BSDF only; light counts when a ray hits it
#define ESTIMATOR_MIS 2   // both, weighted by multiple importance sampling

// The kinds of material (Material::kind): how a surface reflects.
#define MATERIAL_DIFFUSE 0    // Lambertian: albedo / pi in every direction
#define MATERIAL_MIRROR 1     // an ideal mirror, reflecting the fraction `albedo`
#define MATERIAL_CONDUCTOR 2  // a metal: smooth, or rough (GGX microfacets)
#define MATERIAL_DIELECTRIC 3  // glass: reflects and refracts; smooth, or rough (GGX)

// The kinds of shape, for the nearest hit and the emitters to say which.
#define SHAPE_SPHERE 0
#define SHAPE_QUAD 1
#define SHAPE_TRIANGLE 2
#define NO_EMITTER 0xFFFFFFFFu  // a shape's `emitter` when its material does not emit

// The kinds of texture (Texture::kind), and a material's `texture` when it has none.
#define TEXTURE_IMAGE 0    // texels from an image file, filtered bilinearly
#define TEXTURE_CHECKER 1  // squares of two colours, computed where they are looked up
#define NO_TEXTURE -1

// New rays start RAY_OFFSET * (1 + the hit's largest |coordinate|) off the surface,
// along its normal, so that float32 rounding does not make them find the surface they
// leave (chapter 05). Relative, like float32's precision: 0.2 mm in the 2 m Cornell box.
#define RAY_OFFSET 1e-4

// Russian roulette starts after this many bounces: the first few are cheap and carry
// most of the light, so every path makes them.
#define ROULETTE_AFTER 3

// 8x8 tiles of invocations: neighbouring rays run together (chapter 02).
#define TILE_SIZE 8

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
    uvec3 cornerUvs;      // indices into the texture coordinates, in the corners' order
    uint unused;
};
struct Material {
    vec3 albedo;      // Lambertian: the reflected fraction; mirror: its reflectance
    uint kind;        // MATERIAL_DIFFUSE, _MIRROR, _CONDUCTOR or _DIELECTRIC
    vec3 emission;    // the radiance it gives out from its front; zero if none
    float roughness;  // conductor, dielectric: the GGX alpha; 0 is smooth
    vec3 eta;         // conductor: the complex index of refraction eta + i k, per
                      // channel (at a red, a green and a blue wavelength)
    float ior;        // dielectric: the index of refraction inside (outside: 1)
    vec3 k;
    int textureIndex;  // Lambertian: its albedo's texture (an index), or NO_TEXTURE
};
struct Texture {
    uint kind;        // TEXTURE_IMAGE or TEXTURE_CHECKER
    uint firstTexel;  // image: where its texels start in the texel buffer, row by row
    uint width;       // image: texels across and down
    uint height;
    vec3 color0;      // checker: the two colours
    float scale;      // checker: squares of each colour per unit of u and of v
    vec3 color1;
    uint unused;
};
struct Emitter {
    uint shape;   // SHAPE_SPHERE, SHAPE_QUAD or SHAPE_TRIANGLE
    uint index;   // into the spheres, quads or triangles
    float area;   // its surface area: uniform sampling has the density 1 / area
    float power;  // unused; room for picking bright lights more often
};
// --8<-- [end:structs]

// --8<-- [start:parameters]
// The pinhole camera of chapter 03 (eye, forward, right and up: unit vectors at right
// angles, as the host computes them once per image in camera.cpp) with a thin lens.
struct ThinLensCamera {
    vec3 eye;
    float focalLength;  // eye to sensor, in metres
    vec3 forward;
    float sensorWidth;  // in metres; the height follows from the image's shape
    vec3 right;
    float lensRadius;     // the aperture's radius in metres, round the eye; 0: a pinhole
    vec3 up;
    float focusDistance;  // metres along forward to the plane that is sharp
};

// What a dispatch reads besides the buffers, as one std140 uniform block: the host
// fills this struct and uploads it before each dispatch, and GLSL sees its members as
// global names (camera, imageSize, ...). A misspelt name fails to compile on either
// side, where a misspelt glUniform name would set nothing and say nothing.
#ifdef __cplusplus
struct PathParameters {
#else
layout(std140, binding = PARAMETERS_BINDING) uniform PathParameters {
#endif
    ThinLensCamera camera;
    uvec2 imageSize;
    uint seed;         // --seed, for seed.comp
    uint sampleIndex;  // how many samples the image's mean holds already
    int maxBounces;    // --depth: 1 is direct light only
    int estimator;     // ESTIMATOR_NEE, ESTIMATOR_BSDF or ESTIMATOR_MIS
    int view;          // VIEW_RADIANCE, VIEW_NORMALS, ... (--view)
    uint bruteForce;   // 1 for --brute-force: every triangle, no tree (scene.glsl)
    float occlusionDistance;  // VIEW_BOUNCE: a bounce ray going farther is "open"
    // The environment (environment.glsl): its radiance map's place in the texels, its
    // size (0 x 0: none), how it is turned about y, and how often next-event estimation
    // samples it rather than an emitting shape (1 with no emitting shapes, 0 with no
    // environment, else ENVIRONMENT_CHANCE).
    uint environmentFirstTexel;
    uint environmentWidth;
    uint environmentHeight;
    float environmentRotation;  // radians, counter-clockwise seen from above
    float environmentChance;
    float exposure;    // --exposure EV: the image is multiplied by 2^EV before display
    int toneMap;       // TONE_MAP_CLAMP, _REINHARD, _ACES or _FALSE_COLOUR
    uint samplesThisDispatch;  // path.comp: the samples each pixel adds in this dispatch
    uint loopCanary;  // path.comp: 2, the turns of the loop that finds loops cut short
    uint unused2, unused3;  // the block's size a multiple of 16 bytes, as std140's
};

// How radiance becomes a displayed value (--tone-map; tone_mapping.glsl).
#define TONE_MAP_CLAMP 0         // as chapters 01-17 did: anything above 1 is white
#define TONE_MAP_REINHARD 1      // extended Reinhard on luminance, white at REINHARD_WHITE
#define TONE_MAP_ACES 2          // Narkowicz's fit of the ACES filmic curve, per channel
#define TONE_MAP_FALSE_COLOUR 3  // luminance in stops about mid-grey, as colours
#define REINHARD_WHITE 8.0       // the (exposed) luminance Reinhard shows as white

// Next-event estimation's choice between the environment and the emitting shapes when
// a scene has both: half and half, a simple split that never starves either.
#define ENVIRONMENT_CHANCE 0.5
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
static_assert(sizeof(Triangle) == 48 && offsetof(Triangle, material) == 12 &&
                  offsetof(Triangle, cornerNormals) == 16 && offsetof(Triangle, emitter) == 28 &&
                  offsetof(Triangle, cornerUvs) == 32,
              "std430 Triangle: each uint fills the fourth slot of the uvec3 before it");
static_assert(sizeof(Material) == 64 && offsetof(Material, kind) == 12 &&
                  offsetof(Material, emission) == 16 && offsetof(Material, roughness) == 28 &&
                  offsetof(Material, eta) == 32 && offsetof(Material, ior) == 44 &&
                  offsetof(Material, k) == 48 && offsetof(Material, textureIndex) == 60,
              "std430 Material: each number fills the fourth slot of the vec3 before it");
static_assert(sizeof(Texture) == 48 && offsetof(Texture, color0) == 16 &&
                  offsetof(Texture, scale) == 28 && offsetof(Texture, color1) == 32,
              "std430 Texture");
static_assert(sizeof(Emitter) == 16 && offsetof(Emitter, area) == 8, "std430 Emitter");
static_assert(sizeof(ThinLensCamera) == 64 && offsetof(ThinLensCamera, focalLength) == 12 &&
                  offsetof(ThinLensCamera, forward) == 16 &&
                  offsetof(ThinLensCamera, sensorWidth) == 28 &&
                  offsetof(ThinLensCamera, right) == 32 &&
                  offsetof(ThinLensCamera, lensRadius) == 44 &&
                  offsetof(ThinLensCamera, up) == 48 &&
                  offsetof(ThinLensCamera, focusDistance) == 60,
              "std140 ThinLensCamera: each number fills the fourth slot of a vec3");
static_assert(offsetof(PathParameters, imageSize) == 64 &&
                  offsetof(PathParameters, seed) == 72 &&
                  offsetof(PathParameters, sampleIndex) == 76 &&
                  offsetof(PathParameters, maxBounces) == 80 &&
                  offsetof(PathParameters, estimator) == 84 &&
                  offsetof(PathParameters, bruteForce) == 92 &&
                  offsetof(PathParameters, environmentFirstTexel) == 100 &&
                  offsetof(PathParameters, environmentChance) == 116 &&
                  offsetof(PathParameters, exposure) == 120 &&
                  offsetof(PathParameters, samplesThisDispatch) == 128 &&
                  offsetof(PathParameters, loopCanary) == 132 &&
                  sizeof(PathParameters) == 144,
              "std140 PathParameters");
}  // namespace gpu
#endif

#endif
