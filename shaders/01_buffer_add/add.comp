#version 430 core
// Chapter 01: every invocation adds one pair of floats, plus a constant.
#include "shared.h"

layout(local_size_x = WORKGROUP_SIZE) in;

// --8<-- [start:buffers]
// std430: floats packed tightly, exactly like a C++ float array.
layout(std430, binding = INPUT_A_BINDING) readonly buffer InputA { float a[]; };
layout(std430, binding = INPUT_B_BINDING) readonly buffer InputB { float b[]; };
layout(std430, binding = OUTPUT_BINDING) writeonly buffer Output { float sum[]; };
// --8<-- [end:buffers]

uniform uint count;     // how many elements are real
uniform float constant; // added to every sum

void main() {
    // --8<-- [start:main]
    uint i = gl_GlobalInvocationID.x;
    // The last work group may run past the end of the arrays: those invocations
    // must not read or write anything.
    // BEGIN SOLUTION return early when i is past the end, then add a[i] + b[i] + constant
    if (i >= count) return;
    sum[i] = a[i] + b[i] + constant;
    // END SOLUTION
    // --8<-- [end:main]
}
