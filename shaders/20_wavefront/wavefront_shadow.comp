#version 430 core
// Trace the shadow rays in the shadow queue: each unblocked one adds its light to its
// path's radiance.
#include "path_tracer.glsl"
#include "wavefront.glsl"

layout(local_size_x = QUEUE_GROUP_SIZE) in;
layout(std430, binding = RAY_COUNT_BINDING) buffer RayCounts { uint rayCounts[]; };

void main() {
    uint pixel;
    if (!itemOf(QUEUE_SHADOW, pixel)) return;
    uint rays = rayCounts[pixel];
    vec3 light = shadowRayLight(loadShadowRay(pixel), rays);
    rayCounts[pixel] = rays;
    slots[pixel].path.radiance += light;
}
