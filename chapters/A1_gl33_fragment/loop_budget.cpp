#include "loop_budget.h"

#include "course/error.h"
#include "course/gl.h"

// --8<-- [start:check]
void checkLoopBudget(size_t triangleCount, const std::string& meshPath) {
    const char* renderer = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
    const long long iterations = loopIterationsPerPixel(triangleCount);
    if (!renderer || std::string(renderer).find("llvmpipe") == std::string::npos ||
        iterations <= kLlvmpipeLoopLimit)
        return;
    course::fail(course::ExitCode::GlProblem,
                 meshPath + ": " + std::to_string(triangleCount) +
                     " triangles (with the floor's 2) need up to " +
                     std::to_string(iterations) + " loop iterations per pixel, but " +
                     renderer + " ends a shader invocation after " +
                     std::to_string(kLlvmpipeLoopLimit) +
                     ", silently, and the picture would be wrong. Testing every triangle "
                     "for every ray, this chapter renders at most " +
                     std::to_string(kLlvmpipeLoopLimit / 2) +
                     " triangles on llvmpipe. Chapter 11's BVH renders this mesh; so does "
                     "a real GPU.");
}
// --8<-- [end:check]
