#version 430 core
// Appendix A1: chapter 12's path tracer as a fragment shader. Each pass draws one
// triangle over the whole image, and this shader runs once per pixel: it adds one
// sample, a path from the camera that bounces off Lambertian surfaces, gathering the
// light of the area lights it finds (by hitting them, by aiming shadow rays at them, or
// both, weighted by multiple importance sampling). What the pixel had before comes from
// the textures the previous pass wrote; the new state goes to this pass's framebuffer.
#include "shared.h"
#include "random.glsl"
#include "camera.glsl"
#include "scene.glsl"
#include "sampling.glsl"

// --8<-- [start:io]
// The previous pass's framebuffer, read-only here: a texture cannot be read and
// written in the same pass, hence two framebuffers that take turns (ping-pong).
uniform sampler2D previousMean;     // RGBA32F, the running mean
uniform usampler2D previousRandom;  // RGBA32UI, the generator states
uniform usampler2D previousRays;    // R32UI, the rays traced so far

// This pass's framebuffer: one colour attachment per output.
layout(location = MEAN_OUTPUT) out vec4 newMean;
layout(location = RANDOM_OUTPUT) out uvec4 newRandomState;
layout(location = RAYS_OUTPUT) out uint newRayCount;
// --8<-- [end:io]

// imageSize, sampleIndex, maxBounces (--depth), estimator and the camera come in the
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

// --8<-- [start:nee]
// Next-event estimation: the light arriving at the hit straight from one point picked
// on one emitter, if a shadow ray finds nothing in the way; per unit albedo and already
// divided by the density of the choice. With MIS, weighted against BSDF sampling.
vec3 lightFromEmitters(Hit hit, inout RandomState random, inout uint rays) {
    uint emitterCount = uint(emitters.length());
    uint chosen = min(uint(random01(random) * float(emitterCount)), emitterCount - 1u);
    LightPoint light = sampleEmitter(emitters[chosen], random2(random));
    vec3 origin = offsetFromSurface(hit.position, hit.geometricNormal);
    vec3 toLight = light.position - origin;
    float distance = length(toLight);
    vec3 direction = toLight / distance;
    float cosSurface = dot(hit.normal, direction);
    float cosLight = -dot(light.normal, direction);
    if (cosSurface <= 0.0 || cosLight <= 0.0) return vec3(0.0);  // behind one or other
    // Under the surface itself: BSDF sampling ends such paths (chapter 11), so must this.
    if (dot(hit.geometricNormal, direction) <= 0.0) return vec3(0.0);
    rays += 1u;
    // Stop short of the light by the same kind of gap, or the light itself is in the way.
    float stop = length(offsetFromSurface(light.position, light.normal) - light.position);
    if (anyHit(Ray(origin, direction), 0.0, distance - stop)) return vec3(0.0);
    float pdf = lightPdf(chosen, distance, cosLight);
    float weight = estimator == ESTIMATOR_MIS ? powerHeuristic(pdf, cosSurface / PI) : 1.0;
    // The Lambertian BSDF is albedo / pi; the albedo is applied by the caller.
    return light.emission * (cosSurface / PI) / pdf * weight;
}
// --8<-- [end:nee]

// --8<-- [start:path]
// One path's estimate of the radiance arriving along `ray`: a loop, not recursion
// (GLSL has none), carrying the `throughput`, the product of (BSDF cos / pdf) so far.
vec3 tracePath(Ray ray, inout RandomState random, inout uint rays) {
    vec3 radiance = vec3(0.0);
    vec3 throughput = vec3(1.0);
    float directionPdf = 0.0;  // the density with which BSDF sampling chose `ray`
    for (int bounce = 0;; ++bounce) {
        Hit hit;
        rays += 1u;
        if (!nearestHit(ray, 0.0, FOREVER, hit)) break;  // out of the scene: no sky
        Material material = materials[hit.material];

        // 1. Light the ray runs into. The camera sees it in full; after a bounce, NEE
        //    has counted it already (weight 0) or shares it with MIS.
        if (hit.front && hit.emitter != NO_EMITTER) {
            float weight = 1.0;
            if (bounce > 0 && estimator == ESTIMATOR_NEE) weight = 0.0;
            if (bounce > 0 && estimator == ESTIMATOR_MIS) {
                float cosLight = -dot(hit.geometricNormal, ray.direction);
                weight = powerHeuristic(directionPdf, lightPdf(hit.emitter, hit.t, cosLight));
            }
            radiance += throughput * material.emission.rgb * weight;
        }
        // A surface's back is black (as Mitsuba's diffuse); --depth ends the path.
        if (!hit.front || bounce == maxBounces) break;
        // So is a front whose smooth normal faces away from the ray (chapter 11).
        if (dot(hit.normal, ray.direction) >= 0.0) break;

        // 2. Light from the emitters straight to this point (next-event estimation).
        vec3 albedo = material.albedo.rgb;
        if (estimator != ESTIMATOR_BSDF)
            radiance += throughput * albedo * lightFromEmitters(hit, random, rays);

        // 3. The next direction, by cosine sampling: (albedo / pi) cos / (cos / pi) is
        //    the albedo, so the throughput only picks up the surface's colour.
        vec3 direction = cosineSampleHemisphere(hit.normal, random2(random));
        if (dot(direction, hit.geometricNormal) <= 0.0) break;  // under it (chapter 11)
        directionPdf = max(dot(hit.normal, direction), 0.0) / PI;
        throughput *= albedo;

        // 4. Russian roulette: after a few bounces, a path carrying little light ends
        //    with probability 1 - survival; the survivors carry 1 / survival more, so
        //    the expected value is unchanged (unbiased), only the noise grows a little.
        if (bounce + 1 >= ROULETTE_AFTER) {
            float survival = min(max(throughput.r, max(throughput.g, throughput.b)), 0.95);
            if (random01(random) >= survival) break;
            throughput /= survival;
        }
        ray = Ray(offsetFromSurface(hit.position, hit.geometricNormal), direction);
    }
    return radiance;
}
// --8<-- [end:path]

void main() {
    // --8<-- [start:pixel]
    // gl_FragCoord is the pixel's centre, (x + 0.5, y + 0.5). Row y of the framebuffer
    // holds row y of the image counted from the top, as in chapter 12: upside down by
    // GL's convention, but glReadPixels then hands back the top row first, the order
    // of an image file. The pixel sees the same ray and random numbers as in chapter 12.
    uvec2 pixel = uvec2(gl_FragCoord.xy);
    ivec2 samePixel = ivec2(pixel);  // where the previous pass left this pixel's state
    // --8<-- [end:pixel]

    // --8<-- [start:accumulate]
    // As in chapter 12: the pixel's generator continues from the previous pass, and the
    // image holds the running mean of the samples.
    // BEGIN SOLUTION the pixel's state from the previous pass's textures, one more sample
    RandomState random = RandomState(texelFetch(previousRandom, samePixel, 0));
    uint rays = sampleIndex == 0u ? 0u : texelFetch(previousRays, samePixel, 0).r;
    Ray ray = primaryRay(pixel, imageSize, random2(random));  // a random point (AA)
    vec3 radiance = tracePath(ray, random, rays);
    newRandomState = random.words;
    newRayCount = rays;
    vec3 mean = sampleIndex == 0u ? vec3(0.0) : texelFetch(previousMean, samePixel, 0).rgb;
    mean += (radiance - mean) / float(sampleIndex + 1u);
    newMean = vec4(mean, 1.0);
    // STUB: newMean = vec4(1.0, 0.0, 1.0, 1.0);  // magenta: no sample traced yet
    // END SOLUTION
    // --8<-- [end:accumulate]
}
