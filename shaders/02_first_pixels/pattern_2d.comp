#version 430 core
// Chapter 02, second try: 8x8 tiles of invocations, so gl_GlobalInvocationID.xy is
// already the pixel.
#include "shared.h"
#include "pattern.glsl"

layout(local_size_x = TILE_SIZE, local_size_y = TILE_SIZE) in;
layout(std430, binding = PIXELS_BINDING) writeonly buffer Pixels { vec4 pixels[]; };
uniform uvec2 imageSize;

void main() {
    // --8<-- [start:index]
    uvec2 pixel = gl_GlobalInvocationID.xy;
    // Tiles on the right and bottom edges overhang the image.
    if (pixel.x >= imageSize.x || pixel.y >= imageSize.y) return;
    uint index = pixel.y * imageSize.x + pixel.x;
    // --8<-- [end:index]
    pixels[index] = vec4(patternColor(pixel, imageSize), 1.0);
}
