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
    // What --out writes and the window shows: denoised, or as traced (--denoise none).
    const course::ImageBuffer& picture(const course::ImageBuffer& pathTraced) const {
        return enabled() ? denoised_ : pathTraced;
    }
    // Filters the means of `samples` samples into picture(), timed as denoise_ms (--json).
    void run(unsigned samples);
    // --aux-out PREFIX: what the filter starts from, as PFMs (--help names them), printed.
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
