#version 430
// Runs a chapter's environment light (environment.glsl, chapter 18 on) for a list of
// queries, so that tests/python/chapters/test_18_environment_sampling.py can compare it with
// python_prototypes/environment_sampling.py: for each query, the direction and pdf
// sampleEnvironment draws from two uniform numbers, and environmentPdf and
// environmentRadiance along a given direction. Run by tests/cpp/bsdf_probe.cpp (20
// floats a query, 24 an answer) with the chapter's shader folder as the base, so the
// includes below resolve there, and with the map's buffers bound as the chapter binds
// them: --buffer TEXELS_BINDING (14) the radiance, one vec4 a pixel, and --buffer
// ENVIRONMENT_CDF_BINDING (16) the tables (environment.cpp's layout).
#include "shared.h"

// environment.glsl reads the map's size, place and turn from globals named as members
// of the PathParameters block (shared.h, declared above). Here the names stand for
// variables set from each query instead.
#define environmentWidth probeWidth
#define environmentHeight probeHeight
#define environmentFirstTexel probeFirstTexel
#define environmentRotation probeRotation
uint environmentWidth, environmentHeight, environmentFirstTexel;
float environmentRotation;

const float PI = 3.14159265358979;  // as sampling.glsl has it, without its buffers
#include "textures.glsl"
#include "environment.glsl"

layout(local_size_x = 64) in;

struct Query {
    vec4 u;          // xy: the two uniform numbers sampleEnvironment takes
    vec4 direction;  // xyz: a unit direction for environmentPdf and environmentRadiance
    vec4 map;        // x: width, y: height, z: the first texel, w: the turn (radians)
    vec4 unused[2];
};
struct Answer {
    vec4 sampled;       // xyz: sampleEnvironment's direction, w: the pdf it gave
    vec4 atDirection;   // xyz: environmentRadiance(direction), w: environmentPdf(direction)
    vec4 atSampled;     // the same two at the sampled direction
    vec4 unused[3];
};
layout(std430, binding = 0) readonly buffer Queries { Query queries[]; };
layout(std430, binding = 1) writeonly buffer Answers { Answer answers[]; };

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= uint(queries.length())) return;
    Query q = queries[i];
    environmentWidth = uint(q.map.x);
    environmentHeight = uint(q.map.y);
    environmentFirstTexel = uint(q.map.z);
    environmentRotation = q.map.w;
    float pdf;
    vec3 radiance;  // the chosen pixel's: unused[0] below
    vec3 sampled = sampleEnvironment(q.u.xy, pdf, radiance);
    Answer a;
    a.sampled = vec4(sampled, pdf);
    a.atDirection = vec4(environmentRadiance(q.direction.xyz),
                         environmentPdf(q.direction.xyz));
    a.atSampled = vec4(environmentRadiance(sampled), environmentPdf(sampled));
    a.unused[1] = a.unused[2] = vec4(0.0);
    a.unused[0] = vec4(radiance, 0.0);
    answers[i] = a;
}
