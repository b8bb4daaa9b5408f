#version 430
// Runs chapter 24's media.glsl for a list of queries, so that
// tests/python/chapters/test_24_participating_media.py can compare its phase function
// with python_prototypes/media.py and test its sampling by chi-square, and check its
// free-flight sampling's weight against the closed form. Loaded by
// tests/cpp/bsdf_probe.cpp as bsdf_probe.comp is: the same query and answer sizes
// (20 and 24 floats), other meanings.
#include "shared.h"
const float PI = 3.14159265358979;
const float FOREVER = 3.0e38;
// sampling.glsl's basis, without the scene's buffers that file also declares.
mat3 basisAround(vec3 n) {
    float s = n.z >= 0.0 ? 1.0 : -1.0;
    float a = -1.0 / (s + n.z);
    float b = n.x * n.y * a;
    return mat3(vec3(1.0 + s * n.x * n.x * a, s * b, -s * n.x),
                vec3(b, s + n.y * n.y * a, -n.y), n);
}
#include "media.glsl"

layout(local_size_x = 64) in;

// One query: the direction light travels, g, two random numbers, a direction `given`
// to evaluate the phase function at; a medium (sigma_a, sigma_s) with the distance to
// a surface and two more random numbers for a free flight.
struct Query {
    vec4 travelG;      // xyz: the direction of travel, w: g
    vec4 u;            // xy: the phase function's random numbers, zw: the free flight's
    vec4 given;        // xyz
    vec4 sigmaA;       // xyz; w: the distance to the surface
    vec4 sigmaS;       // xyz
};
struct Answer {
    vec4 sampled;      // xyz: sampleHenyeyGreenstein's direction, w: the phase there
    vec4 givenPhase;   // x: henyeyGreenstein(dot(travel, given), g)
    vec4 flight;       // x: scattered (1) or not (0), y: the distance
    vec4 weight;       // xyz: the free flight's weight
    vec4 transmittance;  // xyz: transmittanceThrough(medium, the surface's distance)
    vec4 unused;
};
layout(std430, binding = 0) readonly buffer Queries { Query queries[]; };
layout(std430, binding = 1) writeonly buffer Answers { Answer answers[]; };

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= uint(queries.length())) return;
    Query q = queries[i];
    vec3 travel = q.travelG.xyz;
    float g = q.travelG.w;
    vec3 sampled = sampleHenyeyGreenstein(travel, g, q.u.xy);
    Medium medium = Medium(q.sigmaA.xyz, g, q.sigmaS.xyz, 0.0);
    FreeFlight flight = sampleFreeFlight(medium, q.sigmaA.w, q.u.zw);
    answers[i] = Answer(vec4(sampled, henyeyGreenstein(dot(travel, sampled), g)),
                        vec4(henyeyGreenstein(dot(travel, q.given.xyz), g), 0.0, 0.0, 0.0),
                        vec4(flight.scattered ? 1.0 : 0.0, flight.distance, 0.0, 0.0),
                        vec4(flight.weight, 0.0),
                        vec4(transmittanceThrough(medium, q.sigmaA.w), 0.0), vec4(0.0));
}
