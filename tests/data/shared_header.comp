#version 430 core
// A checkpoint's shared.h compiled on its own as GLSL (tests/cpp/test_shader_program.cpp,
// loaded with that checkpoint's shader folder as the base): what it keeps for C++ inside
// #ifdef __cplusplus (#include <glm/glm.hpp>, namespace gpu, static_asserts) must never
// reach the GLSL compiler.
#include "shared.h"

layout(local_size_x = 1) in;
void main() {}
