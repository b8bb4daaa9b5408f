#include "temporal.h"

#include <cstdio>
#include <cstring>
#include <vector>

#include "course/error.h"
#include "course/image_file.h"

namespace {
constexpr size_t kVec4 = 4 * sizeof(float);

void copyBuffer(const course::GpuBuffer& from, const course::GpuBuffer& to) {
    glBindBuffer(GL_COPY_READ_BUFFER, from.id());
    glBindBuffer(GL_COPY_WRITE_BUFFER, to.id());
    glCopyBufferSubData(GL_COPY_READ_BUFFER, GL_COPY_WRITE_BUFFER, 0, 0, from.bytes());
}
}  // namespace

void declareTemporalOptions(course::CommandLine& cli, TemporalOptions& options) {
    cli.option("--blend", "A", "while the camera moves, each frame's least share of the "
               "blend, from 0 to 1 (1: no history)", &options.blend);
    cli.option("--move", "X,Y,Z", "the camera's step from one frame to the next, in "
               "metres (headless with --move-frames, or each frame of the window)",
               &options.move);
    cli.option("--move-frames", "N", "headless: draw N frames of --spp samples, stepping "
               "--move between them; --out is the last", &options.moveFrames, 1, 1000);
    cli.option("--frames-out", "PREFIX", "headless: also write every frame's picture, "
               "PREFIX_01.pfm, PREFIX_02.pfm, ...", &options.framesOut);
}

void checkTemporalOptions(const TemporalOptions& options) {
    if (!(options.blend >= 0.0f && options.blend <= 1.0f))
        course::fail(course::ExitCode::BadUsage, "--blend: a share, from 0 to 1");
    if (!options.framesOut.empty()) course::checkOutputPath(options.framesOut + "_01.pfm");
}

TemporalAccumulator::TemporalAccumulator(course::Session& session, int width, int height,
                                         float minimumBlend,
                                         const course::GpuBuffer& blendedFeatures,
                                         const course::GpuBuffer& blendedReflected)
    : program_(session.loadCompute("temporal.comp")), width_(width), height_(height),
      minimumBlend_(minimumBlend), blendedFeatures_(blendedFeatures),
      blendedReflected_(blendedReflected),
      frameFeatures_(size_t(width) * height * 3 * kVec4),
      frameReflected_(size_t(width) * height * kVec4),
      historyFeatures_(size_t(width) * height * 3 * kVec4),
      historyReflected_(size_t(width) * height * kVec4),
      frameFeatureTexels_(frameFeatures_, "the frame's feature buffer"),
      frameReflectedTexels_(frameReflected_, "the frame's reflected light's buffer"),
      blended_(width, height), parameters_(sizeof(gpu::TemporalParameters)) {
    // path.comp writes the frame's means through image units; temporal.comp reads them.
    frameFeatureTexels_.bindImage(FEATURES_UNIT);
    frameReflectedTexels_.bindImage(REFLECTED_UNIT);
    frameFeatures_.bindStorage(FRAME_FEATURES_BINDING);
    frameReflected_.bindStorage(FRAME_REFLECTED_BINDING);
    historyFeatures_.bindStorage(HISTORY_FEATURES_BINDING);
    historyReflected_.bindStorage(HISTORY_REFLECTED_BINDING);
    blended_.pixels.bindStorage(BLENDED_PIXELS_BINDING);
}

// --8<-- [start:blend]
void TemporalAccumulator::blend(const gpu::ThinLensCamera& camera, unsigned samples) {
    // Standing still, each pixel keeps its own history whole: the plain mean of all.
    const bool moved = hasHistory_ && std::memcmp(&camera, &before_, sizeof camera) != 0;
    gpu::TemporalParameters parameters{};
    parameters.before = before_;
    parameters.temporalSize = glm::uvec2(width_, height_);
    parameters.frameSamples = samples;
    parameters.cameraMoved = moved;
    parameters.hasHistory = hasHistory_;
    parameters.minimumBlend = moved ? minimumBlend_ : 0.0f;
    parameters.planeTolerance = 0.02f;
    parameters.normalAgreement = 0.9f;
    parameters_.write(&parameters, sizeof parameters);
    parameters_.bindUniform(TEMPORAL_BINDING);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
    program_.dispatchCovering(width_, height_);
    // The blend is the next frame's history, seen from this camera.
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT | GL_SHADER_STORAGE_BARRIER_BIT);
    copyBuffer(blendedFeatures_, historyFeatures_);
    copyBuffer(blendedReflected_, historyReflected_);
    before_ = camera;
    hasHistory_ = true;
    lastSamples_ = samples;
}
// --8<-- [end:blend]

int TemporalAccumulator::freshPixels() const {
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    std::vector<float> features = historyFeatures_.readAll<float>();
    int fresh = 0;
    for (size_t i = 11; i < features.size(); i += 12)  // emitted.w: s
        fresh += features[i] * float(lastSamples_) > 0.999f;
    return fresh;
}

void writeFrame(const std::string& prefix, int frame, const course::ImageBuffer& picture) {
    if (prefix.empty()) return;
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    course::Image image{picture.width, picture.height, picture.pixels.readAll<float>()};
    char number[16];
    std::snprintf(number, sizeof number, "_%02d.pfm", frame);
    course::writeImage(prefix + number, image);
    std::printf("%s%s\n", prefix.c_str(), number);
}
