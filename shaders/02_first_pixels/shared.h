// Numbers the C++ host and the GLSL shaders must agree on.
#ifndef CHAPTER02_SHARED_H
#define CHAPTER02_SHARED_H

#define PIXELS_BINDING 0  // the image: one vec4 per pixel, row 0 at the top

// 1D dispatch: a row of 64 invocations per work group.
#define WORKGROUP_SIZE_1D 64
// 2D dispatch: 8x8 tiles, also 64 invocations, but neighbours in both directions.
#define TILE_SIZE 8

#endif
