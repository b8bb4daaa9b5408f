#version 430 core
// The wavefront's first kernel: each pixel's camera ray starts a path, queued to be
// traced (the megakernel's main() up to tracePath).
#include "path_tracer.glsl"
#include "wavefront.glsl"

layout(local_size_x = TILE_SIZE, local_size_y = TILE_SIZE) in;
layout(std430, binding = RANDOM_BINDING) buffer Random { RandomState randomStates[]; };
layout(std430, binding = RAY_COUNT_BINDING) buffer RayCounts { uint rayCounts[]; };

void main() {
    uvec2 pixel = gl_GlobalInvocationID.xy;
    if (pixel.x >= imageSize.x || pixel.y >= imageSize.y) return;  // overhanging tiles
    uint index = pixel.y * imageSize.x + pixel.x;
    RandomState random = randomStates[index];
    vec2 inPixel = random2(random);
    Ray ray = primaryRay(pixel, imageSize, inPixel, random2(random));
    randomStates[index] = random;
    if (sampleIndex == 0u) rayCounts[index] = 0u;
    storePath(index, startPath(ray));
    push(rayQueue, index);
}
