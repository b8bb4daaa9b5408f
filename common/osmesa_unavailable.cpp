// Stands in for osmesa_context.cpp on Windows, which has no OSMesa to load: --backend
// osmesa is refused with the reason, and the headless default goes on to a hidden
// GLFW window (gl_context.cpp), which the Windows driver's OpenGL renders into.
#include "course/error.h"
#include "course/gl_context.h"

namespace course {

bool osmesaBuiltIn() { return false; }

std::unique_ptr<GlContext> createOsMesaContext(GlVersion) {
    fail(ExitCode::GlProblem,
         "OSMesa: this build has none (Windows, whose OpenGL comes from the graphics "
         "driver); use --backend glfw, or leave --backend out for the default");
}

}  // namespace course
