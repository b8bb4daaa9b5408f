#version 430 core
// The wavefront's last kernel: every path of the wave has ended, and its radiance joins
// its pixel's running mean (the megakernel's main() after tracePath).
#include "path_tracer.glsl"
#include "wavefront.glsl"

layout(local_size_x = QUEUE_GROUP_SIZE) in;
layout(std430, binding = PIXELS_BINDING) buffer Pixels { vec4 pixels[]; };

void main() {
    uint slot = gl_GlobalInvocationID.x;
    if (slot >= waveSize) return;  // the last work group overhangs
    uint index = pixelOf(slot);
    vec3 radiance = slots[slot].path.radiance;
    vec3 mean = sampleIndex == 0u ? vec3(0.0) : pixels[index].rgb;
    mean += (radiance - mean) / float(sampleIndex + 1u);
    pixels[index] = vec4(mean, 1.0);
}
