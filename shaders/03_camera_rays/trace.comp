#version 430 core
// Chapter 03: one camera ray per pixel; the picture shows each ray's direction.
#include "shared.h"
#include "camera.glsl"

layout(local_size_x = TILE_SIZE, local_size_y = TILE_SIZE) in;
layout(std430, binding = PIXELS_BINDING) writeonly buffer Pixels { vec4 pixels[]; };
uniform uvec2 imageSize;

void main() {
    uvec2 pixel = gl_GlobalInvocationID.xy;
    if (pixel.x >= imageSize.x || pixel.y >= imageSize.y) return;  // overhanging tiles

    // --8<-- [start:color]
    Ray ray = primaryRay(pixel, imageSize);
    // A unit direction has components in [-1, 1]; squeeze them into colours in [0, 1]:
    // red is rightwards (+x), green upwards (+y), blue towards us (+z).
    vec3 color = 0.5 * ray.direction + 0.5;
    // --8<-- [end:color]
    pixels[pixel.y * imageSize.x + pixel.x] = vec4(color, 1.0);
}
