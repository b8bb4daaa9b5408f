#version 430 core
// The wavefront's first kernel: the camera ray of each pixel of the wave starts a path
// in the pixel's slot, queued to be traced (the megakernel's main() up to tracePath).
#include "path_tracer.glsl"
#include "wavefront.glsl"

layout(local_size_x = QUEUE_GROUP_SIZE) in;
layout(std430, binding = RANDOM_BINDING) buffer Random { RandomState randomStates[]; };
layout(std430, binding = RAY_COUNT_BINDING) buffer RayCounts { uint rayCounts[]; };

void main() {
    uint slot = gl_GlobalInvocationID.x;
    if (slot >= waveSize) return;  // the last work group overhangs
    uint index = pixelOf(slot);
    uvec2 pixel = uvec2(index % imageSize.x, index / imageSize.x);
    RandomState random = randomStates[index];
    vec2 inPixel = random2(random);
    Ray ray = primaryRay(pixel, imageSize, inPixel, random2(random));
    randomStates[index] = random;
    if (sampleIndex == 0u) rayCounts[index] = 0u;
    storePath(slot, startPath(ray));
    push(rayQueue, slot);
}
