#version 430 core
// --dump-random: each dispatch draws one 32-bit number from every pixel's generator
// and stores it as number `drawIndex` of that pixel, for the checks to read back.
#include "shared.h"
#include "random.glsl"

layout(local_size_x = TILE_SIZE, local_size_y = TILE_SIZE) in;
layout(std430, binding = RANDOM_BINDING) buffer Random { RandomState randomStates[]; };
layout(std430, binding = DUMP_BINDING) writeonly buffer Drawn { uint drawn[]; };
uniform uvec2 imageSize;
uniform uint drawIndex;

void main() {
    uvec2 pixel = gl_GlobalInvocationID.xy;
    if (pixel.x >= imageSize.x || pixel.y >= imageSize.y) return;
    uint index = pixel.y * imageSize.x + pixel.x;
    RandomState random = randomStates[index];
    // Laid out as (count, height, width), like rng.pixel_streams().
    drawn[drawIndex * imageSize.x * imageSize.y + index] = nextRandom(random);
    randomStates[index] = random;
}
