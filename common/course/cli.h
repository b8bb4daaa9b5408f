// The command line every chapter program shares (book/docs/maintainers.md), plus the
// few options a chapter declares for itself. Bad usage throws Failure(BadUsage) with a
// message.
#pragma once
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include <glm/fwd.hpp>

namespace course {

enum class Backend { Auto, Egl, OsMesa, Glfw };

struct Options {
    bool window = false;        // --window / --headless
    std::string outPath;        // --out FILE (.png or .pfm); empty: chapter default
    int width = 640;            // --width
    int height = 480;           // --height
    int spp = 1;                // --spp: samples (or dispatches) per pixel
    uint32_t seed = 1;          // --seed
    std::string scene;          // --scene NAME or FILE
    std::string objPath;        // --obj FILE (chapters that load meshes)
    Backend backend = Backend::Auto;
    int gpu = -1;               // --gpu N, or COURSE_GPU=N: the EGL device to render on
    bool gpuFromEnvironment = false;  // COURSE_GPU: used where EGL is, ignored elsewhere
    bool json = false;          // --json: one line of stats on stdout
    bool verbose = false;       // --verbose
    bool probeLoopLimit = false;  // --probe-loop-limit: measure it, print it, stop
    int frames = 0;             // --frames N: window mode closes after N frames
    std::string shaderDir;      // --shader-dir: overrides the folder fixed at build time
    std::string assetDir;       // --asset-dir
};

// An option that only one chapter has, e.g. --direct or --dispatch 2d.
struct ChapterOption {
    std::string name;  // "--direct"
    std::string help;
    std::string valueName;  // empty for a flag
    std::function<void(const std::string& value)> apply;
};

class CommandLine {
public:
    explicit CommandLine(std::string summary) : summary_(std::move(summary)) {}
    void setProgramName(std::string name) { program_ = std::move(name); }

    void flag(const std::string& name, const std::string& help, bool* target);
    void option(const std::string& name, const std::string& valueName,
                const std::string& help, int* target, int minValue, int maxValue);
    void option(const std::string& name, const std::string& valueName,
                const std::string& help, std::string* target);
    // A finite number ("0.035"), or three of them with commas ("0,-0.25,-1"); --help
    // adds the target's value when declared as the default.
    void option(const std::string& name, const std::string& valueName,
                const std::string& help, float* target);
    void option(const std::string& name, const std::string& valueName,
                const std::string& help, glm::vec3* target);
    void choice(const std::string& name, const std::string& help,
                const std::vector<std::string>& choices, std::string* target);
    // The same for an enum whose values are 0, 1, ... in the order of `choices`: the
    // name is compared once, here, and the program compares values.
    template <typename Enum>
    void choice(const std::string& name, const std::string& help,
                const std::vector<std::string>& choices, Enum* target) {
        choiceIndex(name, help, choices, [target](size_t i) { *target = Enum(i); });
    }
    // Which shared options this chapter accepts beyond the basics (e.g. --obj from 07).
    void acceptObj() { acceptObj_ = true; }
    void acceptScene() { acceptScene_ = true; }
    // A chapter that makes no picture: --out, --width, --height are refused.
    void withoutImage() { makesImage_ = false; }

    // Parses argv. --help prints usage and returns false (the caller exits 0).
    bool parse(int argc, const char* const* argv, Options& options) const;
    std::string usage() const;

private:
    void choiceIndex(const std::string& name, const std::string& help,
                     const std::vector<std::string>& choices,
                     std::function<void(size_t index)> set);
    std::string program_, summary_;
    std::vector<ChapterOption> extra_;
    bool acceptObj_ = false, acceptScene_ = false, makesImage_ = true;
};

// Limits that keep a typo from asking for a 40 GB buffer.
constexpr int kMaxImageSide = 16384;
constexpr long long kMaxImagePixels = 4096LL * 4096LL;
constexpr int kMaxSpp = 1 << 20;
constexpr int kMaxGpu = 15;  // EGL lists at most 16 devices here (egl_context.cpp)

}  // namespace course
