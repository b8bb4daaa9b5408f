#version 430 core
// Chapter 10: a scene from a file, previewed. One random sample per pixel per dispatch,
// averaged into the image, as in chapter 09. A sample is what the ray through a random
// point of the pixel finds: the surface's own glow, plus its colour times ambient
// occlusion (--view shaded); or the pixel's next random number (--view noise); or
// ambient occlusion alone (--view ao).
#include "shared.h"
#include "random.glsl"
#include "camera.glsl"
#include "scene.glsl"

layout(local_size_x = TILE_SIZE, local_size_y = TILE_SIZE) in;
layout(std430, binding = PIXELS_BINDING) buffer Pixels { vec4 pixels[]; };
layout(std430, binding = RANDOM_BINDING) buffer Random { RandomState randomStates[]; };
uniform uvec2 imageSize;
uniform int view;            // VIEW_SHADED, VIEW_NOISE or VIEW_AO
uniform uint sampleIndex;    // how many samples the image holds already
uniform float aoDistance;    // how far an occluder counts, for --view ao

const float FOREVER = 3.0e38;  // close to the largest float: no tMax
const float PI = 3.14159265358979;

// --8<-- [start:offset]
// A point just off the surface, on its front: float32 rounds a hit point to within a
// few units in the last place of its coordinates, so the gap grows with their size.
vec3 offsetFromSurface(vec3 position, vec3 normal) {
    vec3 size = abs(position);
    return position + RAY_OFFSET * (1.0 + max(size.x, max(size.y, size.z))) * normal;
}
// --8<-- [end:offset]

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
    vec3 origin = offsetFromSurface(hit.position, hit.geometricNormal);
    Ray ray = Ray(origin, cosineDirection(hit.normal, random));
    if (dot(ray.direction, hit.geometricNormal) <= 0.0) return 0.0;  // into the surface
    return anyHit(ray, 0.0, aoDistance) ? 0.0 : 1.0;
}
// --8<-- [end:ao]

// --8<-- [start:sample]
vec3 traceSample(uvec2 pixel, inout RandomState random) {
    if (view == VIEW_NOISE) return vec3(random01(random));
    // --8<-- [start:jitter]
    // A random point in the pixel instead of its centre: averaged over samples, the
    // pixel shows the mean of the scene over its area, and edges are no longer stairs.
    vec2 pointInPixel = vec2(random01(random), random01(random));
    Ray ray = primaryRay(pixel, imageSize, pointInPixel);
    // --8<-- [end:jitter]
    Hit hit;
    // Out of the scene, or the back of a surface: black. Surfaces have a front now,
    // the side a quad's edges or a triangle's corners turn counter-clockwise about.
    if (!nearestHit(ray, 0.0, FOREVER, hit) || !hit.front) return vec3(0.0);
    // A smooth normal turned away from the ray, near a mesh's outline: black as well.
    if (dot(hit.normal, ray.direction) >= 0.0) return vec3(0.0);
    float occlusion = ambientOcclusion(hit, random);
    if (view == VIEW_AO) return vec3(occlusion);
    Material material = materials[hit.material];
    // BEGIN SOLUTION what a surface shows: its glow, and its colour where light gets in
    return material.emission.rgb + material.albedo.rgb * occlusion;
    // STUB: return vec3(1.0);  // every surface white: no materials yet
    // END SOLUTION
}
// --8<-- [end:sample]

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
