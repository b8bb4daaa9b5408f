// Mesa's llvmpipe, the software GL the course runs on without a GPU, ends a shader
// invocation after 65535 loop iterations in total, silently: the invocation stops where
// it is and the pixel gets whatever was written so far. A GPU has no such limit.
#pragma once
#include <cstddef>
#include <string>

// Each shape a path tests in a loop costs up to two iterations: the ray's search for
// the nearest hit, then the shadow ray's search for any hit.
constexpr long long kLlvmpipeLoopLimit = 65535;
constexpr long long loopIterationsPerPixel(size_t shapeCount) {
    return 2LL * static_cast<long long>(shapeCount);
}

// On llvmpipe, a scene that needs more than the limit fails with exit code 4 and a
// message naming `scenePath`, the count and `wayOut`, instead of rendering a wrong
// picture. On any other GL it does nothing.
void checkLoopBudget(size_t shapeCount, const std::string& scenePath,
                     const std::string& wayOut);
