#version 430 core
// The wavefront's last kernel: every path has ended, and its radiance joins the
// pixel's running mean (the megakernel's main() after tracePath).
#include "path_tracer.glsl"
#include "wavefront.glsl"

layout(local_size_x = TILE_SIZE, local_size_y = TILE_SIZE) in;
layout(std430, binding = PIXELS_BINDING) buffer Pixels { vec4 pixels[]; };

void main() {
    uvec2 pixel = gl_GlobalInvocationID.xy;
    if (pixel.x >= imageSize.x || pixel.y >= imageSize.y) return;  // overhanging tiles
    uint index = pixel.y * imageSize.x + pixel.x;
    vec3 radiance = slots[index].path.radiance;
    vec3 mean = sampleIndex == 0u ? vec3(0.0) : pixels[index].rgb;
    mean += (radiance - mean) / float(sampleIndex + 1u);
    pixels[index] = vec4(mean, 1.0);
}
