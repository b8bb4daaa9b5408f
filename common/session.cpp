#include "course/session.h"

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>

#include "course/display.h"
#include "course/image_file.h"
#include "course/log.h"

namespace fs = std::filesystem;

namespace course {

Session::Session(const Options& options, const ChapterPaths& chapter, GlVersion required)
    : options_(options), chapter_(chapter),
      shaderDir_(options.shaderDir.empty() ? chapter.shaderDir : options.shaderDir) {
    if (!fs::is_directory(shaderDir_))
        fail(ExitCode::BadUsage, "shader folder not found: " + fs::absolute(shaderDir_).string());
    context_ = createGlContext(options_, required, "GPU ray tracing course: " + chapter.name);
    stats_.set("chapter", chapter.name);
    stats_.set("backend", context_->backendName());
    stats_.set("renderer", reinterpret_cast<const char*>(glGetString(GL_RENDERER)));
    stats_.set("gl_version", reinterpret_cast<const char*>(glGetString(GL_VERSION)));
    stats_.set("width", options_.width);
    stats_.set("height", options_.height);
}

std::string Session::assetPath(const std::string& relative) const {
    const std::string& root = options_.assetDir.empty() ? chapter_.assetDir : options_.assetDir;
    return (fs::path(root) / relative).string();
}

ShaderProgram& Session::loadCompute(const std::string& fileName) {
    programs_.push_back(ShaderProgram::compute(shaderDir_, fileName));
    return programs_.back();
}

ShaderProgram& Session::loadProgram(const std::vector<ShaderStage>& stages) {
    programs_.push_back(ShaderProgram(shaderDir_, stages));
    return programs_.back();
}

// Waits until the GPU has finished everything queued so far, but not forever: on a GPU a
// shader that never leaves its loop would hang the program (llvmpipe cuts such loops
// off itself). COURSE_GPU_TIMEOUT_SECONDS overrides the limit.
void waitForGpu() {
    const char* setting = std::getenv("COURSE_GPU_TIMEOUT_SECONDS");
    const double limit = setting ? std::atof(setting) : 600.0;
    GLsync fence = glFenceSync(GL_SYNC_GPU_COMMANDS_COMPLETE, 0);
    auto start = std::chrono::steady_clock::now();
    for (;;) {
        GLenum state = glClientWaitSync(fence, GL_SYNC_FLUSH_COMMANDS_BIT, 100'000'000);
        if (state == GL_ALREADY_SIGNALED || state == GL_CONDITION_SATISFIED) break;
        std::chrono::duration<double> waited = std::chrono::steady_clock::now() - start;
        if (state == GL_WAIT_FAILED || waited.count() > limit) {
            std::fprintf(stderr,
                         "error: the GPU did not finish within %.0f s: a shader probably "
                         "loops forever (check its loop conditions)\n",
                         limit);
            // Not a normal return: tearing down a context whose GPU work is still
            // running can block forever too. Nothing has been written yet.
            std::_Exit(static_cast<int>(ExitCode::GlProblem));
        }
    }
    glDeleteSync(fence);
}

void Session::timeRender(const std::function<void()>& render) {
    GpuTimer timer;
    auto start = std::chrono::steady_clock::now();
    timer.begin();
    render();
    timer.end();
    waitForGpu();  // wall time must include the GPU's work, not just queuing it
    std::chrono::duration<double, std::milli> wall = std::chrono::steady_clock::now() - start;
    stats_.set("wall_ms", wall.count());
    stats_.set("gpu_ms", timer.milliseconds());
    logInfo("render: " + std::to_string(wall.count()) + " ms wall, " +
            std::to_string(stats_.number("gpu_ms")) + " ms GPU");
}

bool Session::reloadChangedShaders() {
    bool any = false;
    for (ShaderProgram& program : programs_) any |= program.reloadIfChanged();
    return any;
}

static Image downloadImage(const ImageBuffer& image) {
    Image pixels;
    pixels.width = image.width;
    pixels.height = image.height;
    pixels.rgba = image.pixels.readAll<float>();
    return pixels;
}

void Session::finish(const ImageBuffer& image, const std::function<void()>& render,
                     const std::function<void(int frame)>& eachFrame) {
    if (GLFWwindow* window = context_->window()) {
        ImageDisplay display;
        auto lastCheck = std::chrono::steady_clock::now();
        bool screenshotKeyWasDown = false;
        int screenshots = 0;
        for (int frame = 0; !glfwWindowShouldClose(window); ++frame) {
            if (options_.frames && frame >= options_.frames) break;
            glfwPollEvents();
            if (glfwGetKey(window, GLFW_KEY_ESCAPE) == GLFW_PRESS) break;
            // Look for edited shaders a few times a second, not every frame.
            auto now = std::chrono::steady_clock::now();
            if (render && now - lastCheck > std::chrono::milliseconds(250)) {
                lastCheck = now;
                if (reloadChangedShaders()) render();
            }
            if (eachFrame) eachFrame(frame);
            // F12: the image as it is now, as a PNG in the working folder.
            bool screenshotKeyDown = glfwGetKey(window, GLFW_KEY_F12) == GLFW_PRESS;
            if (screenshotKeyDown && !screenshotKeyWasDown) {
                std::string path = chapter_.name + "_screenshot_" +
                                   std::to_string(++screenshots) + ".png";
                writeImage(path, downloadImage(image));
                std::printf("saved %s\n", fs::absolute(path).c_str());
            }
            screenshotKeyWasDown = screenshotKeyDown;
            int width = 0, height = 0;
            glfwGetFramebufferSize(window, &width, &height);
            if (width > 0 && height > 0) display.draw(image, width, height);
            glfwSwapBuffers(window);
        }
        if (options_.outPath.empty()) return;
    }
    std::string path = options_.outPath.empty() ? chapter_.name + ".png" : options_.outPath;
    writeImage(path, downloadImage(image));
    stats_.set("out", fs::absolute(path).string());
    if (!options_.json) std::printf("wrote %s\n", fs::absolute(path).c_str());
}

int runChapter(CommandLine& cli, int argc, char** argv, const ChapterPaths& chapter,
               GlVersion required, const std::function<void(Session&)>& body) {
    cli.setProgramName(chapter.name);
    try {
        Options options;
        if (!cli.parse(argc, argv, options)) {
            std::fputs(cli.usage().c_str(), stdout);
            return 0;
        }
        verboseLogging() = options.verbose;
        if (!options.outPath.empty()) checkOutputPath(options.outPath);
        Session session(options, chapter, required);
        body(session);
        if (options.json) std::printf("%s\n", session.stats().toJson().c_str());
        return 0;
    } catch (const Failure& failure) {
        std::fprintf(stderr, "%s: error: %s\n", chapter.name.c_str(), failure.what());
        return static_cast<int>(failure.code());
    } catch (const std::exception& error) {
        std::fprintf(stderr, "%s: internal error: %s\n", chapter.name.c_str(), error.what());
        return 70;  // EX_SOFTWARE: a bug in the course, not in the user's input
    }
}

}  // namespace course
