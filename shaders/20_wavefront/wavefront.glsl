// What the wavefront kernels share: the paths, hits and shadow rays waiting between
// kernels, one of each per pixel, and the queues that say which pixels have work for
// the next kernel. Needs shared.h, path_steps.glsl (PathState, ShadowRay) and scene.glsl
// (Hit): path_tracer.glsl.
#include "wavefront_layout.h"

layout(std430, binding = PATHS_BINDING) buffer Paths { StoredPath paths[]; };
layout(std430, binding = HITS_BINDING) buffer Hits { StoredHit hits[]; };
layout(std430, binding = SHADOW_RAYS_BINDING) buffer ShadowRays {
    StoredShadowRay shadowRays[];
};
layout(std430, binding = QUEUES_BINDING) buffer Queues { Queue queues[QUEUE_COUNT]; };
layout(std430, binding = QUEUE_ITEMS_BINDING) buffer QueueItems { uint queueItems[]; };
// Each pixel's random number generator and ray count, as the megakernel keeps them.
layout(std430, binding = RANDOM_BINDING) buffer Random { RandomState randomStates[]; };
layout(std430, binding = RAY_COUNT_BINDING) buffer RayCounts { uint rayCounts[]; };

// Which of the two ray queues the kernels read; the shading kernels fill the other.
uniform uint rayQueue;

uint pixelCount() { return imageSize.x * imageSize.y; }

// --8<-- [start:push]
// Add a pixel's path to a queue. Many invocations push at once: atomicAdd gives each
// its own slot (the size before its own addition), so no two write the same one.
void push(uint queue, uint pixel) {
    uint slot = atomicAdd(queues[queue].size, 1u);
    queueItems[queue * pixelCount() + slot] = pixel;
}
// --8<-- [end:push]

// The pixel whose path is this invocation's work in `queue`, if it has one: the queue
// is dispatched in whole work groups, so the last one overhangs.
bool itemOf(uint queue, out uint pixel) {
    uint slot = gl_GlobalInvocationID.x;
    if (slot >= queues[queue].size) return false;
    pixel = queueItems[queue * pixelCount() + slot];
    return true;
}

PathState loadPath(uint pixel) {
    StoredPath p = paths[pixel];
    return PathState(Ray(p.origin, p.direction), p.radiance, p.throughput, p.directionPdf,
                     p.afterDelta != 0u, p.bounce);
}
void storePath(uint pixel, PathState path) {
    paths[pixel] = StoredPath(path.ray.origin, path.directionPdf, path.ray.direction,
                              path.bounce, path.throughput, uint(path.afterDelta),
                              path.radiance, 0u);
}

Hit loadHit(uint pixel) {
    StoredHit h = hits[pixel];
    return Hit(h.t, h.position, h.normal, h.geometricNormal, h.front != 0u, h.material,
               h.emitter, h.uv);
}
void storeHit(uint pixel, Hit hit) {
    hits[pixel] = StoredHit(hit.position, hit.t, hit.normal, hit.material,
                            hit.geometricNormal, hit.emitter, hit.uv, uint(hit.front), 0u);
}

ShadowRay loadShadowRay(uint pixel) {
    StoredShadowRay s = shadowRays[pixel];
    return ShadowRay(Ray(s.origin, s.direction), s.tMax, s.light);
}
void storeShadowRay(uint pixel, ShadowRay shadow) {
    shadowRays[pixel] = StoredShadowRay(shadow.ray.origin, shadow.tMax, shadow.ray.direction,
                                        0u, shadow.light, 0u);
}
