// Temporal accumulation (temporal.comp): each frame's means, the history (the frames
// before, and the camera that saw them) and their blend, which the denoiser filters.
#pragma once
#include <string>

#include "course/cli.h"
#include "course/gpu_buffer.h"
#include "course/session.h"
#include "shared.h"  // gpu::TemporalParameters, gpu::ThinLensCamera

struct TemporalOptions {
    float blend = 0.2f;       // --blend: this frame's least share while the camera moves
    glm::vec3 move{0.0f};     // --move X,Y,Z: the camera's step from frame to frame
    int moveFrames = 1;       // --move-frames N: headless, the frames drawn
    std::string framesOut;    // --frames-out PREFIX: every frame's picture, PREFIX_NN.pfm
};

void declareTemporalOptions(course::CommandLine& cli, TemporalOptions& options);
// --blend outside 0..1 is bad usage (exit code 2); --frames-out's folder must exist.
void checkTemporalOptions(const TemporalOptions& options);

class TemporalAccumulator {
public:
    // `blendedFeatures` and `blendedReflected` are the denoiser's inputs: the blend is
    // written there (FEATURES_BINDING, REFLECTED_BINDING) and copied into the history.
    TemporalAccumulator(course::Session& session, int width, int height, float minimumBlend,
                        const course::GpuBuffer& blendedFeatures,
                        const course::GpuBuffer& blendedReflected);

    // Blends the frame just drawn (`samples` samples, seen by `camera`) into the history.
    void blend(const gpu::ThinLensCamera& camera, unsigned samples);
    // The next frame has no history (a new render).
    void restart() { hasHistory_ = false; }
    // The blend's radiance: the picture, before denoising.
    const course::ImageBuffer& picture() const { return blended_; }
    // Pixels of the last blend that found no history (s is 1/k there).
    int freshPixels() const;

private:
    course::ShaderProgram& program_;
    int width_, height_;
    float minimumBlend_;
    const course::GpuBuffer &blendedFeatures_, &blendedReflected_;
    course::GpuBuffer frameFeatures_, frameReflected_, historyFeatures_, historyReflected_;
    course::BufferTexture frameFeatureTexels_, frameReflectedTexels_;
    course::ImageBuffer blended_;
    course::GpuBuffer parameters_;
    gpu::ThinLensCamera before_{};
    bool hasHistory_ = false;
    unsigned lastSamples_ = 1;
};

// --frames-out: a frame's picture as PREFIX_NN.pfm (NN from 01); nothing without PREFIX.
void writeFrame(const std::string& prefix, int frame, const course::ImageBuffer& picture);
