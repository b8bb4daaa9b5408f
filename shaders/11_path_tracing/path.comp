#version 430 core
// Chapter 11: path tracing. Each dispatch adds one sample to every pixel: a path from
// the camera that bounces off Lambertian surfaces in random directions, gathering the
// light of every glowing surface it runs into. The image holds the running mean: linear
// radiance.
#include "shared.h"
#include "random.glsl"
#include "camera.glsl"
#include "scene.glsl"
#include "sampling.glsl"

layout(local_size_x = TILE_SIZE, local_size_y = TILE_SIZE) in;
layout(std430, binding = PIXELS_BINDING) buffer Pixels { vec4 pixels[]; };
layout(std430, binding = RANDOM_BINDING) buffer Random { RandomState randomStates[]; };
layout(std430, binding = RAY_COUNT_BINDING) buffer RayCounts { uint rayCounts[]; };

// imageSize, sampleIndex, maxBounces (--depth) and the camera come in the
// PathParameters uniform block (shared.h).

const float FOREVER = 3.0e38;

// --8<-- [start:offset]
// A point just off the surface, on its front: float32 rounds a hit point to within a
// few units in the last place of its coordinates, so the gap grows with their size.
vec3 offsetFromSurface(vec3 position, vec3 normal) {
    vec3 size = abs(position);
    return position + RAY_OFFSET * (1.0 + max(size.x, max(size.y, size.z))) * normal;
}
// --8<-- [end:offset]

// --8<-- [start:path]
// One path's estimate of the radiance arriving along `ray`: a loop, not recursion
// (GLSL has none), carrying the `throughput`, the product of (BSDF cos / pdf) so far.
vec3 tracePath(Ray ray, inout RandomState random, inout uint rays) {
    vec3 radiance = vec3(0.0);
    vec3 throughput = vec3(1.0);
    for (int bounce = 0;; ++bounce) {
        Hit hit;
        rays += 1u;
        if (!nearestHit(ray, 0.0, FOREVER, hit)) break;  // out of the scene: no sky
        Material material = materials[hit.material];

        // 1. Light the ray runs into, seen through everything the path bounced off.
        if (hit.front) radiance += throughput * material.emission.rgb;
        // A surface's back is black (as Mitsuba's diffuse); --depth ends the path.
        if (!hit.front || bounce == maxBounces) break;
        // --8<-- [start:shading_normal]
        // So is a front whose smooth normal faces away from the ray: near a mesh's
        // outline the blended normal can lean past the flat one (Mitsuba agrees).
        if (dot(hit.normal, ray.direction) >= 0.0) break;

        // 2. The next direction, by cosine sampling about the smooth normal:
        //    (albedo / pi) cos / (cos / pi) is the albedo, so the throughput only picks
        //    up the surface's colour.
        vec3 direction = cosineSampleHemisphere(hit.normal, random2(random));
        // A direction under the surface itself would leave through the mesh's inside
        // (where a closed mesh is black) or leak light through an open one: it ends.
        if (dot(direction, hit.geometricNormal) <= 0.0) break;
        // --8<-- [end:shading_normal]
        // BEGIN SOLUTION the throughput picks up this bounce's f cos / pdf
        throughput *= material.albedo.rgb;
        // STUB: throughput *= 0.0;
        // END SOLUTION
        ray = Ray(offsetFromSurface(hit.position, hit.geometricNormal), direction);
    }
    return radiance;
}
// --8<-- [end:path]

void main() {
    uvec2 pixel = gl_GlobalInvocationID.xy;
    if (pixel.x >= imageSize.x || pixel.y >= imageSize.y) return;  // overhanging tiles
    uint index = pixel.y * imageSize.x + pixel.x;

    // --8<-- [start:accumulate]
    // As in chapter 09: the pixel's generator continues from the previous dispatch,
    // and the image holds the running mean of the samples.
    RandomState random = randomStates[index];
    uint rays = sampleIndex == 0u ? 0u : rayCounts[index];
    Ray ray = primaryRay(pixel, imageSize, random2(random));  // a random point (AA)
    vec3 radiance = tracePath(ray, random, rays);
    randomStates[index] = random;
    rayCounts[index] = rays;
    vec3 mean = sampleIndex == 0u ? vec3(0.0) : pixels[index].rgb;
    mean += (radiance - mean) / float(sampleIndex + 1u);
    pixels[index] = vec4(mean, 1.0);
    // --8<-- [end:accumulate]
}
