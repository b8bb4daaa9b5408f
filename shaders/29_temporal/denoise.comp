#version 430 core
// The denoiser, one stage a dispatch (DenoiseParameters.stage): gather the illumination
// (the reflected light's mean over the albedo's) and the variance of its luminance,
// from the blend's first two moments and s; filter, one pass of a 5 x 5 kernel, taps `tapStep`
// pixels apart: the edge-avoiding a-trous wavelet filter (Dammertz et al. 2010) with SVGF's
// luminance weight (Schied et al. 2017), or a plainer one; finish: the albedo put back.
#include "shared.h"
#include "tone_mapping.glsl"

layout(local_size_x = TILE_SIZE, local_size_y = TILE_SIZE) in;
struct Features {
    vec4 albedoDepth;  // albedo (rgb), depth along the path (w)
    vec4 normal;       // the samples' mean normal (shorter at an edge); depths' variance (w)
    vec4 emitted;      // the light the surface sends the camera itself (rgb), and s:
                       // the blend's weights squared, summed (w; temporal.comp)
};
layout(std430, binding = FEATURES_BINDING) readonly buffer FeatureBuffer {
    Features features[];
};
layout(std430, binding = REFLECTED_BINDING) readonly buffer Reflected {
    vec4 reflected[];     // mean (rgb), mean of its luminance squared (w)
};
layout(std430, binding = FILTERED_BINDING) readonly buffer Filtered {
    vec4 filtered[];      // illumination (rgb), the variance of its luminance (w)
};
layout(std430, binding = FILTERED_OUT_BINDING) writeonly buffer FilteredOut {
    vec4 filteredOut[];
};
layout(std430, binding = DENOISED_BINDING) writeonly buffer Denoised { vec4 denoised[]; };

const float KERNEL[5] = float[5](1.0 / 16.0, 1.0 / 4.0, 3.0 / 8.0, 1.0 / 4.0, 1.0 / 16.0);
const float EPSILON = 1e-10;

uint indexOf(ivec2 pixel) { return uint(pixel.y) * filterSize.x + uint(pixel.x); }
bool inside(ivec2 pixel) { return all(greaterThanEqual(pixel, ivec2(0))) &&
                                  all(lessThan(pixel, ivec2(filterSize))); }
float depthAt(ivec2 pixel) { return features[indexOf(pixel)].albedoDepth.w; }
vec3 albedoAt(uint index) { return max(features[index].albedoDepth.rgb, vec3(ALBEDO_FLOOR)); }

// --8<-- [start:gather]
// The illumination: the mean reflected light over the mean albedo (each sample over its
// own albedo, then averaged, would be wrong where a pixel's samples meet two surfaces:
// the albedo put back is their mean). Its noise: the blend's weights sum to 1, their
// squares to s (1/n for n alike); one sample's variance is (E[l^2] - E[l]^2) / (1 - s),
// the mean's s times that, over the albedo's luminance squared. One sample (s = 1) says
// nothing of its noise: call it large.
const float ONE_SAMPLE = 0.999;  // s at or above: a single sample
float perSampleVariance(uint index) {
    vec4 moments = reflected[index];
    float mean = luminance(moments.rgb), s = features[index].emitted.w;
    float scale = max(luminance(albedoAt(index)), ALBEDO_FLOOR);
    return max(moments.w - mean * mean, 0.0) / (1.0 - s) / (scale * scale);
}
vec4 gathered(uint index) {
    float s = features[index].emitted.w;
    float variance = s < ONE_SAMPLE ? perSampleVariance(index) * s : 1e30;
    return vec4(reflected[index].rgb / albedoAt(index), variance);
}

// A pixel of one sample (a disocclusion, as the camera moves) borrows the noise of one
// sample from its neighbours that have more: counted as infinitely noisy, it would let
// every neighbour take its one sample whole.
float oneSampleVariance(ivec2 pixel) {
    float sum = 0.0, count = 0.0;
    for (int y = -1; y <= 1; ++y)
        for (int x = -1; x <= 1; ++x) {
            ivec2 other = pixel + ivec2(x, y);
            if (!inside(other) || features[indexOf(other)].emitted.w >= ONE_SAMPLE) continue;
            sum += perSampleVariance(indexOf(other));
            count += 1.0;
        }
    return count > 0.0 ? sum / count : 1e30;
}
// --8<-- [end:gather]

// --8<-- [start:spikes]
// A lone spike (a lucky caustic) where the features set a pixel apart (a rim) is spread by
// no tap. Its colour above a cap, its eight neighbours' mean luminance plus SPIKE_SIGMAS of
// their spread, is shared evenly with the 3 x 3 pixels around it: a faint patch, no dot.
const float SPIKE_SIGMAS = 8.0;
vec3 excessAt(ivec2 pixel, out float sharers) {
    vec3 moments = vec3(0.0);  // the neighbours' count, luminances' sum and squares' sum
    for (int y = -1; y <= 1; ++y)
        for (int x = -1; x <= 1; ++x) {
            ivec2 other = pixel + ivec2(x, y);
            if (!inside(other) || (x == 0 && y == 0)) continue;
            float light = luminance(gathered(indexOf(other)).rgb);
            moments += vec3(1.0, light, light * light);
        }
    sharers = moments.x + 1.0;  // and the pixel itself
    float mean = moments.y / moments.x;
    float cap = mean + SPIKE_SIGMAS * sqrt(max(moments.z / moments.x - mean * mean, 0.0));
    vec3 light = gathered(indexOf(pixel)).rgb;
    float over = luminance(light);
    return over > cap ? light * (1.0 - cap / over) * albedoAt(indexOf(pixel)) : vec3(0.0);
}
vec4 spikesShared(ivec2 pixel) {
    vec4 here = gathered(indexOf(pixel));
    vec3 albedo = albedoAt(indexOf(pixel));
    float sharers;
    vec3 colour = here.rgb * albedo - excessAt(pixel, sharers);
    for (int y = -1; y <= 1; ++y)
        for (int x = -1; x <= 1; ++x)
            if (inside(pixel + ivec2(x, y)))
                colour += excessAt(pixel + ivec2(x, y), sharers) / sharers;
    float variance = features[indexOf(pixel)].emitted.w >= ONE_SAMPLE
                         ? oneSampleVariance(pixel) : here.w;
    return vec4(colour / albedo, variance);
}
// --8<-- [end:spikes]

// --8<-- [start:gradient]
// How depth changes to the next pixel on the same surface, along x and y: of the
// differences to the two neighbours on an axis, the smaller (at a silhouette, the
// other is the jump); at the image's border, the one there is.
float smaller(float ahead, float behind) { return abs(ahead) < abs(behind) ? ahead : behind; }
vec2 depthGradient(ivec2 pixel) {
    float here = depthAt(pixel);
    vec2 gradient;
    for (int axis = 0; axis < 2; ++axis) {
        ivec2 offset = axis == 0 ? ivec2(1, 0) : ivec2(0, 1);
        bool hasAhead = inside(pixel + offset), hasBehind = inside(pixel - offset);
        float ahead = hasAhead ? depthAt(pixel + offset) - here : 0.0;
        float behind = hasBehind ? here - depthAt(pixel - offset) : 0.0;
        gradient[axis] = !hasAhead ? behind : !hasBehind ? ahead : smaller(ahead, behind);
    }
    return gradient;
}
// --8<-- [end:gradient]

// --8<-- [start:weights]
// How much the tap at `offset` may count, from 0 to 1:
// - depth: the tap's against the pixel's plane, in units of the plane's change over the
//   tap's distance, plus the spread of the pixel's own depths (a pixel whose samples
//   meet two surfaces lies on neither's plane, and takes taps from both);
// - normal: how well the tap's normal agrees with the pixel's mean normal, against how
//   well the pixel's own samples do (|mean|^2; 1 where they all agree), to a power;
// - luminance (the a-trous filter): the tap's against the pixel's, in units of the
//   noise of their difference, both pixels' together: the same weight from either side,
//   so a pixel lifted by one lucky sample spreads its light rather than losing it.
float edgeWeight(ivec2 pixel, ivec2 offset, vec2 gradient, vec4 normalSpread, float light,
                 float lightVariance, vec4 tap) {
    ivec2 other = pixel + offset;
    float offPlane = abs(depthAt(other) - depthAt(pixel) - dot(gradient, vec2(offset)));
    float scale = depthSigma * (length(gradient) * length(vec2(offset)) + sqrt(normalSpread.w));
    float weight = exp(-offPlane / (scale + EPSILON));
    vec3 mean = normalSpread.xyz, otherNormal = features[indexOf(other)].normal.xyz;
    float agreement = dot(mean, otherNormal) /
                      max(dot(mean, mean) * length(otherNormal), EPSILON);
    weight *= pow(clamp(agreement, 0.0, 1.0), normalPower);
    float lightApart = abs(light - luminance(tap.rgb));
    float noise = sqrt(lightVariance + tap.w);
    if (filterKind == FILTER_ATROUS)
        weight *= exp(-lightApart / (luminanceSigma * noise + EPSILON));
    return weight;
}
// --8<-- [end:weights]

// The luminance and variance the taps meet: 3 x 3 Gaussians (one pixel's own are noisy).
vec2 lightAndVarianceAround(ivec2 pixel) {
    vec3 sum = vec3(0.0);  // the weights', the luminances' and the variances' sums
    for (int y = -1; y <= 1; ++y)
        for (int x = -1; x <= 1; ++x) {
            ivec2 other = pixel + ivec2(x, y);
            if (!inside(other)) continue;
            vec4 tap = filtered[indexOf(other)];
            sum += (x == 0 ? 0.5 : 0.25) * (y == 0 ? 0.5 : 0.25) *
                   vec3(1.0, luminance(tap.rgb), tap.w);
        }
    return sum.yz / sum.x;
}

// --8<-- [start:pass]
// One pass: sum w illumination / sum w over the taps, and the variance through the
// weights squared (a weighted mean's), so the next pass knows how much noise is left.
vec4 filterPass(ivec2 pixel) {
    uint index = indexOf(pixel);
    vec2 gradient = depthGradient(pixel);
    vec4 normalSpread = features[index].normal;
    vec2 around = filterKind == FILTER_ATROUS ? lightAndVarianceAround(pixel) : vec2(0.0);
    vec3 sum = vec3(0.0);
    float variance = 0.0, weights = 0.0;
    for (int y = -2; y <= 2; ++y)
        for (int x = -2; x <= 2; ++x) {
            ivec2 offset = ivec2(x, y) * int(tapStep);
            if (!inside(pixel + offset)) continue;
            vec4 tap = filtered[indexOf(pixel + offset)];
            float w = filterKind == FILTER_BOX ? 1.0 : KERNEL[x + 2] * KERNEL[y + 2];
            if (filterKind >= FILTER_FEATURES && offset != ivec2(0))  // itself: alike
                w *= edgeWeight(pixel, offset, gradient, normalSpread, around.x, around.y, tap);
            sum += w * tap.rgb;
            variance += w * w * tap.w;
            weights += w;
        }
    return vec4(sum / weights, variance / (weights * weights));
}
// --8<-- [end:pass]

// --8<-- [start:emitted]
// The light the camera sees directly is exact where a pixel's samples agree. At an
// emitter's rim (a lamp the lens blurs) a pixel sees it with a chance share f of its n
// samples: f L, L the brightest light within EMITTED_REACH, with a coverage's variance
// f (1 - f) L^2 / n, if darkness is near (a sky is no rim). Such a pixel takes a mean of
// the pixels around, Gaussian (sigma EMITTED_REACH / 2) and by the luminance weight.
const int EMITTED_REACH = 3;
vec3 emittedAt(ivec2 pixel) { return features[indexOf(pixel)].emitted.rgb; }
float coverageVariance(ivec2 pixel, float brightest) {
    float light = luminance(emittedAt(pixel));
    return max(light * (brightest - light), 0.0) * features[indexOf(pixel)].emitted.w;  // s
}
vec3 emittedFiltered(ivec2 pixel) {
    float light = luminance(emittedAt(pixel)), darkest = light, brightest = light;
    for (int y = -EMITTED_REACH; y <= EMITTED_REACH && light > 0.0; ++y)  // none: no rim
        for (int x = -EMITTED_REACH; x <= EMITTED_REACH; ++x) {
            if (!inside(pixel + ivec2(x, y))) continue;
            float tap = luminance(emittedAt(pixel + ivec2(x, y)));
            darkest = min(darkest, tap);
            brightest = max(brightest, tap);
        }
    float variance = coverageVariance(pixel, brightest), weights = 0.0;
    if (variance <= 0.0 || darkest > 0.0) return emittedAt(pixel);  // not on a rim
    vec3 sum = vec3(0.0);
    for (int y = -EMITTED_REACH; y <= EMITTED_REACH; ++y)
        for (int x = -EMITTED_REACH; x <= EMITTED_REACH; ++x) {
            ivec2 tap = pixel + ivec2(x, y);
            if (!inside(tap)) continue;
            float noise = sqrt(variance + coverageVariance(tap, brightest));
            float w = exp(-2.0 * float(x * x + y * y) / float(EMITTED_REACH * EMITTED_REACH) -
                          abs(light - luminance(emittedAt(tap))) / (noise + EPSILON));
            sum += w * emittedAt(tap);
            weights += w;
        }
    return sum / weights;
}
// --8<-- [end:emitted]

void main() {
    ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
    if (!inside(pixel)) return;
    uint index = indexOf(pixel);
    if (stage == STAGE_GATHER) {
        filteredOut[index] = spikesShared(pixel);
    } else if (stage == STAGE_FILTER) {
        filteredOut[index] = filterPass(pixel);
    } else {  // STAGE_FINISH: the albedo back, and emitted light (filtered at a rim)
        denoised[index] = vec4(filtered[index].rgb * albedoAt(index) +
                               emittedFiltered(pixel), 1.0);
    }
}
