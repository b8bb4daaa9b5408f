#version 430 core
// The image as the eye sees it: each pixel's running mean of radiance, exposed and
// tone mapped (tone_mapping.glsl), for the window and the PNG. Run before each frame
// is drawn and before a PNG is written (course::Session::setDisplay).
#include "shared.h"
#include "tone_mapping.glsl"

layout(local_size_x = TILE_SIZE, local_size_y = TILE_SIZE) in;
layout(std430, binding = PIXELS_BINDING) readonly buffer Pixels { vec4 pixels[]; };
layout(std430, binding = DISPLAY_BINDING) writeonly buffer Display { vec4 displayed[]; };

void main() {
    uvec2 pixel = gl_GlobalInvocationID.xy;
    if (pixel.x >= imageSize.x || pixel.y >= imageSize.y) return;
    uint index = pixel.y * imageSize.x + pixel.x;
    // The other views (albedo, normals, ...) show numbers, not light: as they are.
    bool light = view == VIEW_RADIANCE;
    displayed[index] = vec4(toneMapped(pixels[index].rgb, light ? exposure : 0.0,
                                       light ? toneMap : TONE_MAP_CLAMP), 1.0);
}
