// What the wavefront kernels share: each pixel's path, hit and shadow ray waiting
// between kernels (its PathSlot), and the queues that say which pixels have work for
// the next kernel. Needs shared.h, path_steps.glsl (PathState, ShadowRay) and scene.glsl
// (Hit): path_tracer.glsl.
#include "wavefront_layout.h"

layout(std430, binding = PATH_SLOTS_BINDING) buffer PathSlots { PathSlot slots[]; };
layout(std430, binding = QUEUES_BINDING) buffer Queues {
    Queue queues[QUEUE_COUNT];
    uint queueItems[];  // queue q's items from q * pixelCount()
};

// Which of the two ray queues the kernels read; the shading kernels fill the other.
uniform uint rayQueue;

uint pixelCount() { return imageSize.x * imageSize.y; }

// --8<-- [start:push]
// Add a pixel's path to a queue. Many invocations push at once: atomicAdd gives each
// its own place (the size before its own addition), so no two write the same one.
void push(uint queue, uint pixel) {
    // BEGIN SOLUTION take a place in the queue (atomicAdd on its size), put the pixel there
    uint place = atomicAdd(queues[queue].size, 1u);
    queueItems[queue * pixelCount() + place] = pixel;
    // STUB: // nothing queued: no path is ever traced
    // END SOLUTION
}
// --8<-- [end:push]

// The pixel whose path is this invocation's work in `queue`, if it has one: the queue
// is dispatched in whole work groups, so the last one overhangs.
bool itemOf(uint queue, out uint pixel) {
    uint place = gl_GlobalInvocationID.x;
    if (place >= queues[queue].size) return false;
    pixel = queueItems[queue * pixelCount() + place];
    return true;
}

PathState loadPath(uint pixel) {
    StoredPath p = slots[pixel].path;
    return PathState(Ray(p.origin, p.direction), p.radiance, p.throughput, p.directionPdf,
                     p.afterDelta != 0u, p.bounce);
}
void storePath(uint pixel, PathState path) {
    slots[pixel].path = StoredPath(path.ray.origin, path.directionPdf, path.ray.direction,
                                   path.bounce, path.throughput, uint(path.afterDelta),
                                   path.radiance, 0u);
}

Hit loadHit(uint pixel) {
    StoredHit h = slots[pixel].hit;
    return Hit(h.t, h.position, h.normal, h.geometricNormal, h.front != 0u, h.material,
               h.emitter, h.uv);
}
void storeHit(uint pixel, Hit hit) {
    slots[pixel].hit = StoredHit(hit.position, hit.t, hit.normal, hit.material,
                                 hit.geometricNormal, hit.emitter, hit.uv, uint(hit.front),
                                 0u);
}

ShadowRay loadShadowRay(uint pixel) {
    StoredShadowRay s = slots[pixel].shadowRay;
    return ShadowRay(Ray(s.origin, s.direction), s.tMax, s.light);
}
void storeShadowRay(uint pixel, ShadowRay shadow) {
    slots[pixel].shadowRay = StoredShadowRay(shadow.ray.origin, shadow.tMax,
                                             shadow.ray.direction, 0u, shadow.light, 0u);
}
