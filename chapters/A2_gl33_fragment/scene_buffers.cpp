#include "scene_buffers.h"

#include <algorithm>
#include <cstdlib>

#include "course/error.h"

namespace {

// The largest buffer texture, in texels: at least 65536 in any GL 3.3, in practice
// hundreds of millions (2^27 on llvmpipe).
long long maxTextureBufferTexels() {
    GLint limit = 0;
    glGetIntegerv(GL_MAX_TEXTURE_BUFFER_SIZE, &limit);
    if (const char* lower = std::getenv("COURSE_MAX_TEXTURE_BUFFER_TEXELS"))
        return std::min<long long>(limit, std::atoll(lower));
    return limit;
}

}  // namespace

// --8<-- [start:upload]
SceneBuffers::SceneBuffers(const GpuScene& scene, const std::string& scenePath) {
    // 1. The shapes: a buffer of RGBA32F texels, seen by the shader through a buffer
    //    texture. Any invocation may read any texel (texelFetch), and the limit on its
    //    size is the GL's largest buffer texture, counted in texels.
    const long long limit = maxTextureBufferTexels();
    if (static_cast<long long>(scene.texels.size()) > limit)
        course::fail(course::ExitCode::GlProblem,
                     scenePath + ": " + std::to_string(scene.shapeCount()) + " shapes need " +
                         std::to_string(scene.texels.size()) + " texels, but this GL's "
                         "buffer textures hold at most " + std::to_string(limit) +
                         " (GL_MAX_TEXTURE_BUFFER_SIZE)");
    glGenBuffers(1, &texelBuffer_);
    glBindBuffer(GL_TEXTURE_BUFFER, texelBuffer_);
    // A scene with no shapes of a kind still gets a texel: a zero-sized buffer is an error.
    const glm::vec4 none(0.0f);
    const bool empty = scene.texels.empty();
    glBufferData(GL_TEXTURE_BUFFER, empty ? sizeof none : scene.texels.size() * sizeof none,
                 empty ? &none : scene.texels.data(), GL_STATIC_DRAW);
    glGenTextures(1, &texelTexture_);
    glBindTexture(GL_TEXTURE_BUFFER, texelTexture_);
    glTexBuffer(GL_TEXTURE_BUFFER, GL_RGBA32F, texelBuffer_);  // 4 floats per texel

    // 2. Materials and emitters: a uniform block. Every invocation reads the same few
    //    entries, which GPUs keep close (constant caches); the limit is small and fixed,
    //    GL_MAX_UNIFORM_BLOCK_SIZE bytes (at least 16 KiB), hence fixed-size arrays.
    GLint maxBlockBytes = 0;
    glGetIntegerv(GL_MAX_UNIFORM_BLOCK_SIZE, &maxBlockBytes);
    if (static_cast<long long>(sizeof(gpu::SceneBlock)) > maxBlockBytes)
        course::fail(course::ExitCode::GlProblem,
                     "the uniform block has " + std::to_string(sizeof(gpu::SceneBlock)) +
                         " bytes, but this GL allows " + std::to_string(maxBlockBytes) +
                         " (GL_MAX_UNIFORM_BLOCK_SIZE): lower MAX_MATERIALS in shared.h");
    glGenBuffers(1, &uniformBuffer_);
    glBindBuffer(GL_UNIFORM_BUFFER, uniformBuffer_);
    glBufferData(GL_UNIFORM_BUFFER, sizeof(gpu::SceneBlock), scene.block.get(), GL_STATIC_DRAW);
}
// --8<-- [end:upload]

SceneBuffers::~SceneBuffers() {
    glDeleteTextures(1, &texelTexture_);
    glDeleteBuffers(1, &texelBuffer_);
    glDeleteBuffers(1, &uniformBuffer_);
}

// --8<-- [start:bind]
void SceneBuffers::bind(const course::ShaderProgram& program) const {
    // The block's binding point is set by name (GLSL 3.30 has no layout(binding)); a
    // program that does not use the block (seed.frag) has none to set.
    GLuint block = glGetUniformBlockIndex(program.id(), "SceneBlock");
    if (block != GL_INVALID_INDEX)
        glUniformBlockBinding(program.id(), block, SCENE_BLOCK_BINDING);
    glBindBufferBase(GL_UNIFORM_BUFFER, SCENE_BLOCK_BINDING, uniformBuffer_);
    glActiveTexture(GL_TEXTURE0 + PRIMITIVES_UNIT);
    glBindTexture(GL_TEXTURE_BUFFER, texelTexture_);
    program.set("primitives", PRIMITIVES_UNIT);
}
// --8<-- [end:bind]
