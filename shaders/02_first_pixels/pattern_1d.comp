#version 430 core
// Chapter 02, first try: one long line of invocations, one per pixel.
#include "shared.h"
#include "pattern.glsl"

layout(local_size_x = WORKGROUP_SIZE_1D) in;
layout(std430, binding = PIXELS_BINDING) writeonly buffer Pixels { vec4 pixels[]; };
uniform uvec2 imageSize;

void main() {
    // --8<-- [start:index]
    uint index = gl_GlobalInvocationID.x;
    if (index >= imageSize.x * imageSize.y) return;  // the last group overhangs
    // BEGIN SOLUTION turn the flat index into a column and a row
    uvec2 pixel = uvec2(index % imageSize.x, index / imageSize.x);
    // STUB: uvec2 pixel = uvec2(0u);
    // END SOLUTION
    // --8<-- [end:index]
    pixels[index] = vec4(patternColor(pixel, imageSize), 1.0);
}
