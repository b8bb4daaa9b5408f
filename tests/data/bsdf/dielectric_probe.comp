#version 430
// Runs a chapter's dielectric.glsl (chapter 16 on) for a list of queries, so that
// tests/python/chapters/test_16_glass.py can compare every answer with
// python_prototypes/microfacet.py. Loaded by tests/cpp/bsdf_probe.cpp as
// bsdf_probe.comp is: the same query and answer sizes, other meanings.
const float PI = 3.14159265358979;
#include "microfacet.glsl"
#include "dielectric.glsl"

layout(local_size_x = 64) in;

// One query: the direction to the viewer wi (either side), the roughness, the index of
// refraction, three random numbers, and a second direction `given` (a wo for eval and
// pdf). All in the shading frame.
struct Query {
    vec4 wiAlpha;  // xyz: wi, w: alpha
    vec4 eta;      // x: the index inside
    vec4 unused;
    vec4 u;        // xyz: the random numbers (xy the normal, z the lobe)
    vec4 given;    // xyz
};
struct Answer {
    vec4 sampled;    // xyz: roughDielectricSample's wo, w: its pdf
    vec4 weight;     // x: its weight, y: smoothDielectricSample's weight
    vec4 evalGiven;  // x: roughDielectricEval(wi, given), y: roughDielectricPdf
    vec4 fresnel;    // fresnelDielectric(wi.z, eta): reflectance, cosT, etaIT, etaTI
    vec4 smoothWo;    // xyz: smoothDielectricSample's wo
    vec4 halfVector;  // xyz: generalizedHalfVector(wi, given, eta)
};
layout(std430, binding = 0) readonly buffer Queries { Query queries[]; };
layout(std430, binding = 1) writeonly buffer Answers { Answer answers[]; };

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= uint(queries.length())) return;
    Query q = queries[i];
    vec3 wi = q.wiAlpha.xyz, given = q.given.xyz;
    float alpha = q.wiAlpha.w, eta = q.eta.x;
    BsdfSample rough = roughDielectricSample(wi, alpha, eta, q.u.xyz);
    BsdfSample smoothSample = smoothDielectricSample(wi, eta, q.u.z);
    Fresnel f = fresnelDielectric(wi.z, eta);
    Answer a;
    a.sampled = vec4(rough.wo, rough.pdf);
    a.weight = vec4(rough.weight.x, smoothSample.weight.x, 0.0, 0.0);
    a.evalGiven = vec4(roughDielectricEval(wi, given, alpha, eta),
                       roughDielectricPdf(wi, given, alpha, eta), 0.0, 0.0);
    a.fresnel = vec4(f.reflectance, f.cosT, f.etaIT, f.etaTI);
    a.smoothWo = vec4(smoothSample.wo, 0.0);
    a.halfVector = vec4(generalizedHalfVector(wi, given, eta), 0.0);
    answers[i] = a;
}
