// Mesa's llvmpipe, the software GL the course runs on without a GPU, ends a shader
// invocation after 65535 loop iterations in total, silently: the invocation stops where
// it is and the pixel gets whatever was written so far. A GPU has no such limit.
#pragma once
#include <cstddef>
#include <string>

// Brute force costs up to two loops over all triangles per pixel: the camera ray's
// search for the nearest hit, then the shadow ray's search for any hit.
constexpr long long kLlvmpipeLoopLimit = 65535;
constexpr long long loopIterationsPerPixel(size_t triangleCount) {
    return 2LL * static_cast<long long>(triangleCount);
}

// On llvmpipe, a scene that needs more than the limit fails with exit code 4 and a
// message naming `meshPath`, the count and the way out (chapter 11's BVH), instead of
// rendering a wrong picture. On any other GL it does nothing.
void checkLoopBudget(size_t triangleCount, const std::string& meshPath);
