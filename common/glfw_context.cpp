// A window through GLFW: for watching a checkpoint render (--window). Headless runs
// never touch GLFW, so they work where there is no display at all.
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include "course/error.h"
#include "course/gl_context.h"

namespace course {
namespace {

std::string lastGlfwError;
void rememberGlfwError(int, const char* description) { lastGlfwError = description; }

class GlfwContext : public GlContext {
public:
    explicit GlfwContext(GLFWwindow* window) : window_(window) {}
    ~GlfwContext() override {
        glfwDestroyWindow(window_);
#ifndef COURSE_SANITIZE_BUILD
        glfwTerminate();  // sanitizer builds keep the GL driver loaded: see egl_context.cpp
#endif
    }
    std::string backendName() const override { return "glfw"; }
    GLFWwindow* window() override { return window_; }

private:
    GLFWwindow* window_;
};

}  // namespace

std::unique_ptr<GlContext> createGlfwContext(GlVersion required, const Options& options,
                                             const std::string& title) {
    glfwSetErrorCallback(rememberGlfwError);
    if (!glfwInit())
        fail(ExitCode::GlProblem, "GLFW: cannot open a window (" + lastGlfwError +
                                      "); is there a display? Use --headless without one.");
    glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, required.major);
    glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, required.minor);
    glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
    glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);  // macOS insists on it
#ifndef NDEBUG
    glfwWindowHint(GLFW_OPENGL_DEBUG_CONTEXT, GLFW_TRUE);
#endif
    GLFWwindow* window =
        glfwCreateWindow(options.width, options.height, title.c_str(), nullptr, nullptr);
    if (!window) {
        std::string reason = lastGlfwError;
        glfwTerminate();
        if (reason.find("version") != std::string::npos)
            failTooOld(required, "less (" + reason + ")", "the window system");
        fail(ExitCode::GlProblem, "GLFW: could not create a window: " + reason);
    }
    glfwMakeContextCurrent(window);
    glfwSwapInterval(1);  // vsync: no point drawing frames the screen cannot show
    auto context = std::make_unique<GlfwContext>(window);
    loadGlAndCheckVersion(reinterpret_cast<GlProcLoader>(glfwGetProcAddress), required,
                          "glfw");
    return context;
}

}  // namespace course
