// A window through GLFW: for watching a checkpoint render (--window). Headless runs
// use EGL or OSMesa where they can, so they work with no display at all; where there
// is neither (macOS), or with --backend glfw --headless, a window that is never shown
// holds the context instead.
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include <cstdlib>

#include "course/error.h"
#include "course/gl_context.h"

namespace course {
namespace {

std::string lastGlfwError;
int lastGlfwErrorCode = 0;
void rememberGlfwError(int code, const char* description) {
    lastGlfwError = description;
    lastGlfwErrorCode = code;
}

class GlfwContext : public GlContext {
public:
    GlfwContext(GLFWwindow* window, bool visible) : window_(window), visible_(visible) {}
    ~GlfwContext() override {
        glfwDestroyWindow(window_);
#ifndef COURSE_SANITIZE_BUILD
        glfwTerminate();  // sanitizer builds keep the GL driver loaded: see egl_context.cpp
#endif
    }
    std::string backendName() const override {
        return visible_ ? "glfw" : "glfw (hidden window)";
    }
    GLFWwindow* window() override { return visible_ ? window_ : nullptr; }

private:
    GLFWwindow* window_;
    bool visible_;
};

}  // namespace

std::unique_ptr<GlContext> createGlfwContext(GlVersion required, const Options& options,
                                             const std::string& title, bool visible) {
    glfwSetErrorCallback(rememberGlfwError);
#ifdef GLFW_PLATFORM  // GLFW 3.4 and later
    // GLFW 3.4 tries Wayland before X11. With an X display and no Wayland one (Xvfb,
    // ssh -X, a desktop without Wayland), go straight to X11: the Wayland attempt
    // prints "XDG_RUNTIME_DIR is invalid or not set" where there is no user session.
    const char* x11 = std::getenv("DISPLAY");
    const char* wayland = std::getenv("WAYLAND_DISPLAY");
    if (x11 && *x11 && !(wayland && *wayland) && glfwPlatformSupported(GLFW_PLATFORM_X11))
        glfwInitHint(GLFW_PLATFORM, GLFW_PLATFORM_X11);
#endif
    if (!visible) {
        // macOS only (ignored elsewhere): no menu bar for a program that shows nothing,
        // and keep the working folder, where --out's relative paths point.
        glfwInitHint(GLFW_COCOA_MENUBAR, GLFW_FALSE);
        glfwInitHint(GLFW_COCOA_CHDIR_RESOURCES, GLFW_FALSE);
    }
    if (!glfwInit())
        fail(ExitCode::GlProblem,
             "GLFW: cannot open a window (" + lastGlfwError + "); is there a display? " +
                 (visible ? "Use --headless without one."
                          : "A hidden window needs one too."));
    glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, required.major);
    glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, required.minor);
    glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
    glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);  // macOS insists on it
#ifndef NDEBUG
    glfwWindowHint(GLFW_OPENGL_DEBUG_CONTEXT, GLFW_TRUE);
#endif
    // Hidden: the window only holds the context. Chapters render into their own
    // buffers, never its framebuffer, so its size does not matter.
    glfwWindowHint(GLFW_VISIBLE, visible ? GLFW_TRUE : GLFW_FALSE);
    GLFWwindow* window = visible ? glfwCreateWindow(options.width, options.height,
                                                    title.c_str(), nullptr, nullptr)
                                 : glfwCreateWindow(16, 16, title.c_str(), nullptr, nullptr);
    if (!window) {
        std::string reason = lastGlfwError;
        int code = lastGlfwErrorCode;
        glfwTerminate();
        // GLX (Mesa) and NSGL (macOS, which stops at 4.1) report a version they cannot
        // make with this code; the message does not always say "version".
        if (code == GLFW_VERSION_UNAVAILABLE ||
            reason.find("version") != std::string::npos)
            failTooOld(required, "less (" + reason + ")", "the window system");
        fail(ExitCode::GlProblem, "GLFW: could not create a window: " + reason);
    }
    glfwMakeContextCurrent(window);
    if (visible) glfwSwapInterval(1);  // vsync: no use drawing frames nobody sees
    auto context = std::make_unique<GlfwContext>(window, visible);
    loadGlAndCheckVersion(reinterpret_cast<GlProcLoader>(glfwGetProcAddress), required,
                          context->backendName());
    return context;
}

}  // namespace course
