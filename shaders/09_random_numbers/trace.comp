#version 430 core
// Chapter 09: one random sample per pixel per dispatch, averaged into the image. Each
// pixel draws from its own generator, whose state waits in a storage buffer for the
// next dispatch. A sample is the lit teapot of chapter 08 seen through a random point
// of the pixel (anti-aliasing), the pixel's next random number (--view noise), or
// ambient occlusion from one random ray (--view ao).
#include "shared.h"
#include "random.glsl"
#include "camera.glsl"
#include "scene.glsl"
#include "shading.glsl"

layout(local_size_x = TILE_SIZE, local_size_y = TILE_SIZE) in;
layout(std430, binding = PIXELS_BINDING) buffer Pixels { vec4 pixels[]; };
layout(std430, binding = RANDOM_BINDING) buffer Random { RandomState randomStates[]; };
uniform uvec2 imageSize;
uniform int view;            // VIEW_SHADED, VIEW_NOISE or VIEW_AO
uniform uint sampleIndex;    // how many samples the image holds already
uniform float aoDistance;    // how far an occluder counts, for --view ao

const float FOREVER = 3.0e38;  // close to the largest float: no tMax
const float PI = 3.14159265358979;

// --8<-- [start:sky]
// White near the horizon, light blue straight up: linear colours.
vec3 sky(vec3 direction) {
    return mix(vec3(1.0), vec3(0.5, 0.7, 1.0), 0.5 * (direction.y + 1.0));
}
// --8<-- [end:sky]

// --8<-- [start:ao]
// A direction around `normal`, more likely the closer it is to the normal (density
// cos / pi): a point picked uniformly on the unit disc, lifted onto the hemisphere.
vec3 cosineDirection(vec3 normal, inout RandomState random) {
    float radius = sqrt(random01(random)), angle = 2.0 * PI * random01(random);
    vec3 side = normalize(cross(abs(normal.x) < 0.5 ? vec3(1, 0, 0) : vec3(0, 1, 0),
                                normal));
    vec3 other = cross(normal, side);
    return radius * (cos(angle) * side + sin(angle) * other)
         + sqrt(max(0.0, 1.0 - radius * radius)) * normal;
}

// Ambient occlusion: the share of the sky above a point that nothing nearby hides,
// cosine-weighted. One sample is 1 or 0; the mean over samples converges to it.
float ambientOcclusion(Hit hit, inout RandomState random) {
    vec3 origin = hit.position + hit.geometricNormal * shadowOffset;
    Ray ray = Ray(origin, cosineDirection(hit.normal, random));
    if (dot(ray.direction, hit.geometricNormal) <= 0.0) return 0.0;  // into the surface
    return anyHit(ray, 0.0, aoDistance) ? 0.0 : 1.0;
}
// --8<-- [end:ao]

vec3 traceSample(uvec2 pixel, inout RandomState random) {
    if (view == VIEW_NOISE) return vec3(random01(random));
    // --8<-- [start:jitter]
    // A random point in the pixel instead of its centre: averaged over samples, the
    // pixel shows the mean of the scene over its area, and edges are no longer stairs.
    // BEGIN SOLUTION jitter: two random numbers for the point in the pixel
    vec2 pointInPixel = vec2(random01(random), random01(random));
    // STUB: vec2 pointInPixel = vec2(0.5);
    // END SOLUTION
    Ray ray = primaryRay(pixel, imageSize, pointInPixel);
    // --8<-- [end:jitter]
    Hit hit;
    if (!nearestHit(ray, 0.0, FOREVER, hit))
        return view == VIEW_AO ? vec3(1.0) : sky(ray.direction);
    if (view == VIEW_AO) return vec3(ambientOcclusion(hit, random));
    return shade(hit);  // lit by the light, unless something is in the way
}

void main() {
    uvec2 pixel = gl_GlobalInvocationID.xy;
    if (pixel.x >= imageSize.x || pixel.y >= imageSize.y) return;  // overhanging tiles
    uint index = pixel.y * imageSize.x + pixel.x;

    // --8<-- [start:accumulate]
    // Take the pixel's generator out of the buffer, draw, and put it back advanced: the
    // next dispatch continues the same stream, however the dispatches are grouped.
    RandomState random = randomStates[index];
    vec3 color = traceSample(pixel, random);
    randomStates[index] = random;
    // The running mean of the samples so far, so the image is always the estimate:
    // mean(n + 1) = mean(n) + (sample - mean(n)) / (n + 1).
    vec3 mean = sampleIndex == 0u ? vec3(0.0) : pixels[index].rgb;
    mean += (color - mean) / float(sampleIndex + 1u);
    pixels[index] = vec4(mean, 1.0);
    // --8<-- [end:accumulate]
}
