#version 430 core
// Chapter 08: a smooth-looking mesh from flat triangles. Every camera ray looks for the
// nearest triangle; the normal there is blended from the normals at its corners, and
// the hit is lit by a point light unless a shadow ray finds something in the way.
#include "shared.h"
#include "camera.glsl"
#include "hit.glsl"
#include "triangle.glsl"
#include "scene.glsl"
#include "shading.glsl"

layout(local_size_x = TILE_SIZE, local_size_y = TILE_SIZE) in;
layout(std430, binding = PIXELS_BINDING) writeonly buffer Pixels { vec4 pixels[]; };
uniform uvec2 imageSize;

const float FOREVER = 3.0e38;  // close to the largest float: no tMax

// --8<-- [start:sky]
// White near the horizon, light blue straight up: linear colours.
vec3 sky(vec3 direction) {
    return mix(vec3(1.0), vec3(0.5, 0.7, 1.0), 0.5 * (direction.y + 1.0));
}
// --8<-- [end:sky]

void main() {
    uvec2 pixel = gl_GlobalInvocationID.xy;
    if (pixel.x >= imageSize.x || pixel.y >= imageSize.y) return;  // overhanging tiles

    // --8<-- [start:color]
    Ray ray = primaryRay(pixel, imageSize);
    Hit hit;
    vec3 color;
    if (nearestHit(ray, 0.0, FOREVER, hit))
        color = shade(hit);  // lit by the light, unless something is in the way
    else
        color = sky(ray.direction);
    // --8<-- [end:color]
    pixels[pixel.y * imageSize.x + pixel.x] = vec4(color, 1.0);
}
