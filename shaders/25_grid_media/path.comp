#version 430 core
// Chapter 25: media whose density varies. Chapter 24's path tracer, whose media may
// now be grids of densities (grid.glsl): a cloud, a plume of smoke. Their free flights
// are drawn by delta tracking and their shadow rays' transmittance estimated by ratio
// tracking; homogeneous media keep chapter 24's closed forms. A medium fills the
// inside of the shapes that name it as their interior, or all space around the
// camera. Each dispatch adds one sample to every pixel.
#include "shared.h"
#include "random.glsl"
#include "camera.glsl"
#include "scene.glsl"
#include "sampling.glsl"
#include "environment.glsl"
const float FOREVER = 3.0e38;
#include "media.glsl"
#include "grid.glsl"
#include "microfacet.glsl"
#include "dielectric.glsl"
#include "bsdf.glsl"

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

// --8<-- [start:offset]
// A point just off the surface, on the side `normal` points to: float32 rounds a hit
// point to within a few units in the last place of its coordinates, so the gap grows
// with their size.
vec3 offsetFromSurface(vec3 position, vec3 normal) {
    vec3 size = abs(position);
    return position + RAY_OFFSET * (1.0 + max(size.x, max(size.y, size.z))) * normal;
}
// --8<-- [end:offset]

// --8<-- [start:boundaries]
// The medium beyond a surface, on the side a ray leaves it by: a surface light passes
// through (a boundary, glass) has the shape's interior behind it and the camera's
// medium in front; no ray passes an opaque one, so the medium stays `current`.
uint mediumOnSide(Hit hit, Material material, bool front, uint current) {
    if (material.kind != MATERIAL_BOUNDARY && material.kind != MATERIAL_DIELECTRIC)
        return current;
    return front ? cameraMedium : hit.interior;
}

// The light a shadow ray keeps over `distance`, starting in `medium`: Beer-Lambert or
// ratio tracking through each medium on the way, on through the invisible boundaries
// between them.
// Any other surface blocks it: glass too (its refraction would bend the ray away from
// the light), as in Mitsuba's volumetric path tracer.
vec3 shadowTransmittance(Ray ray, float distance, uint medium, inout RandomState random,
                         inout uint rays) {
    if (mediumCount == 0u) {  // no media: chapter 18's shadow ray
        rays += 1u;
        return anyHit(ray, 0.0, distance) ? vec3(0.0) : vec3(1.0);
    }
    vec3 kept = vec3(1.0);
    // Where the ray stops (short of the light): each crossing moves the origin off the
    // line a little, so the distance left is measured to this point again.
    bool forever = distance >= FOREVER;
    vec3 end = ray.origin + distance * ray.direction;
    for (int crossing = 0; crossing <= MAX_BOUNDARY_CROSSINGS; ++crossing) {
        Hit hit;
        rays += 1u;
        bool blocked = nearestHit(ray, 0.0, distance, hit);
        if (medium != NO_MEDIUM)
            kept *= transmittanceAlong(media[medium], ray, blocked ? hit.t : distance,
                                       random);
        if (!blocked) return kept;
        if (materials[hit.material].kind != MATERIAL_BOUNDARY) return vec3(0.0);
        medium = hit.front ? hit.interior : cameraMedium;
        ray.origin = offsetFromSurface(hit.position,
                                       hit.front ? -hit.geometricNormal : hit.geometricNormal);
        distance = forever ? FOREVER : dot(end - ray.origin, ray.direction);
        if (distance <= 0.0) return kept;
    }
    return vec3(0.0);  // more boundaries than a shadow ray crosses
}
// --8<-- [end:boundaries]

// --8<-- [start:nee]
// A light for next-event estimation: the environment (with environmentChance) or a
// point on one emitting shape, picked as chapter 18 picks them.
struct LightChoice {
    bool environment;
    vec3 direction;    // the environment: where it was sampled
    float pdf;         // the environment: the density per steradian, the choice included
    uint emitter;      // a shape: which one, and the point on it
    LightPoint point;
};

LightChoice chooseLight(inout RandomState random) {
    LightChoice light;
    light.environment = random01(random) < environmentChance;
    if (light.environment) {
        vec3 radiance;
        light.direction = sampleEnvironment(random2(random), light.pdf, radiance);
        light.pdf *= environmentChance;
        light.point.emission = radiance;
    } else {
        uint emitterCount = uint(emitters.length());
        light.emitter = min(uint(random01(random) * float(emitterCount)), emitterCount - 1u);
        light.point = sampleEmitter(emitters[light.emitter], random2(random));
    }
    return light;
}

// Seen from `origin`: the direction to the light, how far a shadow ray must go (short
// of the light by the gap that keeps it from finding the light itself), and the
// density per steradian. False: nothing to gain (the light faces away).
bool aimAt(LightChoice light, vec3 origin, out vec3 direction, out float distance,
           out float pdf) {
    if (light.environment) {
        direction = light.direction;
        distance = FOREVER;
        pdf = light.pdf;
        return pdf > 0.0;
    }
    vec3 toLight = light.point.position - origin;
    float reach = length(toLight);
    direction = toLight / reach;
    float cosLight = -dot(light.point.normal, direction);
    float stop = length(offsetFromSurface(light.point.position, light.point.normal) -
                        light.point.position);
    distance = reach - stop;
    pdf = cosLight > 0.0 ? lightPdf(light.emitter, reach, cosLight) : 0.0;
    return pdf > 0.0;
}

// Next-event estimation at a surface: the light arriving from one chosen light, if
// the shadow ray gets through (with what the media on the way keep of it), reflected
// towards the viewer by the BSDF, over the density of the choice, weighted by MIS.
vec3 lightAtSurface(Hit hit, Material material, mat3 frame, vec3 toViewer, uint medium,
                    inout RandomState random, inout uint rays) {
    LightChoice light = chooseLight(random);
    // The shadow ray leaves from the light's side of the surface: through glass, the
    // back. (The BSDF says whether anything gets there: nothing, for an opaque one.)
    vec3 towards = light.environment ? light.direction : light.point.position - hit.position;
    bool front = dot(towards, hit.geometricNormal) > 0.0;
    vec3 origin = offsetFromSurface(hit.position,
                                    front ? hit.geometricNormal : -hit.geometricNormal);
    vec3 direction;
    float distance, pdf;
    if (!aimAt(light, origin, direction, distance, pdf)) return vec3(0.0);
    // The flat and the smooth normal must put the light on the same side.
    if (dot(hit.normal, direction) * dot(hit.geometricNormal, direction) <= 0.0)
        return vec3(0.0);
    vec3 reflected = bsdfEval(material, frame, toViewer, direction);  // f cos
    if (reflected == vec3(0.0)) return vec3(0.0);  // no shadow ray for nothing
    uint beyond = mediumOnSide(hit, material, front, medium);
    vec3 kept = shadowTransmittance(Ray(origin, direction), distance, beyond, random, rays);
    if (kept == vec3(0.0)) return vec3(0.0);
    float weight = estimator == ESTIMATOR_MIS
                       ? powerHeuristic(pdf, bsdfPdf(material, frame, toViewer, direction))
                       : 1.0;
    return light.point.emission * kept * reflected / pdf * weight;
}

// The same at a point in a medium, where the phase function takes the BSDF's place
// (and there is no side to leave from): its value is also its sampling density.
vec3 lightInMedium(vec3 position, vec3 travelling, Medium here, uint medium,
                   inout RandomState random, inout uint rays) {
    LightChoice light = chooseLight(random);
    vec3 direction;
    float distance, pdf;
    if (!aimAt(light, position, direction, distance, pdf)) return vec3(0.0);
    float phase = henyeyGreenstein(dot(travelling, direction), here.g);
    vec3 kept = shadowTransmittance(Ray(position, direction), distance, medium, random,
                                    rays);
    if (kept == vec3(0.0)) return vec3(0.0);
    float weight = estimator == ESTIMATOR_MIS ? powerHeuristic(pdf, phase) : 1.0;
    return light.point.emission * kept * phase / pdf * weight;
}
// --8<-- [end:nee]

// --8<-- [start:path]
// Russian roulette: after a few bounces, a path carrying little light ends with
// probability 1 - survival; the survivors carry 1 / survival more (unbiased).
bool survivesRoulette(int bounces, inout vec3 throughput, inout RandomState random) {
    if (bounces < ROULETTE_AFTER) return true;
    float survival = min(max(throughput.r, max(throughput.g, throughput.b)), 0.95);
    if (random01(random) >= survival) return false;
    throughput /= survival;
    return true;
}

// One path's estimate of the radiance arriving along `ray`: a loop, not recursion
// (GLSL has none), carrying the `throughput`. A bounce is a scattering, at a surface
// or in a medium; crossing a medium's boundary is none.
vec3 tracePath(Ray ray, inout RandomState random, inout uint rays) {
    vec3 radiance = vec3(0.0);
    vec3 throughput = vec3(1.0);
    float directionPdf = 0.0;  // the density with which the last scattering chose `ray`
    bool afterDelta = false;   // chosen by a delta BSDF: no NEE could find that light
    uint medium = cameraMedium;  // what the ray travels through now
    float sinceScatter = 0.0;  // metres from the last scattering, across boundaries
    int crossings = 0;         // boundaries passed: bounded, as every loop here
    for (int bounce = 0;;) {
        Hit hit;
        rays += 1u;
        bool found = nearestHit(ray, 0.0, FOREVER, hit);

        // 0. A medium on the way may scatter the ray before the surface: then the
        //    scattering point is lit (NEE with the phase function), and the phase
        //    function picks the next direction.
        if (medium != NO_MEDIUM) {
            Medium here = media[medium];
            FreeFlight flight = flyThrough(here, ray, found ? hit.t : FOREVER, random);
            throughput *= flight.weight;
            if (flight.scattered) {
                if (bounce == maxBounces) break;
                vec3 position = ray.origin + flight.distance * ray.direction;
                if (estimator != ESTIMATOR_BSDF)
                    radiance += throughput *
                                lightInMedium(position, ray.direction, here, medium, random, rays);
                vec3 next = sampleHenyeyGreenstein(ray.direction, here.g, random2(random));
                directionPdf = henyeyGreenstein(dot(ray.direction, next), here.g);
                afterDelta = false;
                sinceScatter = 0.0;
                if (!survivesRoulette(++bounce, throughput, random)) break;
                ray = Ray(position, next);
                continue;
            }
            if (throughput == vec3(0.0)) break;  // absorbed (or out into endless fog)
        }
        if (!found) {
            // Out of the scene: the environment's light, counted as an emitter's is.
            if (hasEnvironment()) {
                float weight = 1.0;
                bool sampledOnly = bounce == 0 || afterDelta;
                if (!sampledOnly && estimator == ESTIMATOR_NEE) weight = 0.0;
                if (!sampledOnly && estimator == ESTIMATOR_MIS)
                    weight = powerHeuristic(directionPdf,
                                            environmentChance * environmentPdf(ray.direction));
                radiance += throughput * environmentRadiance(ray.direction) * weight;
            }
            break;
        }
        Material material = materials[hit.material];
        // A medium's boundary is no surface: the ray goes straight on, into the medium
        // behind it (or back out), and no bounce is counted.
        if (material.kind == MATERIAL_BOUNDARY) {
            if (++crossings > MAX_BOUNDARY_CROSSINGS * (maxBounces + 1)) break;
            medium = hit.front ? hit.interior : cameraMedium;
            sinceScatter += hit.t;
            ray.origin = offsetFromSurface(hit.position, hit.front ? -hit.geometricNormal
                                                                    : hit.geometricNormal);
            continue;
        }
        material.albedo = albedoAt(material, hit.uv);  // a texture's, where it has one

        // 1. Light the ray runs into. The camera sees it in full, and so does a mirror;
        //    after another bounce, NEE has counted it already (weight 0) or shares it.
        if (hit.front && hit.emitter != NO_EMITTER) {
            float weight = 1.0;
            bool sampledOnly = bounce == 0 || afterDelta;
            if (!sampledOnly && estimator == ESTIMATOR_NEE) weight = 0.0;
            if (!sampledOnly && estimator == ESTIMATOR_MIS) {
                float cosLight = -dot(hit.geometricNormal, ray.direction);
                weight = powerHeuristic(directionPdf,
                                        lightPdf(hit.emitter, sinceScatter + hit.t, cosLight));
            }
            radiance += throughput * material.emission * weight;
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
                        lightAtSurface(hit, material, frame, toViewer, medium, random, rays);

        // 3. The next direction, sampled by the material: the throughput picks up
        //    eval / pdf (the albedo for a Lambertian surface, F for a mirror).
        vec3 u = vec3(random2(random), random01(random));
        BsdfSample next = bsdfSample(material, frame, toViewer, u);
        if (next.weight == vec3(0.0)) break;  // a failed sample
        // The side it leaves on, by the flat normal; the smooth one must agree.
        bool front = dot(next.wo, hit.geometricNormal) > 0.0;
        if (dot(next.wo, hit.normal) * dot(next.wo, hit.geometricNormal) <= 0.0) break;
        directionPdf = next.pdf;
        throughput *= next.weight;
        medium = mediumOnSide(hit, material, front, medium);  // through glass: inside
        sinceScatter = 0.0;

        // 4. Russian roulette, then on from just off the surface.
        if (!survivesRoulette(++bounce, throughput, random)) break;
        ray = Ray(offsetFromSurface(hit.position, front ? hit.geometricNormal
                                                        : -hit.geometricNormal), next.wo);
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
        radiance = tracePath(ray, random, rays);
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
