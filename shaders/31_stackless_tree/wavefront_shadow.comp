#version 430 core
// Trace the shadow rays in the shadow queue: each unblocked one adds its light to its
// path's radiance.
#include "path_tracer.glsl"
#include "wavefront.glsl"

layout(local_size_x = QUEUE_GROUP_SIZE) in;
layout(std430, binding = RAY_COUNT_BINDING) buffer RayCounts { uint rayCounts[]; };

void main() {
    uint slot;
    if (!itemOf(QUEUE_SHADOW, slot)) return;
    uint rays = rayCounts[pixelOf(slot)];
    vec3 light = shadowRayLight(loadShadowRay(slot), rays);
    rayCounts[pixelOf(slot)] = rays;
    slots[slot].path.radiance += light;
}
