// Stands in for egl_context.cpp in builds without EGL (macOS; -DCOURSE_WITH_EGL=OFF):
// --backend egl is refused with the reason, and the headless default skips EGL.
#include "course/error.h"
#include "course/gl_context.h"

namespace course {

bool eglBuiltIn() { return false; }

std::unique_ptr<GlContext> createEglContext(GlVersion, int) {
    fail(ExitCode::GlProblem,
         "EGL: this build has no EGL (configured with COURSE_WITH_EGL=OFF, the default "
         "on macOS, which has no EGL); use --backend osmesa or --backend glfw, or leave "
         "--backend out for the default");
}

}  // namespace course
