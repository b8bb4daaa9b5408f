#version 430 core
// Gives every pixel its generator's starting state, once per image: chapter 09's hashed
// seeding. imageSize and seed (--seed) come in the PathParameters block (shared.h).
#include "shared.h"
#include "random.glsl"

layout(local_size_x = TILE_SIZE, local_size_y = TILE_SIZE) in;
layout(std430, binding = RANDOM_BINDING) writeonly buffer Random {
    RandomState randomStates[];
};

void main() {
    uvec2 pixel = gl_GlobalInvocationID.xy;
    if (pixel.x >= imageSize.x || pixel.y >= imageSize.y) return;
    // --8<-- [start:seed]
    uint index = pixel.y * imageSize.x + pixel.x;  // rng.py's pixel index
    randomStates[index] = seedHashed(seed, index);
    // --8<-- [end:seed]
}
