// What guides the denoiser: each path's first surface that is not a mirror or glass
// (through those, the surface they show, whose edges are its own). The means over a
// pixel's samples go to the features buffer (albedo, normal, depth, the light it emits:
// a lamp, the sky), the light it reflects and its luminance squared to the reflected one.
#include "tone_mapping.glsl"

layout(rgba32ui, binding = FEATURES_UNIT) uniform uimageBuffer featureTexels;
layout(rgba32ui, binding = REFLECTED_UNIT) uniform uimageBuffer reflectedTexels;

struct SurfaceFeatures {
    vec3 albedo;  // times the tint of the mirrors and glass on the way
    vec3 normal;  // the shading normal, in the world
    float depth;  // the path's length to it
    vec3 emitted; // the light it sends the camera itself
};

// --8<-- [start:albedo]
// The colour the denoiser divides out and puts back: a Lambertian surface's albedo, a
// rough metal's reflectance head-on (its Fresnel colour), rough glass's 1 (clear). Their
// albedo field means nothing: a zero there made the illumination 100 times too large.
vec3 surfaceAlbedo(Material material) {
    if (material.kind == MATERIAL_DIFFUSE) return material.albedo;
    if (material.kind == MATERIAL_CONDUCTOR) {
        vec3 eta = material.eta, k = material.k;
        return ((eta - 1.0) * (eta - 1.0) + k * k) / ((eta + 1.0) * (eta + 1.0) + k * k);
    }
    return vec3(1.0);
}
// --8<-- [end:albedo]

// --8<-- [start:record]
// Called at every surface the path meets until `settled`: a mirror or glass leaves it
// unsettled, so the surface behind it is recorded over it.
void recordSurface(inout SurfaceFeatures first, inout bool settled, vec3 throughput,
                   Material material, Hit hit, float travelled) {
    if (settled) return;
    first = SurfaceFeatures(throughput * surfaceAlbedo(material), hit.normal, travelled,
                            vec3(0.0));
    settled = !isDelta(material);
}
// --8<-- [end:record]

vec4 meanWith(vec4 mean, vec4 value) {
    return sampleIndex == 0u ? value : mean + (value - mean) / float(sampleIndex + 1u);
}

vec4 texelAt(bool features, int texel) {
    return uintBitsToFloat(features ? imageLoad(featureTexels, texel)
                                    : imageLoad(reflectedTexels, texel));
}

// --8<-- [start:accumulate_features]
// The running means, and the spread of the depths: their variance kept as Welford's
// running mean of (d - old mean)(d - new mean), which stays exact where E[d^2] - E[d]^2
// in floats would be rounding noise (d^2 near 16, its last bit 2e-6).
void accumulateFeatures(uint index, SurfaceFeatures first, vec3 radiance) {
    vec3 reflected = radiance - first.emitted;
    float light = luminance(reflected);
    int at = int(index);
    vec4 surface = texelAt(true, 3 * at), normalSpread = texelAt(true, 3 * at + 1);
    vec4 newSurface = meanWith(surface, vec4(first.albedo, first.depth));
    float depthVariance = sampleIndex == 0u ? 0.0 : normalSpread.w +
        ((first.depth - surface.w) * (first.depth - newSurface.w) - normalSpread.w) /
        float(sampleIndex + 1u);
    vec3 normal = meanWith(normalSpread, vec4(first.normal, 0.0)).xyz;
    imageStore(featureTexels, 3 * at, floatBitsToUint(newSurface));
    imageStore(featureTexels, 3 * at + 1, floatBitsToUint(vec4(normal, depthVariance)));
    imageStore(featureTexels, 3 * at + 2, floatBitsToUint(
        meanWith(texelAt(true, 3 * at + 2), vec4(first.emitted, 0.0))));
    imageStore(reflectedTexels, at, floatBitsToUint(
        meanWith(texelAt(false, at), vec4(reflected, light * light))));
}
// --8<-- [end:accumulate_features]
