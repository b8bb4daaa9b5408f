// What the wavefront kernels share: the pool of path slots, where each path's state,
// hit and shadow ray wait between kernels (PathSlot), and the queues that say which
// slots have work for the next kernel. Needs path_tracer.glsl (PathState, ShadowRay,
// Hit).
#include "wavefront_layout.h"

layout(std430, binding = PATH_SLOTS_BINDING) buffer PathSlots { PathSlot slots[]; };
layout(std430, binding = QUEUES_BINDING) buffer Queues {
    Queue queues[QUEUE_COUNT];
    uint queueItems[];  // queue q's items from q * poolSize
};

// The pixel whose path a slot holds in this wave (WaveParameters, wavefront_layout.h).
uint pixelOf(uint slot) { return firstPixel + slot; }

// --8<-- [start:push]
// Add a path's slot to a queue. Many invocations push at once: atomicAdd gives each its
// own place (the size before its own addition), so no two write the same one.
void push(uint queue, uint slot) {
    uint place = atomicAdd(queues[queue].size, 1u);
    queueItems[queue * poolSize + place] = slot;
}
// --8<-- [end:push]

// The slot whose path is this invocation's work in `queue`, if it has one: the queue
// is dispatched in whole work groups, so the last one overhangs.
bool itemOf(uint queue, out uint slot) {
    uint place = gl_GlobalInvocationID.x;
    if (place >= queues[queue].size) return false;
    slot = queueItems[queue * poolSize + place];
    return true;
}

PathState loadPath(uint slot) {
    StoredPath p = slots[slot].path;
    return PathState(Ray(p.origin, p.direction), p.radiance, p.throughput, p.directionPdf,
                     p.afterDelta != 0u, p.bounce);
}
void storePath(uint slot, PathState path) {
    slots[slot].path = StoredPath(path.ray.origin, path.directionPdf, path.ray.direction,
                                   path.bounce, path.throughput, uint(path.afterDelta),
                                   path.radiance, 0u);
}

Hit loadHit(uint slot) {
    StoredHit h = slots[slot].hit;
    return Hit(h.t, h.position, h.normal, h.geometricNormal, h.front != 0u, h.material,
               h.emitter, h.uv);
}
void storeHit(uint slot, Hit hit) {
    slots[slot].hit = StoredHit(hit.position, hit.t, hit.normal, hit.material,
                                 hit.geometricNormal, hit.emitter, hit.uv, uint(hit.front),
                                 0u);
}

ShadowRay loadShadowRay(uint slot) {
    StoredShadowRay s = slots[slot].shadowRay;
    return ShadowRay(Ray(s.origin, s.direction), s.tMax, s.light);
}
void storeShadowRay(uint slot, ShadowRay shadow) {
    slots[slot].shadowRay = StoredShadowRay(shadow.ray.origin, shadow.tMax,
                                             shadow.ray.direction, 0u, shadow.light, 0u);
}
