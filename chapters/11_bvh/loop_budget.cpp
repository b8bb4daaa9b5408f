#include "loop_budget.h"

#include "course/error.h"
#include "course/gl.h"

// --8<-- [start:check]
void checkLoopBudget(size_t shapeCount, const std::string& scenePath,
                     const std::string& wayOut) {
    const char* renderer = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
    const long long iterations = loopIterationsPerPixel(shapeCount);
    if (!renderer || std::string(renderer).find("llvmpipe") == std::string::npos ||
        iterations <= kLlvmpipeLoopLimit)
        return;
    course::fail(course::ExitCode::GlProblem,
                 scenePath + ": " + std::to_string(shapeCount) +
                     " shape tests per path need up to " +
                     std::to_string(iterations) + " loop iterations per pixel, but " +
                     renderer + " ends a shader invocation after " +
                     std::to_string(kLlvmpipeLoopLimit) +
                     ", silently, and the picture would be wrong. " + wayOut);
}
// --8<-- [end:check]
