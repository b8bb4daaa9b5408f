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
    uint pixel;
    if (!itemOf(rayQueue, pixel)) return;
    PathState path = loadPath(pixel);
    rayCounts[pixel] += 1u;
    Hit hit;
    if (!nearestHit(path.ray, 0.0, FOREVER, hit)) {
        leaveScene(path);
        slots[pixel].path.radiance = path.radiance;
        return;
    }
    storeHit(pixel, hit);
    push(QUEUE_SHADE + materialAt(hit.material).kind, pixel);
}
// --8<-- [end:extend]
