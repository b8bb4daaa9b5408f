#include "course/gl_context.h"

#include <cstdio>

#include "course/error.h"
#include "course/gl.h"
#include "course/log.h"

namespace course {
namespace {

void GLAPIENTRY printDebugMessage(GLenum source, GLenum type, GLuint id, GLenum severity,
                                  GLsizei, const GLchar* message, const void*) {
    // Notifications (buffer placed in memory, ...) only with --verbose.
    if (severity == GL_DEBUG_SEVERITY_NOTIFICATION && !verboseLogging()) return;
    // Compile errors are reported by ShaderProgram, with file:line; not twice.
    if (source == GL_DEBUG_SOURCE_SHADER_COMPILER) return;
    const char* kind = type == GL_DEBUG_TYPE_ERROR                 ? "error"
                       : type == GL_DEBUG_TYPE_PERFORMANCE         ? "performance"
                       : type == GL_DEBUG_TYPE_DEPRECATED_BEHAVIOR ? "deprecated"
                       : type == GL_DEBUG_TYPE_UNDEFINED_BEHAVIOR  ? "undefined behaviour"
                                                                   : "other";
    const char* from = source == GL_DEBUG_SOURCE_API               ? "api"
                       : source == GL_DEBUG_SOURCE_SHADER_COMPILER ? "shader compiler"
                       : source == GL_DEBUG_SOURCE_WINDOW_SYSTEM   ? "window system"
                                                                   : "other";
    const char* level = severity == GL_DEBUG_SEVERITY_HIGH     ? "high"
                        : severity == GL_DEBUG_SEVERITY_MEDIUM ? "medium"
                        : severity == GL_DEBUG_SEVERITY_LOW    ? "low"
                                                               : "note";
    std::fprintf(stderr, "GL %s (%s, %s severity, id %u): %s\n", kind, from, level, id,
                 message);
}

void enableDebugMessages() {
    // A GL 4.3 entry point: below 4.3 (the GL 3.3 appendix) the course goes without.
    if (!GLAD_GL_VERSION_4_3) return;
    glEnable(GL_DEBUG_OUTPUT);
#ifndef NDEBUG
    // Synchronous: the callback runs inside the GL call that caused it, so a debugger's
    // backtrace points at the culprit. It costs speed, hence debug builds only.
    glEnable(GL_DEBUG_OUTPUT_SYNCHRONOUS);
#endif
    glDebugMessageCallback(printDebugMessage, nullptr);
}

}  // namespace

void failTooOld(GlVersion required, const std::string& have, const std::string& backend) {
    const bool storage = required.major * 10 + required.minor >= 43;
    throw GlTooOld(
         "this chapter needs OpenGL " + required.text() + " core" +
             (storage ? " (compute shaders and storage buffers)" : "") + ", but " + backend +
             " offers OpenGL " + have + ". Update the graphics driver" +
             (storage ? ", try --backend osmesa (software), or on macOS, which stops at "
                        "OpenGL 4.1, follow the OpenGL 3.3 appendix."
                      : " or try --backend osmesa (software)."));
}

void loadGlAndCheckVersion(GlProcLoader loader, GlVersion required,
                           const std::string& backend) {
    int loaded = gladLoadGL(reinterpret_cast<GLADloadfunc>(loader));
    if (!loaded) fail(ExitCode::GlProblem, backend + ": could not load OpenGL functions");
    int major = GLAD_VERSION_MAJOR(loaded), minor = GLAD_VERSION_MINOR(loaded);
    if (major * 10 + minor < required.major * 10 + required.minor)
        failTooOld(required, std::to_string(major) + "." + std::to_string(minor), backend);
    enableDebugMessages();
    logInfo("backend " + backend + ": " +
            reinterpret_cast<const char*>(glGetString(GL_RENDERER)) + ", OpenGL " +
            reinterpret_cast<const char*>(glGetString(GL_VERSION)));
}

std::unique_ptr<GlContext> createGlContext(const Options& options, GlVersion required,
                                           const std::string& windowTitle) {
    if (options.window) return createGlfwContext(required, options, windowTitle);
    switch (options.backend) {
        case Backend::Egl: return createEglContext(required, options.gpu);
        case Backend::OsMesa: return createOsMesaContext(required);
        case Backend::Glfw:  // --backend glfw --headless: a window that is never shown
            return createGlfwContext(required, options, windowTitle, /*visible=*/false);
        case Backend::Auto: break;
    }
    // Headless by default: EGL (a GPU, or Mesa without a display); OSMesa if EGL fails
    // for a reason other than an old GL version.
    // --gpu N: that device or a clear failure, never another renderer in its place.
    if (options.gpu >= 0 && (eglBuiltIn() || !options.gpuFromEnvironment))
        return createEglContext(required, options.gpu);
    if (eglBuiltIn()) {
        try {
            return createEglContext(required);
        } catch (const GlTooOld&) {
            throw;  // OSMesa is the same Mesa: it would be too old as well
        } catch (const Failure& eglFailure) {
            logInfo(std::string("EGL failed (") + eglFailure.what() + "), trying OSMesa");
        }
        return createOsMesaContext(required);
    }
    // Windows: the driver's OpenGL, through a window that is never shown.
    if (!osmesaBuiltIn())
        return createGlfwContext(required, options, windowTitle, /*visible=*/false);
    // A build without EGL (macOS): OSMesa if it is installed, else a hidden GLFW window,
    // which on a Mac gives the system's OpenGL 4.1.
    try {
        return createOsMesaContext(required);
    } catch (const GlTooOld&) {
        throw;
    } catch (const Failure& osmesaFailure) {
        logInfo(std::string("OSMesa failed (") + osmesaFailure.what() +
                "), trying a hidden GLFW window");
        try {
            return createGlfwContext(required, options, windowTitle, /*visible=*/false);
        } catch (const GlTooOld&) {
            throw;  // on a Mac: the compute chapters need 4.3, macOS has 4.1
        } catch (const Failure& glfwFailure) {
            fail(ExitCode::GlProblem,
                 std::string("no headless OpenGL context (this build has no EGL):\n  ") +
                     osmesaFailure.what() + "\n  " + glfwFailure.what());
        }
    }
}

}  // namespace course
