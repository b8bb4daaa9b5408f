#version 430 core
// Chapter 18: chapter 17's path tracer under an environment light (environment.glsl):
// a ray that leaves the scene sees it, and next-event estimation samples it as it
// samples the emitting shapes, by importance, weighted by MIS against BSDF sampling.
// At each bounce the material's BSDF (bsdf.glsl) evaluates, weighs and samples; a
// delta BSDF skips next-event estimation; a hit on the back of glass is the ray leaving
// it. Each dispatch adds one sample to every pixel; the image holds the running mean.
// --view shows what the camera rays hit (normals, distance, albedo, texture
// coordinates), how hard the tree worked for them, or random bounce rays.
#include "shared.h"
#include "random.glsl"
#include "camera.glsl"
#include "scene.glsl"
#include "sampling.glsl"
#include "environment.glsl"
#include "microfacet.glsl"
#include "dielectric.glsl"
#include "bsdf.glsl"
#include "features.glsl"

layout(local_size_x = TILE_SIZE, local_size_y = TILE_SIZE) in;
layout(std430, binding = PIXELS_BINDING) buffer Pixels { vec4 pixels[]; };
layout(std430, binding = RANDOM_BINDING) buffer Random { RandomState randomStates[]; };
layout(std430, binding = RAY_COUNT_BINDING) buffer RayCounts { uint rayCounts[]; };

// imageSize, sampleIndex, maxBounces (--depth), estimator and the camera come in the
// PathParameters uniform block (shared.h), and so do view and occlusionDistance.

// VIEW_BOUNCE: where each pixel's camera ray hit (w = 1) or that it hit nothing (w = 0),
// found by the first dispatch; every dispatch then traces one random ray from there.
struct BounceStart {
    vec4 position;
    vec4 normal;
};
layout(std430, binding = BOUNCE_START_BINDING) buffer BounceStarts {
    BounceStart bounceStarts[];
};

const float FOREVER = 3.0e38;

// --8<-- [start:offset]
// A point just off the surface, on the side `normal` points to: float32 rounds a hit
// point to within a few units in the last place of its coordinates, so the gap grows
// with their size.
vec3 offsetFromSurface(vec3 position, vec3 normal) {
    vec3 size = abs(position);
    return position + RAY_OFFSET * (1.0 + max(size.x, max(size.y, size.z))) * normal;
}
// --8<-- [end:offset]

// --8<-- [start:environment_nee]
// Next-event estimation towards the environment: a direction picked by its tables; if
// nothing is in the way, its radiance reflected towards the viewer, divided by the
// density of the choice (the chance of sampling the environment at all, times the
// tables' density), weighted by MIS against BSDF sampling.
vec3 lightFromEnvironment(Hit hit, Material material, mat3 frame, vec3 toViewer,
                          inout RandomState random, inout uint rays) {
    float pdf;
    vec3 radiance;
    vec3 direction = sampleEnvironment(random2(random), pdf, radiance);
    if (pdf <= 0.0) return vec3(0.0);
    if (dot(hit.normal, direction) * dot(hit.geometricNormal, direction) <= 0.0)
        return vec3(0.0);
    vec3 reflected = bsdfEval(material, frame, toViewer, direction);  // f cos
    if (reflected == vec3(0.0)) return vec3(0.0);
    vec3 side = dot(direction, hit.geometricNormal) > 0.0 ? hit.geometricNormal
                                                           : -hit.geometricNormal;
    rays += 1u;
    if (anyHit(Ray(offsetFromSurface(hit.position, side), direction), 0.0, FOREVER))
        return vec3(0.0);
    pdf *= environmentChance;
    float weight = estimator == ESTIMATOR_MIS
                       ? powerHeuristic(pdf, bsdfPdf(material, frame, toViewer, direction))
                       : 1.0;
    return radiance * reflected / pdf * weight;
}
// --8<-- [end:environment_nee]

// --8<-- [start:nee]
// Next-event estimation: the light arriving at the hit straight from one point picked
// on one emitter, if a shadow ray finds nothing in the way, reflected towards the
// viewer by the material's BSDF and divided by the density of the choice. With MIS,
// weighted against the BSDF sampling that could have found the same point. With an
// environment, it is the light sampled instead with probability environmentChance.
vec3 lightFromEmitters(Hit hit, Material material, mat3 frame, vec3 toViewer,
                       inout RandomState random, inout uint rays) {
    if (random01(random) < environmentChance)
        return lightFromEnvironment(hit, material, frame, toViewer, random, rays);
    uint emitterCount = uint(emitters.length());
    uint chosen = min(uint(random01(random) * float(emitterCount)), emitterCount - 1u);
    LightPoint light = sampleEmitter(emitters[chosen], random2(random));
    // The shadow ray leaves from the light's side of the surface: through glass, the
    // back. (The BSDF says whether anything gets there: nothing, for an opaque one.)
    vec3 lightSide = dot(light.position - hit.position, hit.geometricNormal) > 0.0
                         ? hit.geometricNormal : -hit.geometricNormal;
    vec3 origin = offsetFromSurface(hit.position, lightSide);
    vec3 toLight = light.position - origin;
    float distance = length(toLight);
    vec3 direction = toLight / distance;
    float cosLight = -dot(light.normal, direction);
    if (cosLight <= 0.0) return vec3(0.0);  // behind the light
    // The flat and the smooth normal must put the light on the same side: BSDF
    // sampling ends other paths (chapter 11), so must this.
    if (dot(hit.normal, direction) * dot(hit.geometricNormal, direction) <= 0.0)
        return vec3(0.0);
    vec3 reflected = bsdfEval(material, frame, toViewer, direction);  // f cos
    if (reflected == vec3(0.0)) return vec3(0.0);  // no shadow ray for nothing
    rays += 1u;
    // Stop short of the light by the same kind of gap, or the light itself is in the way.
    float stop = length(offsetFromSurface(light.position, light.normal) - light.position);
    if (anyHit(Ray(origin, direction), 0.0, distance - stop)) return vec3(0.0);
    float pdf = lightPdf(chosen, distance, cosLight);
    float weight = estimator == ESTIMATOR_MIS
                       ? powerHeuristic(pdf, bsdfPdf(material, frame, toViewer, direction))
                       : 1.0;
    return light.emission * reflected / pdf * weight;
}
// --8<-- [end:nee]

// --8<-- [start:path]
// One path's estimate of the radiance arriving along `ray`: a loop, not recursion
// (GLSL has none), carrying the `throughput`, the product of (BSDF cos / pdf) so far.
vec3 tracePath(Ray ray, inout RandomState random, inout uint rays,
               out SurfaceFeatures first) {
    vec3 radiance = vec3(0.0);
    vec3 throughput = vec3(1.0);
    float directionPdf = 0.0;  // the density with which BSDF sampling chose `ray`
    bool afterDelta = false;   // chosen by a delta BSDF: no NEE could find that light
    bool settled = false;
    float travelled = 0.0;
    first = SurfaceFeatures(vec3(1.0), -ray.direction, DEPTH_OF_NOTHING, vec3(0.0));
    for (int bounce = 0;; ++bounce) {
        Hit hit;
        rays += 1u;
        if (!nearestHit(ray, 0.0, FOREVER, hit)) {
            if (!settled)
                first = SurfaceFeatures(vec3(1.0), -ray.direction, DEPTH_OF_NOTHING, vec3(0.0));
            // Out of the scene: the environment's light, counted as an emitter's is.
            if (hasEnvironment()) {
                float weight = 1.0;
                bool sampledOnly = bounce == 0 || afterDelta;
                if (!sampledOnly && estimator == ESTIMATOR_NEE) weight = 0.0;
                if (!sampledOnly && estimator == ESTIMATOR_MIS)
                    weight = powerHeuristic(directionPdf,
                                            environmentChance * environmentPdf(ray.direction));
                radiance += throughput * environmentRadiance(ray.direction) * weight;
                if (!settled && bounce == 0) first.emitted = environmentRadiance(ray.direction);
            }
            break;
        }
        Material material = materials[hit.material];
        material.albedo = albedoAt(material, hit.uv);  // a texture's, where it has one
        travelled += hit.t;
        bool recordedHere = !settled;
        recordSurface(first, settled, throughput, material, hit, travelled);

        // 1. Light the ray runs into. The camera sees it in full, and so does a mirror;
        //    after another bounce, NEE has counted it already (weight 0) or shares it.
        if (hit.front && hit.emitter != NO_EMITTER) {
            float weight = 1.0;
            bool sampledOnly = bounce == 0 || afterDelta;
            if (!sampledOnly && estimator == ESTIMATOR_NEE) weight = 0.0;
            if (!sampledOnly && estimator == ESTIMATOR_MIS) {
                float cosLight = -dot(hit.geometricNormal, ray.direction);
                weight = powerHeuristic(directionPdf, lightPdf(hit.emitter, hit.t, cosLight));
            }
            radiance += throughput * material.emission * weight;
            if (recordedHere && bounce == 0) first.emitted = material.emission;
        }
        // A surface's back is black (as Mitsuba's), except glass's: a ray that meets
        // it is inside, on its way out. --depth ends the path.
        bool glass = material.kind == MATERIAL_DIELECTRIC;
        if ((!hit.front && !glass) || bounce == maxBounces) break;
        // The flat normal says which side the ray is on; where the smooth one disagrees
        // the path ends (chapter 11's rule for a front, now for both sides).
        if (dot(hit.normal, ray.direction) * dot(hit.geometricNormal, ray.direction) <= 0.0)
            break;

        // 2. Light from the emitters straight to this point (next-event estimation),
        //    except at a delta BSDF, which reflects none of it.
        // The shading frame: the smooth normal, outwards, so wi.z < 0 inside glass.
        mat3 frame = basisAround(hit.normal);
        vec3 toViewer = -ray.direction;
        afterDelta = isDelta(material);
        if (estimator != ESTIMATOR_BSDF && !afterDelta)
            radiance += throughput *
                        lightFromEmitters(hit, material, frame, toViewer, random, rays);

        // 3. The next direction, sampled by the material: the throughput picks up
        //    eval / pdf (the albedo for a Lambertian surface, F for a mirror).
        vec3 u = vec3(random2(random), random01(random));
        BsdfSample next = bsdfSample(material, frame, toViewer, u);
        if (next.weight == vec3(0.0)) break;  // a failed sample
        // The side it leaves on, by the flat normal; the smooth one must agree.
        vec3 side = dot(next.wo, hit.geometricNormal) > 0.0 ? hit.geometricNormal
                                                            : -hit.geometricNormal;
        if (dot(next.wo, hit.normal) * dot(next.wo, hit.geometricNormal) <= 0.0) break;
        directionPdf = next.pdf;
        throughput *= next.weight;

        // 4. Russian roulette: after a few bounces, a path carrying little light ends
        //    with probability 1 - survival; the survivors carry 1 / survival more, so
        //    the expected value is unchanged (unbiased), only the noise grows a little.
        if (bounce + 1 >= ROULETTE_AFTER) {
            float survival = min(max(throughput.r, max(throughput.g, throughput.b)), 0.95);
            if (random01(random) >= survival) break;
            throughput /= survival;
        }
        ray = Ray(offsetFromSurface(hit.position, side), next.wo);
    }
    return radiance;
}
// --8<-- [end:path]

// --8<-- [start:views]
// A heat map for --view cost: dark blue (no work) through cyan and yellow to red (the
// scale's worth of traversal steps, or more).
vec3 heat(float x) {
    const vec3 blue = vec3(0.0, 0.0, 0.4), cyan = vec3(0.0, 0.7, 1.0);
    const vec3 yellow = vec3(1.0, 0.9, 0.0), red = vec3(0.9, 0.0, 0.0);
    x = clamp(x, 0.0, 1.0) * 3.0;
    return x < 1.0 ? mix(blue, cyan, x) : x < 2.0 ? mix(cyan, yellow, x - 1.0)
                                                  : mix(yellow, red, x - 2.0);
}
const float COST_SCALE = 60.0;  // traversal steps shown as red

// What one ray through the pixel's centre finds, for the views that are not radiance.
vec3 firstHitView(Ray ray, inout uint rays) {
    rays += 1u;
    bvhLoopIterations = 0u;
    Hit hit;
    bool found = nearestHit(ray, 0.0, FOREVER, hit);
    if (view == VIEW_COST) return heat(float(bvhLoopIterations) / COST_SCALE);
    if (!found) return vec3(0.0);
    if (view == VIEW_ALBEDO) return albedoAt(materials[hit.material], hit.uv);
    if (view == VIEW_UV) return vec3(fract(hit.uv), 0.0);
    return view == VIEW_NORMALS ? 0.5 + 0.5 * hit.normal : vec3(hit.t);
}

// One random diffuse ray from the pixel's first hit (found once, by the first
// dispatch): 1 if it travels farther than occlusionDistance, else 0. The mean is the
// ambient occlusion; the rays are the incoherent kind a path's bounces trace.
vec3 bounceView(uint index, Ray cameraRay, inout RandomState random, inout uint rays) {
    if (sampleIndex == 0u) {
        Hit hit;
        rays += 1u;
        bool found = nearestHit(cameraRay, 0.0, FOREVER, hit) && hit.front;
        bounceStarts[index] = BounceStart(vec4(hit.position, found ? 1.0 : 0.0),
                                          vec4(hit.geometricNormal, 0.0));
    }
    BounceStart start = bounceStarts[index];
    if (start.position.w == 0.0) return vec3(0.0);
    vec3 normal = start.normal.xyz;
    Ray ray = Ray(offsetFromSurface(start.position.xyz, normal),
                  cosineSampleHemisphere(normal, random2(random)));
    rays += 1u;
    // The nearest hit, however far (not just within occlusionDistance): a full ray, as
    // the benchmark wants it.
    Hit hit;
    bool blocked = nearestHit(ray, 0.0, FOREVER, hit) && hit.t < occlusionDistance;
    return vec3(blocked ? 0.0 : 1.0);
}
// --8<-- [end:views]

void main() {
    uvec2 pixel = gl_GlobalInvocationID.xy;
    if (pixel.x >= imageSize.x || pixel.y >= imageSize.y) return;  // overhanging tiles
    uint index = pixel.y * imageSize.x + pixel.x;

    // --8<-- [start:accumulate]
    // As in chapter 09: the pixel's generator continues from the previous dispatch,
    // and the image holds the running mean of the samples.
    RandomState random = randomStates[index];
    uint rays = sampleIndex == 0u ? 0u : rayCounts[index];
    vec3 radiance;
    if (view == VIEW_RADIANCE) {
        // A random point of the pixel (anti-aliasing) and of the lens (depth of field).
        vec2 inPixel = random2(random);
        Ray ray = primaryRay(pixel, imageSize, inPixel, random2(random));
        SurfaceFeatures first;
        radiance = tracePath(ray, random, rays, first);
        accumulateFeatures(index, first, radiance);
    } else {  // the other views look through the pixel's centre and the lens's
        Ray ray = primaryRay(pixel, imageSize, vec2(0.5), vec2(0.5));
        radiance = view == VIEW_BOUNCE ? bounceView(index, ray, random, rays)
                                       : firstHitView(ray, rays);
    }
    randomStates[index] = random;
    rayCounts[index] = rays;
    vec3 mean = sampleIndex == 0u ? vec3(0.0) : pixels[index].rgb;
    mean += (radiance - mean) / float(sampleIndex + 1u);
    pixels[index] = vec4(mean, 1.0);
    // --8<-- [end:accumulate]
}
