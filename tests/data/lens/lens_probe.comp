#version 430
// Runs a chapter's primaryRay (camera.glsl, chapter 17 on) for a list of queries, so
// that tests/python/chapters/test_17_lens_textures.py can compare every ray with
// python_prototypes/thin_lens.py and look at where the rays leave the lens. Run by
// tests/cpp/bsdf_probe.cpp (20 floats a query, 24 an answer) with the chapter's shader
// folder as the base, so the includes below resolve there.
#include "shared.h"

// camera.glsl reads the camera from a global named `camera`: in the chapter, a member
// of the PathParameters block (shared.h, declared above). Here the name stands for a
// variable set from each query instead. Its basis is the world's: forward -z, right
// +x, up +y.
#define camera probeCamera
ThinLensCamera camera;
#include "camera.glsl"

layout(local_size_x = 64) in;

struct Query {
    vec4 pixelAndSize;  // xy: the pixel, zw: the image's width and height
    vec4 randoms;       // xy: pointInPixel, zw: pointOnLens
    vec4 lens;          // x: focal length, y: sensor width, z: lens radius, w: focus
    vec4 eye;           // xyz
    vec4 unused;
};
struct Answer {
    vec4 origin;     // xyz
    vec4 direction;  // xyz
    vec4 unused[4];
};
layout(std430, binding = 0) readonly buffer Queries { Query queries[]; };
layout(std430, binding = 1) writeonly buffer Answers { Answer answers[]; };

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= uint(queries.length())) return;
    Query q = queries[i];
    camera = ThinLensCamera(q.eye.xyz, q.lens.x, vec3(0.0, 0.0, -1.0), q.lens.y,
                            vec3(1.0, 0.0, 0.0), q.lens.z, vec3(0.0, 1.0, 0.0), q.lens.w);
    Ray ray = primaryRay(uvec2(q.pixelAndSize.xy), uvec2(q.pixelAndSize.zw), q.randoms.xy,
                         q.randoms.zw);
    Answer a;
    a.origin = vec4(ray.origin, 0.0);
    a.direction = vec4(ray.direction, 0.0);
    a.unused[0] = a.unused[1] = a.unused[2] = a.unused[3] = vec4(0.0);
    answers[i] = a;
}
