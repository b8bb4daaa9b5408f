// The wavefront path tracer's memory (wavefront.glsl, wavefront.cpp): where each pixel's
// path waits between kernels, and the queues of work between them. Both sides read this
// one file, like shared.h: GLSL sees the structs as they are, C++ sees them in namespace
// gpu with glm's types, and the includes it needs inside `#ifdef __cplusplus`.
#ifndef COURSE_WAVEFRONT_LAYOUT_H
#define COURSE_WAVEFRONT_LAYOUT_H

// Storage buffer bindings, after shared.h's: two only, since llvmpipe gives a compute
// shader at most 16 storage blocks, and a generic shader (--generic) uses 14 already.
#define PATH_SLOTS_BINDING 18  // each path's state, hit and shadow ray: PathSlot
#define QUEUES_BINDING 19      // the queues' sizes and dispatch commands (Queue), then
                               // their items: slot numbers, room for every slot in each
#define WAVE_BINDING 5         // the uniform block WaveParameters (after shared.h's)

// --8<-- [start:queues]
// The queues of path slots. Paths to trace alternate between two: the kernels read one
// and fill the other. A hit waits in the queue of its material's kind (QUEUE_SHADE +
// kind), a shadow ray in QUEUE_SHADOW. Each queue holds at most one item per slot.
#define QUEUE_RAYS 0     // 0 and 1
#define QUEUE_SHADE 2    // 2 to 5, one per material kind (shared.h)
#define QUEUE_SHADOW 6
#define QUEUE_COUNT 7
// Invocations per work group of the kernels that run over a queue.
#define QUEUE_GROUP_SIZE 64
// --8<-- [end:queues]

#ifdef __cplusplus
#include <cstddef>      // offsetof, for the static_asserts
#include <glm/glm.hpp>  // the vector types
namespace gpu {
using uint = glm::uint;
using vec2 = glm::vec2;
using vec3 = glm::vec3;
#endif

// --8<-- [start:queue]
// A queue's size, and the command glDispatchComputeIndirect reads to run one invocation
// per item: groupsX = size / QUEUE_GROUP_SIZE rounded up, by wavefront_dispatch.comp.
struct Queue {
    uint size;
    uint groupsX;
    uint groupsY;  // 1
    uint groupsZ;  // 1
};
// --8<-- [end:queue]

// path_steps.glsl's PathState and ShadowRay, and scene.glsl's Hit, as std430 stores
// them (bools as uints; each number after a vec3 fills its fourth slot).
struct StoredPath {
    vec3 origin;
    float directionPdf;
    vec3 direction;
    int bounce;
    vec3 throughput;
    uint afterDelta;
    vec3 radiance;
    uint unused;
};
struct StoredHit {
    vec3 position;
    float t;
    vec3 normal;
    uint material;
    vec3 geometricNormal;
    uint emitter;
    vec2 uv;
    uint front;
    uint unused;
};
struct StoredShadowRay {
    vec3 origin;
    float tMax;
    vec3 direction;
    uint unused0;
    vec3 light;
    uint unused1;
};
// What a path keeps between kernels, in its slot: its state, its last hit (from extend
// to shade), its shadow ray (from shade to shadow).
struct PathSlot {
    StoredPath path;
    StoredHit hit;
    StoredShadowRay shadowRay;
};

// --8<-- [start:wave]
// The pool holds poolSize path slots; a sample of the image is run as waves of at most
// that many pixels, slot s holding pixel firstPixel + s. What the kernels of one round
// read besides the buffers, as one std140 uniform block (shared.h's way).
#ifdef __cplusplus
struct WaveParameters {
#else
layout(std140, binding = WAVE_BINDING) uniform WaveParameters {
#endif
    uint firstPixel;  // the pixel of slot 0, in row order
    uint waveSize;    // pixels in this wave: slots 0 to waveSize - 1
    uint poolSize;    // slots in the pool: each queue has room for as many items
    uint rayQueue;    // which of the two ray queues the kernels read (0 or 1)
};
// --8<-- [end:wave]

#ifdef __cplusplus
static_assert(sizeof(WaveParameters) == 16, "std140 WaveParameters");
static_assert(sizeof(Queue) == 16 && offsetof(Queue, groupsX) == 4, "std430 Queue");
static_assert(sizeof(StoredPath) == 64 && offsetof(StoredPath, bounce) == 28 &&
                  offsetof(StoredPath, radiance) == 48,
              "std430 StoredPath");
static_assert(sizeof(StoredHit) == 64 && offsetof(StoredHit, uv) == 48 &&
                  offsetof(StoredHit, front) == 56,
              "std430 StoredHit");
static_assert(sizeof(StoredShadowRay) == 48 && offsetof(StoredShadowRay, light) == 32,
              "std430 StoredShadowRay");
static_assert(sizeof(PathSlot) == 176, "std430 PathSlot");
}  // namespace gpu
#endif

#endif
