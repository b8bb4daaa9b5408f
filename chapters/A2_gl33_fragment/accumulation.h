// Progressive rendering without image load/store or storage buffers: two framebuffers
// that take turns (ping-pong). A pass draws into one of them while its fragment shader
// reads what the previous pass left in the other; then they swap roles. Each holds,
// per pixel, what chapter 12 kept in storage buffers between dispatches:
//   MEAN_OUTPUT    GL_RGBA32F   the running mean of the samples, linear RGB
//   RANDOM_OUTPUT  GL_RGBA32UI  the generator's state (random.glsl)
//   RAYS_OUTPUT    GL_R32UI     the rays traced so far
#pragma once
#include <cstdint>
#include <vector>

#include "course/gl.h"
#include "course/gpu_buffer.h"
#include "course/shader_program.h"

class Accumulation {
public:
    // Exit code 4 when this GL's textures cannot be that large (GL_MAX_TEXTURE_SIZE).
    Accumulation(int width, int height);
    ~Accumulation();
    Accumulation(const Accumulation&) = delete;
    Accumulation& operator=(const Accumulation&) = delete;

    // One pass of `program` (a fragment shader over the whole image) into the
    // framebuffer the last pass did not write; its textures are on the units shared.h
    // names, for the shader's previousMean, previousRandom and previousRays.
    void draw(const course::ShaderProgram& program);

    // The newest running mean, copied into `image`'s buffer on the GPU.
    void copyMeanTo(course::ImageBuffer& image) const;
    // The newest ray counts, row 0 at the top.
    std::vector<uint32_t> readRayCounts() const;

private:
    struct Target {
        GLuint framebuffer = 0;
        GLuint textures[3] = {0, 0, 0};  // MEAN_OUTPUT, RANDOM_OUTPUT, RAYS_OUTPUT
    };
    Target targets_[2];
    int newest_ = 0;  // the target the last pass wrote
    int width_, height_;
    GLuint emptyVertexArray_ = 0;  // a core profile draw needs one bound, even unused
};
