#version 430 core
// --8<-- [start:extend]
// Trace the rays of the paths in the ray queue: a path whose ray leaves the scene gains
// the environment's light and ends; a hit is stored and queued to be shaded by the
// kernel of its material's kind.
#include "path_tracer.glsl"
#include "wavefront.glsl"

layout(local_size_x = QUEUE_GROUP_SIZE) in;
layout(std430, binding = RAY_COUNT_BINDING) buffer RayCounts { uint rayCounts[]; };

void main() {
    uint slot;
    if (!itemOf(rayQueue, slot)) return;
    PathState path = loadPath(slot);
    rayCounts[pixelOf(slot)] += 1u;
    Hit hit;
    if (!nearestHit(path.ray, 0.0, FOREVER, hit)) {
        leaveScene(path);
        slots[slot].path.radiance = path.radiance;
        return;
    }
    storeHit(slot, hit);
    push(QUEUE_SHADE + materialAt(hit.material).kind, slot);
}
// --8<-- [end:extend]
