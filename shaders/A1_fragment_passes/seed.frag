#version 430 core
// Gives every pixel its generator's starting state, once per image: chapter 12's
// seed.comp as a pass over the whole image. It starts the mean and ray count at zero.
// imageSize and seed (--seed) come in the PathParameters block (shared.h).
#include "shared.h"
#include "random.glsl"

layout(location = MEAN_OUTPUT) out vec4 newMean;
layout(location = RANDOM_OUTPUT) out uvec4 newRandomState;
layout(location = RAYS_OUTPUT) out uint newRayCount;

void main() {
    uvec2 pixel = uvec2(gl_FragCoord.xy);  // row 0 at the top, as in path.frag
    // --8<-- [start:seed]
    uint index = pixel.y * imageSize.x + pixel.x;  // rng.py's pixel index
    newRandomState = seedHashed(seed, index).words;
    // --8<-- [end:seed]
    newMean = vec4(0.0);
    newRayCount = 0u;
}
