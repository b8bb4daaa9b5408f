// Numbers the C++ host and the GLSL shader must agree on. Both include this file:
// C++ through its include path, GLSL through the course's #include.
#ifndef CHAPTER01_SHARED_H
#define CHAPTER01_SHARED_H

// Storage buffer bindings: `layout(binding = N)` in GLSL, glBindBufferBase(.., N, ..)
// in C++.
#define INPUT_A_BINDING 0
#define INPUT_B_BINDING 1
#define OUTPUT_BINDING 2

// Invocations per work group. 32 matches an NVIDIA warp; other GPUs prefer 64, and
// llvmpipe does not care much. Any value works: the shader checks its bounds.
#define WORKGROUP_SIZE 32

#endif
