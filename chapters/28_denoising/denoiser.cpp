#include "denoiser.h"

#include <cmath>
#include <cstdio>
#include <utility>
#include <vector>

#include "course/image_file.h"

namespace {
constexpr size_t kVec4 = 4 * sizeof(float);

int filterCode(const std::string& name) {
    return name == "box"        ? FILTER_BOX
           : name == "gaussian" ? FILTER_GAUSSIAN
           : name == "features" ? FILTER_FEATURES
                                : FILTER_ATROUS;
}
}  // namespace

void declareDenoiseOptions(course::CommandLine& cli, DenoiseOptions& options) {
    cli.choice("--denoise", "how the picture is cleaned of noise: not at all, a 5 x 5 box, "
               "a wide blur (the a-trous passes without weights), the features' weights "
               "(depth, normal), or the edge-avoiding a-trous filter (and luminance)",
               {"none", "box", "gaussian", "features", "atrous"}, &options.filter);
    cli.option("--denoise-passes", "N", "filtering passes, their taps 1, 2, 4, ... pixels "
               "apart (box: always one)", &options.passes, 1, 10);
    cli.option("--aux-out", "PREFIX", "also write the denoiser's feature buffers: "
             "PREFIX_albedo.pfm, _normal.pfm, _depth.pfm, _depth_spread.pfm, _emitted.pfm, "
             "_illumination.pfm, _variance.pfm", &options.auxOut);
    options.weights.depthSigma = 1.0f;
    options.weights.normalPower = 4.0f;
    options.weights.luminanceSigma = 1.5f;
}

Denoiser::Denoiser(course::Session& session, int width, int height,
                   const DenoiseOptions& options)
    : options_(options), stats_(session.stats()), width_(width), height_(height),
      program_(session.loadCompute("denoise.comp")),
      features_(size_t(width) * height * 3 * kVec4),
      reflected_(size_t(width) * height * kVec4),
      filtered_(size_t(width) * height * kVec4),
      filteredOut_(size_t(width) * height * kVec4),
      featureTexels_(features_, "the feature buffer"),
      reflectedTexels_(reflected_, "the reflected light's buffer"),
      denoised_(width, height), parameters_(sizeof(gpu::DenoiseParameters)) {
    // path.comp writes the first two through image units, denoise.comp reads them.
    featureTexels_.bindImage(FEATURES_UNIT);
    reflectedTexels_.bindImage(REFLECTED_UNIT);
    features_.bindStorage(FEATURES_BINDING);
    reflected_.bindStorage(REFLECTED_BINDING);
    denoised_.pixels.bindStorage(DENOISED_BINDING);
    if (!options.auxOut.empty()) course::checkOutputPath(options.auxOut + "_albedo.pfm");
}

void Denoiser::dispatch(int stage, unsigned samples, unsigned step) {
    gpu::DenoiseParameters parameters = options_.weights;
    parameters.filterSize = glm::uvec2(width_, height_);
    parameters.samples = samples;
    parameters.tapStep = step;
    parameters.stage = stage;
    parameters.filterKind = filterCode(options_.filter);
    parameters_.write(&parameters, sizeof parameters);
    parameters_.bindUniform(DENOISE_BINDING);
    filtered_.bindStorage(FILTERED_BINDING);
    filteredOut_.bindStorage(FILTERED_OUT_BINDING);
    glMemoryBarrier(kShaderWrites);
    program_.dispatchCovering(width_, height_);
}

// --8<-- [start:run]
void Denoiser::run(unsigned samples) {
    if (!enabled() || samples == 0) return;
    course::GpuTimer timer;
    timer.begin();
    dispatch(STAGE_GATHER, samples);  // the means and their variance, into filteredOut_
    std::swap(filtered_, filteredOut_);
    const int passes = options_.filter == "box" ? 1 : options_.passes;
    for (int pass = 0; pass < passes; ++pass) {
        // BEGIN SOLUTION the pass's taps 1, 2, 4, ... pixels apart
        dispatch(STAGE_FILTER, samples, 1u << pass);
        // STUB: dispatch(STAGE_FILTER, samples, 1u);
        // END SOLUTION
        std::swap(filtered_, filteredOut_);
    }
    dispatch(STAGE_FINISH, samples);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
    timer.end();
    stats_.set("denoise_ms", timer.milliseconds());
}
// --8<-- [end:run]

void Denoiser::writeAuxiliary(unsigned samples) {
    if (options_.auxOut.empty()) return;
    glMemoryBarrier(kShaderWrites);
    std::vector<float> features = features_.readAll<float>();
    dispatch(STAGE_GATHER, samples);  // the variance, as the filter's first pass sees it
    std::vector<float> gathered = filteredOut_.readAll<float>();
    const size_t pixels = size_t(width_) * height_;
    auto write = [&](const char* name, auto texel) {
        course::Image image{width_, height_, std::vector<float>(pixels * 4, 1.0f)};
        for (size_t i = 0; i < pixels; ++i)
            for (int c = 0; c < 3; ++c) image.rgba[4 * i + c] = texel(i, c);
        std::string path = options_.auxOut + "_" + name + ".pfm";
        course::writeImage(path, image);
        std::printf("%s\n", path.c_str());
    };
    write("albedo", [&](size_t i, int c) { return features[12 * i + c]; });
    write("normal", [&](size_t i, int c) { return 0.5f + 0.5f * features[12 * i + 4 + c]; });
    write("depth", [&](size_t i, int) { return features[12 * i + 3]; });
    write("depth_spread", [&](size_t i, int) { return std::sqrt(features[12 * i + 7]); });
    write("emitted", [&](size_t i, int c) { return features[12 * i + 8 + c]; });
    write("illumination", [&](size_t i, int c) { return gathered[4 * i + c]; });
    write("variance", [&](size_t i, int) { return gathered[4 * i + 3]; });
}
