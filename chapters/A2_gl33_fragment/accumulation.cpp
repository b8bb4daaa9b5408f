#include "accumulation.h"

#include <string>

#include "course/error.h"
#include "course/gpu_watchdog.h"
#include "shared.h"

namespace {

// Internal format, then the format and type glReadPixels uses, per output.
struct Format {
    GLenum internal, format, type;
};
constexpr Format kFormats[3] = {
    {GL_RGBA32F, GL_RGBA, GL_FLOAT},                     // MEAN_OUTPUT
    {GL_RGBA32UI, GL_RGBA_INTEGER, GL_UNSIGNED_INT},     // RANDOM_OUTPUT
    {GL_R32UI, GL_RED_INTEGER, GL_UNSIGNED_INT},         // RAYS_OUTPUT
};
constexpr GLenum kUnits[3] = {PREVIOUS_MEAN_UNIT, PREVIOUS_RANDOM_UNIT, PREVIOUS_RAYS_UNIT};
constexpr const char* kSamplers[3] = {"previousMean", "previousRandom", "previousRays"};

}  // namespace

// --8<-- [start:targets]
Accumulation::Accumulation(int width, int height) : width_(width), height_(height) {
    GLint maxSide = 0;
    glGetIntegerv(GL_MAX_TEXTURE_SIZE, &maxSide);
    if (width > maxSide || height > maxSide)
        course::fail(course::ExitCode::GlProblem,
                     "this GL's textures are at most " + std::to_string(maxSide) +
                         " pixels wide and high (GL_MAX_TEXTURE_SIZE)");
    for (Target& target : targets_) {
        glGenFramebuffers(1, &target.framebuffer);
        glBindFramebuffer(GL_FRAMEBUFFER, target.framebuffer);
        glGenTextures(3, target.textures);
        for (int output = 0; output < 3; ++output) {
            glBindTexture(GL_TEXTURE_2D, target.textures[output]);
            // No mipmaps and no filtering: texelFetch reads exact texels, but a texture
            // whose filter expects mipmaps it does not have is incomplete and reads 0.
            glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
            glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
            const Format& f = kFormats[output];
            glTexImage2D(GL_TEXTURE_2D, 0, f.internal, width, height, 0, f.format, f.type,
                         nullptr);
            glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0 + output,
                                   GL_TEXTURE_2D, target.textures[output], 0);
        }
        // Fragment output N (layout(location = N)) goes to colour attachment N.
        const GLenum outputs[3] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1,
                                   GL_COLOR_ATTACHMENT2};
        glDrawBuffers(3, outputs);
        if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
            course::fail(course::ExitCode::GlProblem,
                         "this GL cannot render to RGBA32F, RGBA32UI and R32UI textures "
                         "together (framebuffer incomplete)");
    }
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    glGenVertexArrays(1, &emptyVertexArray_);
}
// --8<-- [end:targets]

Accumulation::~Accumulation() {
    glDeleteVertexArrays(1, &emptyVertexArray_);
    for (Target& target : targets_) {
        glDeleteFramebuffers(1, &target.framebuffer);
        glDeleteTextures(3, target.textures);
    }
}

// --8<-- [start:draw]
void Accumulation::draw(const course::ShaderProgram& program) {
    const Target& previous = targets_[newest_];
    const Target& next = targets_[1 - newest_];
    for (int output = 0; output < 3; ++output) {
        glActiveTexture(GL_TEXTURE0 + kUnits[output]);
        glBindTexture(GL_TEXTURE_2D, previous.textures[output]);
        if (program.hasUniform(kSamplers[output]))  // seed.frag reads none of them
            program.set(kSamplers[output], int(kUnits[output]));
    }
    glBindFramebuffer(GL_FRAMEBUFFER, next.framebuffer);
    glViewport(0, 0, width_, height_);
    program.use();
    glBindVertexArray(emptyVertexArray_);
    glDrawArrays(GL_TRIANGLES, 0, 3);  // one triangle over the image: a fragment a pixel
    course::gpuStepQueued();           // a sample done: the watchdog's sign of progress
    glBindFramebuffer(GL_FRAMEBUFFER, 0);  // the window's own, for the display
    newest_ = 1 - newest_;
}
// --8<-- [end:draw]

// --8<-- [start:read]
void Accumulation::copyMeanTo(course::ImageBuffer& image) const {
    glBindFramebuffer(GL_READ_FRAMEBUFFER, targets_[newest_].framebuffer);
    glReadBuffer(GL_COLOR_ATTACHMENT0 + MEAN_OUTPUT);
    // With a buffer bound to GL_PIXEL_PACK_BUFFER, glReadPixels writes into it (the last
    // argument is an offset there): the copy stays on the GPU. Framebuffer row 0 is the
    // image's top row (path.frag), so the rows arrive in the order of an image file.
    glBindBuffer(GL_PIXEL_PACK_BUFFER, image.pixels.id());
    glReadPixels(0, 0, width_, height_, GL_RGBA, GL_FLOAT, nullptr);
    glBindBuffer(GL_PIXEL_PACK_BUFFER, 0);
    glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
}
// --8<-- [end:read]

std::vector<uint32_t> Accumulation::readRayCounts() const {
    std::vector<uint32_t> counts(size_t(width_) * size_t(height_));
    glBindFramebuffer(GL_READ_FRAMEBUFFER, targets_[newest_].framebuffer);
    glReadBuffer(GL_COLOR_ATTACHMENT0 + RAYS_OUTPUT);
    glReadPixels(0, 0, width_, height_, GL_RED_INTEGER, GL_UNSIGNED_INT, counts.data());
    glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
    return counts;
}
