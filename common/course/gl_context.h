// Where GL calls go: an off-screen context (EGL, OSMesa, or a GLFW window that is
// never shown) or a GLFW window.
// Chapters never create contexts themselves; course::Session does it from the options.
#pragma once
#include <memory>
#include <string>

#include "course/cli.h"
#include "course/error.h"

struct GLFWwindow;

namespace course {

struct GlVersion {
    int major = 4, minor = 3;  // 4.3 core: the first with compute shaders and SSBOs
    std::string text() const { return std::to_string(major) + "." + std::to_string(minor); }
};

class GlContext {
public:
    virtual ~GlContext() = default;
    virtual std::string backendName() const = 0;   // "egl (surfaceless)", "osmesa", ...
    // Only a shown GLFW window: a hidden one (headless) has nothing to show or read.
    virtual GLFWwindow* window() { return nullptr; }
};

// Creates the context the options ask for, loads GL functions with GLAD, checks the
// version and turns on the debug message callback. Throws Failure(GlProblem) with
// the reason and the way out when no context of the required version can be made.
std::unique_ptr<GlContext> createGlContext(const Options& options, GlVersion required,
                                           const std::string& windowTitle);

// The context works but its version is below what the chapter needs.
class GlTooOld : public Failure {
public:
    explicit GlTooOld(const std::string& message) : Failure(ExitCode::GlProblem, message) {}
};

// --- used by the backends (gl_context.cpp) ---
using GlProcLoader = void* (*)(const char* name);
// Loads GL with GLAD and checks the version the context really gives.
void loadGlAndCheckVersion(GlProcLoader loader, GlVersion required,
                           const std::string& backend);
[[noreturn]] void failTooOld(GlVersion required, const std::string& have,
                             const std::string& backend);

bool eglBuiltIn();  // false in builds without EGL (macOS): egl_unavailable.cpp
// gpu >= 0: EGL device `gpu` and no other (--gpu); -1: the first that works.
std::unique_ptr<GlContext> createEglContext(GlVersion required, int gpu = -1);
std::unique_ptr<GlContext> createOsMesaContext(GlVersion required);
bool osmesaBuiltIn();  // false on Windows, which has no OSMesa: osmesa_unavailable.cpp
// visible = false: a window that is never shown, only to hold a context (headless
// where there is neither EGL nor OSMesa, as on macOS).
std::unique_ptr<GlContext> createGlfwContext(GlVersion required, const Options& options,
                                             const std::string& title, bool visible = true);

}  // namespace course
