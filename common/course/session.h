// A chapter program's run: the parsed options, the GL context they ask for, the
// shader folder, the statistics, and the way the finished image leaves the program
// (a file when headless, a window otherwise). Chapters write only the lesson:
//
//     int main(int argc, char** argv) {
//         course::CommandLine cli("Chapter NN: what it teaches");
//         return course::run(cli, argc, argv, [&](course::Session& session) { ... });
//     }
#pragma once
#include <functional>
#include <list>
#include <memory>
#include <string>

#include "course/cli.h"
#include "course/error.h"
#include "course/gl_context.h"
#include "course/gpu_watchdog.h"  // waitForGpu()
#include "course/gpu_buffer.h"
#include "course/shader_program.h"
#include "course/stats.h"

namespace course {

// Where a checkpoint's files are; fixed at build time by add_chapter().
struct ChapterPaths {
    std::string name;       // "NN_name"
    std::string shaderDir;  // <repo>/shaders/NN_name
    std::string assetDir;   // <repo>/assets
};

class Session {
public:
    Session(const Options& options, const ChapterPaths& chapter, GlVersion required);

    const Options& options() const { return options_; }
    bool isWindow() const { return options_.window; }
    GlContext& context() { return *context_; }
    Stats& stats() { return stats_; }
    const std::string& shaderDir() const { return shaderDir_; }
    std::string assetPath(const std::string& relative) const;
    // The scene file --scene names, or `defaultScene` without it: a NAME is
    // assets/scenes/NAME.scene (an unknown name is bad usage, exit code 2); anything
    // with a '/' or '.' is a file, as given (its mistakes are the reader's: exit code 3).
    std::string scenePath(const std::string& defaultScene) const;

    // Compiles a compute shader from the checkpoint's shader folder. The session keeps
    // it, so window mode can hot-reload it; the reference stays valid.
    // `generated`: files the chapter wrote itself, which #include finds by name first.
    ShaderProgram& loadCompute(const std::string& fileName, GeneratedFiles generated = {});
    // The same for a program of several stages, e.g. a fragment and a vertex shader
    // (the GL 3.3 appendix draws instead of dispatching). Messages name the first.
    ShaderProgram& loadProgram(const std::vector<ShaderStage>& stages);

    // Runs `render`, waits for the GPU, and records wall_ms and gpu_ms; a step of it
    // that never finishes ends the program (course/gpu_watchdog.h).
    void timeRender(const std::function<void()>& render);
    // The same for a render that adds --spp samples and counts them in `samplesDone`:
    // on a terminal, a long render shows its progress (course/render_progress.h).
    void timeRender(const std::function<void()>& render, const unsigned& samplesDone);

    // The end of a render. Headless: writes the image to --out (default
    // <chapter>.png) and prints its path. Window: shows it until Esc, the close button,
    // Ctrl+C (or SIGTERM) or --frames, then writes --out if given; before each frame
    // it looks for edited shaders, and after one is hot-reloaded calls `render` again
    // (which should start the picture over); then calls `eachFrame` (a progressive
    // renderer adds samples there). F12 saves a screenshot as a PNG. With --verbose it
    // says what it does: the files it watches, the first frame drawn and the first
    // after each reload, and the number of frames at the end.
    void finish(const ImageBuffer& image, const std::function<void()>& render = {},
                const std::function<void(int frame)>& eachFrame = {});

    // What the eye sees, where it differs from the linear image (an exposure and a tone
    // mapping): `toDisplay` fills `display` from the image, with values the
    // window and a PNG show as they are (sRGB-encoding them); finish() calls it before
    // each frame is drawn and before a PNG is written. A PFM is the linear image still.
    void setDisplay(const ImageBuffer& display, std::function<void()> toDisplay);

private:
    ShaderProgram::Reload reloadChangedShaders();

    Options options_;
    ChapterPaths chapter_;
    std::string shaderDir_;
    std::unique_ptr<GlContext> context_;
    std::list<ShaderProgram> programs_;  // a list: references stay valid as it grows
    Stats stats_;
    const ImageBuffer* display_ = nullptr;
    std::function<void()> toDisplay_;
};

// Parses the command line, makes the session, runs `body`, and turns every Failure
// into its message and exit code. --json prints the statistics at the end.
int runChapter(CommandLine& cli, int argc, char** argv, const ChapterPaths& chapter,
               GlVersion required, const std::function<void(Session&)>& body);

#ifdef COURSE_CHAPTER_NAME
inline int run(CommandLine& cli, int argc, char** argv,
               const std::function<void(Session&)>& body, GlVersion required = {}) {
    return runChapter(cli, argc, argv,
                      {COURSE_CHAPTER_NAME, COURSE_SHADER_DIR, COURSE_ASSET_DIR}, required,
                      body);
}
#endif

}  // namespace course
