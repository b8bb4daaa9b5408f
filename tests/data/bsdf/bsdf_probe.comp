#version 430
// Runs a chapter's microfacet.glsl (chapter 15 on) for a list of queries, so that
// tests/python/chapters/test_15_metals.py can compare every answer with
// python_prototypes/microfacet.py. Loaded by tests/cpp/bsdf_probe.cpp with the
// chapter's shader folder as the base, so the include below resolves there.
const float PI = 3.14159265358979;
#include "microfacet.glsl"

layout(local_size_x = 64) in;

// One query: the direction to the viewer wi, the roughness, the metal's complex index,
// two random numbers, and a second direction `given` (a wo for eval and pdf, or a
// microfacet normal for D and G1). All in the shading frame.
struct Query {
    vec4 wiAlpha;  // xyz: wi, w: alpha
    vec4 eta;      // xyz
    vec4 k;        // xyz
    vec4 u;        // xy: the random numbers
    vec4 given;    // xyz
};
struct Answer {
    vec4 sampled;      // xyz: roughConductorSample's wo, w: its pdf
    vec4 weight;       // xyz: its weight
    vec4 evalGiven;    // xyz: roughConductorEval(wi, given), w: roughConductorPdf
    vec4 fresnel;      // xyz: fresnelConductor(wi.z, eta, k), w: ggxD(given)
    vec4 masking;      // x: ggxG1(wi, given), y: visibleNormalPdf(wi, given)
    vec4 normal;       // xyz: sampleVisibleNormal(wi, alpha, u)
};
layout(std430, binding = 0) readonly buffer Queries { Query queries[]; };
layout(std430, binding = 1) writeonly buffer Answers { Answer answers[]; };

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= uint(queries.length())) return;
    Query q = queries[i];
    vec3 wi = q.wiAlpha.xyz, given = q.given.xyz;
    float alpha = q.wiAlpha.w;
    BsdfSample s = roughConductorSample(wi, alpha, q.eta.xyz, q.k.xyz, q.u.xy);
    Answer a;
    a.sampled = vec4(s.wo, s.pdf);
    a.weight = vec4(s.weight, 0.0);
    a.evalGiven = vec4(roughConductorEval(wi, given, alpha, q.eta.xyz, q.k.xyz),
                       roughConductorPdf(wi, given, alpha));
    a.fresnel = vec4(fresnelConductor(wi.z, q.eta.xyz, q.k.xyz), ggxD(given, alpha));
    a.masking = vec4(ggxG1(wi, given, alpha), visibleNormalPdf(wi, given, alpha), 0.0, 0.0);
    a.normal = vec4(sampleVisibleNormal(wi, alpha, q.u.xy), 0.0);
    answers[i] = a;
}
