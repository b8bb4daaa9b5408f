#include "course/session.h"

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include <algorithm>
#include <chrono>
#include <condition_variable>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <mutex>
#include <thread>

#include "course/display.h"
#include "course/gpu_limits.h"
#include "course/gpu_watchdog.h"
#include "course/render_progress.h"
#include "course/image_file.h"
#include "course/log.h"
#include "course/loop_budget.h"

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
    if (GLAD_GL_VERSION_4_3) {  // what a GPU report wants to know (tools/gpu_check.sh)
        stats_.set("max_compute_storage_blocks",
                   double(glLimit(GL_MAX_COMPUTE_SHADER_STORAGE_BLOCKS,
                                  "GL_MAX_COMPUTE_SHADER_STORAGE_BLOCKS")));
        stats_.set("max_compute_texture_units",
                   double(glLimit(GL_MAX_COMPUTE_TEXTURE_IMAGE_UNITS,
                                  "GL_MAX_COMPUTE_TEXTURE_IMAGE_UNITS")));
    }
    stats_.set("width", options_.width);
    stats_.set("height", options_.height);
}

std::string Session::assetPath(const std::string& relative) const {
    const std::string& root = options_.assetDir.empty() ? chapter_.assetDir : options_.assetDir;
    return (fs::path(root) / relative).string();
}

std::string Session::scenePath(const std::string& defaultScene) const {
    const std::string& scene = options_.scene.empty() ? defaultScene : options_.scene;
    if (scene.find_first_of("/.") != std::string::npos) return scene;
    std::string path = assetPath("scenes/" + scene + ".scene");
    if (!fs::exists(path))
        fail(ExitCode::BadUsage, "unknown scene '" + scene + "': no " + path);
    return path;
}

ShaderProgram& Session::loadCompute(const std::string& fileName, GeneratedFiles generated) {
    programs_.push_back(ShaderProgram::compute(shaderDir_, fileName, std::move(generated)));
    return programs_.back();
}

ShaderProgram& Session::loadProgram(const std::vector<ShaderStage>& stages) {
    programs_.push_back(ShaderProgram(shaderDir_, stages));
    return programs_.back();
}

void Session::timeRender(const std::function<void()>& render, const unsigned& samplesDone) {
    RenderProgress progress(samplesDone, options_.spp);
    timeRender(render);
}

void Session::timeRender(const std::function<void()>& render) {
    GpuTimer timer;
    auto start = std::chrono::steady_clock::now();
    GpuWatchdog watchdog;  // a step that never ends ends the program (exit code 4)
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

// Reloaded when any program was; else KeptLastGood when any failed to build.
ShaderProgram::Reload Session::reloadChangedShaders() {
    using Reload = ShaderProgram::Reload;
    Reload result = Reload::Unchanged;
    for (ShaderProgram& program : programs_) {
        Reload reload = program.reloadIfChanged();
        if (reload == Reload::Reloaded || result == Reload::Unchanged) result = reload;
    }
    return result;
}

static Image downloadImage(const ImageBuffer& image) {
    Image pixels;
    pixels.width = image.width;
    pixels.height = image.height;
    pixels.rgba = image.pixels.readAll<float>();
    return pixels;
}

namespace {

// Ctrl+C in the terminal (SIGINT) or SIGTERM closes the window like Esc does, so --out
// is still written. A second one ends the program at once, as usual.
volatile std::sig_atomic_t closeRequested = 0;

void requestClose(int signal) {
    closeRequested = 1;
    std::signal(signal, SIG_DFL);
}

class CloseOnSignal {
public:
    CloseOnSignal()
        : interrupt_(std::signal(SIGINT, requestClose)),
          terminate_(std::signal(SIGTERM, requestClose)) {}
    ~CloseOnSignal() {
        std::signal(SIGINT, interrupt_);
        std::signal(SIGTERM, terminate_);
    }
    bool requested() const { return closeRequested != 0; }

private:
    void (*interrupt_)(int);
    void (*terminate_)(int);
};

}  // namespace

void Session::setDisplay(const ImageBuffer& display, std::function<void()> toDisplay) {
    display_ = &display;
    toDisplay_ = std::move(toDisplay);
}

void Session::finish(const ImageBuffer& image, const std::function<void()>& render,
                     const std::function<void(int frame)>& eachFrame) {
    // The image as the eye sees it: the display's, made fresh, or the image itself.
    // A display pass is a compute shader's (GL 4.3 on): the GL 3.3 appendix has none.
    auto shown = [&]() -> const ImageBuffer& {
        if (!display_ || !GLAD_GL_VERSION_4_3) return image;
        glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
        toDisplay_();
        glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
        return *display_;
    };
    auto forFile = [&](const std::string& path) -> const ImageBuffer& {
        const bool png = path.size() >= 4 && path.compare(path.size() - 4, 4, ".png") == 0;
        return png ? shown() : image;
    };
    if (GLFWwindow* window = context_->window()) {
        ImageDisplay display;
        CloseOnSignal closeOnSignal;
        std::vector<std::string> watched;
        for (const ShaderProgram& program : programs_)
            for (const std::string& file : program.watchedFiles())
                if (render && std::find(watched.begin(), watched.end(), file) == watched.end())
                    watched.push_back(file);
        for (const std::string& file : watched) logInfo("watching " + file);
        bool screenshotKeyWasDown = false;
        int screenshots = 0;
        bool reportFrame = true;  // the first frame, and the first after each reload
        int frame = 0;
        for (; !glfwWindowShouldClose(window) && !closeOnSignal.requested(); ++frame) {
            if (options_.frames && frame >= options_.frames) break;
            glfwPollEvents();
            if (glfwGetKey(window, GLFW_KEY_ESCAPE) == GLFW_PRESS) break;
            // Edited shaders, looked for before every frame (reading a few small files
            // costs far less than a frame).
            if (render) {
                ShaderProgram::Reload reload = reloadChangedShaders();
                if (reload == ShaderProgram::Reload::Reloaded) render();
                if (reload != ShaderProgram::Reload::Unchanged) reportFrame = true;
            }
            if (eachFrame) eachFrame(frame);
            // F12: the image as it is now, as a PNG in the working folder.
            bool screenshotKeyDown = glfwGetKey(window, GLFW_KEY_F12) == GLFW_PRESS;
            if (screenshotKeyDown && !screenshotKeyWasDown) {
                std::string path = chapter_.name + "_screenshot_" +
                                   std::to_string(++screenshots) + ".png";
                writeImage(path, downloadImage(shown()));
                std::printf("saved %s\n", fs::absolute(path).string().c_str());
            }
            screenshotKeyWasDown = screenshotKeyDown;
            int width = 0, height = 0;
            glfwGetFramebufferSize(window, &width, &height);
            if (width > 0 && height > 0) display.draw(shown(), width, height);
            glfwSwapBuffers(window);
            if (reportFrame) logInfo("frame " + std::to_string(frame) + " drawn");
            reportFrame = false;
        }
        logInfo("window closed after " + std::to_string(frame) + " frames");
        if (options_.outPath.empty()) return;
    }
    std::string path = options_.outPath.empty() ? chapter_.name + ".png" : options_.outPath;
    writeImage(path, downloadImage(forFile(path)));
    stats_.set("out", fs::absolute(path).string());
    if (!options_.json) std::printf("wrote %s\n", fs::absolute(path).string().c_str());
}

// --probe-loop-limit: the loop limit of the shaders the chapter runs (fragment shaders
// when it asks for GL 3.3), as a line of text or in --json's statistics.
static void reportLoopLimit(Session& session, GlVersion required) {
    const bool compute = required.major * 10 + required.minor >= 43;
    const LoopLimit limit = measureLoopLimit(compute ? GL_COMPUTE_SHADER : GL_FRAGMENT_SHADER);
    const std::string stage = compute ? "compute" : "fragment";
    session.stats().set("loop_limit_stage", stage);
    if (limit.limited)
        session.stats().set("loop_limit", double(limit.iterations));
    else
        session.stats().set("loop_limit", "none");
    session.stats().set("loop_probe_iterations", double(limit.probed));
    if (!session.options().json)
        std::printf("loop limit of %s shaders: %s per invocation, on %s\n", stage.c_str(),
                    limit.text().c_str(), limit.driver.c_str());
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
        if (options.probeLoopLimit)
            reportLoopLimit(session, required);
        else
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
