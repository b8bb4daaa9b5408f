#version 430 core
// Chapter 30: chapter 23's megakernel, which now says when the GL cut its loops short.
// One invocation runs a pixel's paths: the steps of path_steps.glsl in a loop, the
// shadow ray traced where next-event estimation makes it, and a new path as soon as one
// ends (path regeneration). Each dispatch adds samplesThisDispatch samples to every
// pixel (one for a view); the image holds the running mean. A GL that stops a group of
// lanes after so many loop iterations (Mesa 22's llvmpipe) leaves a mark: the last loop
// (loopsCutShort) runs short, and the invocation counts itself in cutShortInvocations.
// The host then puts the buffers back and runs the dispatch again with fewer samples
// (checked_dispatch.h).
// --view shows what the camera rays hit (normals, distance, albedo, texture
// coordinates), how hard the tree worked for them, or random bounce rays.
#include "path_tracer.glsl"

layout(local_size_x = TILE_SIZE, local_size_y = TILE_SIZE) in;
layout(std430, binding = PIXELS_BINDING) buffer Pixels { vec4 pixels[]; };
layout(std430, binding = RANDOM_BINDING) buffer Random { RandomState randomStates[]; };
layout(std430, binding = RAY_COUNT_BINDING) buffer RayCounts { uint rayCounts[]; };
layout(binding = CUT_SHORT_BINDING, offset = 0) uniform atomic_uint cutShortInvocations;

// imageSize, sampleIndex, maxBounces (--depth), estimator and the camera come in the
// PathParameters uniform block (shared.h), and so do view and occlusionDistance, and
// samplesThisDispatch, the samples this dispatch adds to each pixel.

// VIEW_BOUNCE: where each pixel's camera ray hit (w = 1) or that it hit nothing (w = 0),
// found by the first dispatch; every dispatch then traces one random ray from there.
struct BounceStart {
    vec4 position;
    vec4 normal;
};
layout(std430, binding = BOUNCE_START_BINDING) buffer BounceStarts {
    BounceStart bounceStarts[];
};

// --8<-- [start:path]
// A random point of the pixel (anti-aliasing) and of the lens (depth of field).
Ray cameraRay(uvec2 pixel, inout RandomState random) {
    vec2 inPixel = random2(random);
    return primaryRay(pixel, imageSize, inPixel, random2(random));
}

// The megakernel: samplesThisDispatch samples of the pixel, added to its running mean
// in one loop. Each turn traces the path's ray, then shades what it hit (path_steps.glsl)
// and traces next-event estimation's shadow ray. A path that ends makes way at once for
// the pixel's next sample (path regeneration), so a lane waits for its group's longest
// path only at the end of the dispatch, not at the end of every sample. The random
// numbers and the sums come in the order of one sample a dispatch: the same picture.
vec3 addSamples(uvec2 pixel, vec3 mean, inout RandomState random, inout uint rays) {
    uint done = 0u;
    PathState path = startPath(cameraRay(pixel, random));
    for (;;) {
        Hit hit;
        bool goesOn = false;
        rays += 1u;
        if (!nearestHit(path.ray, 0.0, FOREVER, hit)) {
            leaveScene(path);
        } else {
            ShadowRay shadow;
            goesOn = shadeHit(path, hit, random, shadow);
            path.radiance += shadowRayLight(shadow, rays);
        }
        if (goesOn) continue;
        done += 1u;  // as chapter 09: the running mean, one sample at a time
        mean += (path.radiance - mean) / float(sampleIndex + done);
        if (done == samplesThisDispatch) return mean;
        path = startPath(cameraRay(pixel, random));  // the next sample, in this lane
    }
}
// --8<-- [end:path]

// --8<-- [start:cut_short]
// Did the GL cut this invocation's loops short? Mesa 22's llvmpipe counts the turns of
// every loop that a group of lanes runs, silently ends the loop that reaches 65535, and
// from then on lets each loop the group starts run once. So a last loop of loopCanary
// (2) turns, a number that the compiler cannot see and unroll, runs both only if no
// loop before it was cut short. (A group with exactly one turn left is reported too:
// the dispatch runs again, which costs time, never a wrong picture.)
bool loopsCutShort() {
    uint turns = 0u;
    for (uint i = 0u; i < loopCanary; ++i) turns += 1u;
    return turns != loopCanary;
}
// --8<-- [end:cut_short]

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
    if (view == VIEW_ALBEDO) return albedoAt(materialAt(hit.material), hit.uv);
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
    vec3 mean = sampleIndex == 0u ? vec3(0.0) : pixels[index].rgb;
    if (view == VIEW_RADIANCE) {
        mean = addSamples(pixel, mean, random, rays);
    } else {  // the other views look through the pixel's centre and the lens's, once
        Ray ray = primaryRay(pixel, imageSize, vec2(0.5), vec2(0.5));
        vec3 value = view == VIEW_BOUNCE ? bounceView(index, ray, random, rays)
                                         : firstHitView(ray, rays);
        mean += (value - mean) / float(sampleIndex + 1u);
    }
    randomStates[index] = random;
    rayCounts[index] = rays;
    pixels[index] = vec4(mean, 1.0);
    // --8<-- [end:accumulate]
    // --8<-- [start:report]
    // What the invocation wrote is wrong if its loops were cut: the host, told, puts
    // back the buffers as they were before the dispatch.
    if (loopsCutShort()) atomicCounterIncrement(cutShortInvocations);
    // --8<-- [end:report]
}
