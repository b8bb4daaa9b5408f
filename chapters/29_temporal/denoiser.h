// The denoiser (denoise.comp): the buffers of first surfaces and illumination it reads
// (temporal.comp's blend of the frames), the filter's passes over them, and the denoised
// picture.
#pragma once
#include <string>

#include "course/cli.h"
#include "course/gpu_buffer.h"
#include "course/session.h"
#include "course/stats.h"
#include "shared.h"  // gpu::DenoiseParameters, FILTER_*

// What a dispatch writes that the next must see: buffers, and texels through image units.
constexpr GLbitfield kShaderWrites =
    GL_SHADER_STORAGE_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT;

struct DenoiseOptions {
    std::string filter = "atrous";  // --denoise: none, box, gaussian, features, atrous
    int passes = 3;                 // --denoise-passes
    std::string auxOut;             // --aux-out PREFIX: the feature buffers as PFMs
    gpu::DenoiseParameters weights{};  // the weights' sigmas (--depth-sigma, ...)
};

void declareDenoiseOptions(course::CommandLine& cli, DenoiseOptions& options);

class Denoiser {
public:
    Denoiser(course::Session& session, int width, int height, const DenoiseOptions& options);

    bool enabled() const { return options_.filter != "none"; }
    // The picture --out writes and the window shows: the denoised one, or the path
    // tracer's own with --denoise none.
    const course::ImageBuffer& picture(const course::ImageBuffer& pathTraced) const {
        return enabled() ? denoised_ : pathTraced;
    }
    // Filters the means of `samples` samples into picture(); its GPU time goes to the
    // statistics as denoise_ms (the bench weighs it in samples of the path tracer).
    void run(unsigned samples);
    // --aux-out PREFIX: what the filter starts from, each PFM printed: PREFIX_albedo,
    // _normal (0.5 + 0.5 n), _depth, _depth_spread, _emitted, _illumination,
    // _variance (of the illumination's luminance) and _history (1/s: the samples the
    // blend is worth).
    void writeAuxiliary(unsigned samples);
    // What it filters: the first surfaces' features and the light they reflect.
    const course::GpuBuffer& features() const { return features_; }
    const course::GpuBuffer& reflected() const { return reflected_; }

private:
    void dispatch(int stage, unsigned samples, unsigned step = 1);

    DenoiseOptions options_;
    course::Stats& stats_;
    int width_, height_;
    course::ShaderProgram& program_;
    course::GpuBuffer features_, reflected_, filtered_, filteredOut_;
    course::ImageBuffer denoised_;
    course::GpuBuffer parameters_;
};
