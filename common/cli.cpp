#include "course/cli.h"

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <sstream>

#include <glm/glm.hpp>

#include "course/error.h"

namespace course {
namespace {

[[noreturn]] void badUsage(const std::string& message) {
    fail(ExitCode::BadUsage, message + " (see --help)");
}

long long parseInteger(const std::string& name, const std::string& text) {
    errno = 0;
    char* end = nullptr;
    long long value = std::strtoll(text.c_str(), &end, 10);
    if (text.empty() || *end != '\0' || errno == ERANGE)
        badUsage(name + " expects a whole number, got '" + text + "'");
    return value;
}

int parseBounded(const std::string& name, const std::string& text, long long lo,
                 long long hi) {
    long long value = parseInteger(name, text);
    if (value < lo || value > hi)
        badUsage(name + " must be between " + std::to_string(lo) + " and " +
                 std::to_string(hi) + ", got " + text);
    return static_cast<int>(value);
}

float parseFinite(const std::string& name, const std::string& text) {
    char* end = nullptr;
    const float value = std::strtof(text.c_str(), &end);
    if (text.empty() || *end != '\0' || !std::isfinite(value))
        badUsage(name + " expects a finite number, got '" + text + "'");
    return value;
}

// "x,y,z": exactly three finite numbers.
glm::vec3 parseVector(const std::string& name, const std::string& text) {
    std::vector<std::string> parts(1);
    for (char c : text) {
        if (c == ',')
            parts.emplace_back();
        else
            parts.back().push_back(c);
    }
    if (parts.size() != 3)
        badUsage(name + " expects three numbers x,y,z, got '" + text + "'");
    return {parseFinite(name, parts[0]), parseFinite(name, parts[1]),
            parseFinite(name, parts[2])};
}

// A default as --help shows it: "0.035", "0,-0.25,-1".
std::string shown(float value) {
    char text[32];
    std::snprintf(text, sizeof text, "%g", double(value));
    return text;
}

std::string shown(const glm::vec3& v) {
    return shown(v.x) + "," + shown(v.y) + "," + shown(v.z);
}

Backend parseBackend(const std::string& text) {
    if (text == "egl") return Backend::Egl;
    if (text == "osmesa") return Backend::OsMesa;
    if (text == "glfw") return Backend::Glfw;
    badUsage("--backend must be egl, osmesa or glfw, got '" + text + "'");
}

bool hasDisplay() {
    const char* x11 = std::getenv("DISPLAY");
    const char* wayland = std::getenv("WAYLAND_DISPLAY");
    return (x11 && *x11) || (wayland && *wayland);
}

}  // namespace

void CommandLine::flag(const std::string& name, const std::string& help, bool* target) {
    extra_.push_back({name, help, "", [target](const std::string&) { *target = true; }});
}

void CommandLine::option(const std::string& name, const std::string& valueName,
                         const std::string& help, int* target, int minValue,
                         int maxValue) {
    extra_.push_back({name, help, valueName, [=](const std::string& value) {
                          *target = parseBounded(name, value, minValue, maxValue);
                      }});
}

void CommandLine::option(const std::string& name, const std::string& valueName,
                         const std::string& help, std::string* target) {
    extra_.push_back(
        {name, help, valueName, [target](const std::string& value) { *target = value; }});
}

void CommandLine::option(const std::string& name, const std::string& valueName,
                         const std::string& help, float* target) {
    extra_.push_back({name, help + " (default " + shown(*target) + ")", valueName,
                      [=](const std::string& value) { *target = parseFinite(name, value); }});
}

void CommandLine::option(const std::string& name, const std::string& valueName,
                         const std::string& help, glm::vec3* target) {
    extra_.push_back({name, help + " (default " + shown(*target) + ")", valueName,
                      [=](const std::string& value) { *target = parseVector(name, value); }});
}

void CommandLine::choice(const std::string& name, const std::string& help,
                         const std::vector<std::string>& choices, std::string* target) {
    choiceIndex(name, help, choices, [=](size_t i) { *target = choices[i]; });
}

void CommandLine::choiceIndex(const std::string& name, const std::string& help,
                              const std::vector<std::string>& choices,
                              std::function<void(size_t index)> set) {
    std::string names;
    for (const auto& c : choices) names += (names.empty() ? "" : "|") + c;
    extra_.push_back({name, help, names, [=](const std::string& value) {
                          for (size_t i = 0; i < choices.size(); ++i)
                              if (choices[i] == value) {
                                  set(i);
                                  return;
                              }
                          badUsage(name + " must be one of " + names + ", got '" + value +
                                   "'");
                      }});
}

std::string CommandLine::usage() const {
    std::ostringstream out;
    out << "usage: " << program_ << " [options]\n" << summary_ << "\n\n"
        << "  --headless | --window   render off-screen (default without a display)\n"
        << "                          or show the image in a window\n";
    if (makesImage_)
        out << "  --out FILE              write the image: .png (8-bit sRGB), or .pfm or .exr\n"
            << "                          (linear floats)\n"
            << "  --width N, --height N   image size in pixels (1.." << kMaxImageSide << ")\n";
    out << "  --spp N                 samples per pixel\n"
        << "  --seed N                random seed\n";
    if (acceptScene_) out << "  --scene NAME|FILE       scene to render\n";
    if (acceptObj_) out << "  --obj FILE              render this OBJ mesh, framed automatically\n";
    out << "  --backend egl|osmesa|glfw  force a GL context backend\n"
        << "  --gpu N                 render headless on EGL device N (--verbose lists\n"
        << "                          them); COURSE_GPU=N does the same\n"
        << "  --json                  print one line of statistics as JSON on stdout\n"
        << "  --verbose               say what happens (backend, GL renderer, timings)\n"
        << "  --frames N              window mode: close after N frames\n"
        << "  --shader-dir DIR        load shaders from DIR instead of the built-in path\n"
        << "  --probe-loop-limit      measure how many loop iterations this GL lets a\n"
        << "                          shader invocation run, print it and stop\n";
    for (const auto& o : extra_) {
        std::string left = o.name + (o.valueName.empty() ? "" : " " + o.valueName);
        out << "  " << left << std::string(left.size() < 24 ? 24 - left.size() : 1, ' ')
            << o.help << "\n";
    }
    out << "\nexit codes: 0 ok, 1 check failed, 2 bad usage, 3 bad input file, "
           "4 GL problem\n";
    return out.str();
}

bool CommandLine::parse(int argc, const char* const* argv, Options& options) const {
    bool windowChosen = false;
    for (int i = 1; i < argc; ++i) {
        const std::string arg = argv[i];
        auto value = [&]() -> std::string {
            if (i + 1 >= argc) badUsage(arg + " needs a value");
            return argv[++i];
        };
        if (arg == "--help" || arg == "-h") {
            return false;
        } else if (arg == "--headless" || arg == "--window") {
            options.window = arg == "--window";
            windowChosen = true;
        } else if (!makesImage_ && (arg == "--out" || arg == "--width" || arg == "--height")) {
            badUsage(arg + ": " + program_ + " makes no image");
        } else if (arg == "--out") {
            options.outPath = value();
            if (options.outPath.empty()) badUsage("--out needs a file name");
        } else if (arg == "--width") {
            options.width = parseBounded(arg, value(), 1, kMaxImageSide);
        } else if (arg == "--height") {
            options.height = parseBounded(arg, value(), 1, kMaxImageSide);
        } else if (arg == "--spp") {
            options.spp = parseBounded(arg, value(), 1, kMaxSpp);
        } else if (arg == "--seed") {
            options.seed = static_cast<uint32_t>(
                parseInteger(arg, value()) & 0xffffffffLL);
        } else if (arg == "--scene" && acceptScene_) {
            options.scene = value();
        } else if (arg == "--obj" && acceptObj_) {
            options.objPath = value();
        } else if (arg == "--backend") {
            options.backend = parseBackend(value());
        } else if (arg == "--gpu") {
            options.gpu = parseBounded(arg, value(), 0, kMaxGpu);
        } else if (arg == "--json") {
            options.json = true;
        } else if (arg == "--verbose" || arg == "-v") {
            options.verbose = true;
        } else if (arg == "--probe-loop-limit") {
            options.probeLoopLimit = true;
        } else if (arg == "--frames") {
            options.frames = parseBounded(arg, value(), 1, 1 << 30);
        } else if (arg == "--shader-dir") {
            options.shaderDir = value();
        } else if (arg == "--asset-dir") {
            options.assetDir = value();
        } else {
            bool known = false;
            for (const auto& o : extra_) {
                if (o.name != arg) continue;
                o.apply(o.valueName.empty() ? std::string() : value());
                known = true;
                break;
            }
            if (!known) badUsage("unknown option '" + arg + "'");
        }
    }
    const char* gpuVariable = std::getenv("COURSE_GPU");
    if (options.gpu < 0 && gpuVariable && *gpuVariable) {
        options.gpu = parseBounded("COURSE_GPU", gpuVariable, 0, kMaxGpu);
        options.gpuFromEnvironment = true;
    }
    const bool gpuAsked = options.gpu >= 0 && !options.gpuFromEnvironment;
    if (gpuAsked && (options.backend == Backend::OsMesa || options.backend == Backend::Glfw))
        badUsage("--gpu chooses an EGL device; not with --backend osmesa or glfw");
    if (gpuAsked && windowChosen && options.window)
        badUsage("--gpu chooses an EGL device for headless rendering; a window renders on "
                 "the display's GPU");
    // Without --headless/--window: a window when there is a display to show it on
    // (--gpu: headless).
    if (!windowChosen)
        options.window = !gpuAsked && (options.backend == Backend::Glfw || hasDisplay());
    if (options.window && options.backend != Backend::Auto && options.backend != Backend::Glfw)
        badUsage("--window needs the glfw backend");
    if (static_cast<long long>(options.width) * options.height > kMaxImagePixels)
        badUsage("image of " + std::to_string(options.width) + "x" +
                 std::to_string(options.height) + " pixels is larger than the " +
                 std::to_string(kMaxImagePixels) + " pixels this course allows");
    return true;
}

}  // namespace course
