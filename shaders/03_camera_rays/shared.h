// Numbers the C++ host and the GLSL shaders must agree on.
#ifndef COURSE_SHARED_H
#define COURSE_SHARED_H

#define PIXELS_BINDING 0  // the image: one vec4 per pixel, row 0 at the top

// 8x8 tiles of invocations: neighbouring rays run together (chapter 02).
#define TILE_SIZE 8

#endif
