#include "course/gpu_buffer.h"

#include <string>
#include <utility>

#include "course/error.h"

namespace course {

// Creating, filling and reading a buffer binds it to GL_COPY_WRITE_BUFFER (GL 3.1), a
// target that implies no use: GL_SHADER_STORAGE_BUFFER would not exist on the GL 3.3
// appendix's contexts, which use the same buffers as pixel buffers.
GpuBuffer::GpuBuffer(size_t bytes, const void* initialData) : bytes_(bytes) {
    glGenBuffers(1, &id_);
    glBindBuffer(GL_COPY_WRITE_BUFFER, id_);
    // GL_DYNAMIC_COPY: written and read by the GPU, copied back now and then.
    glBufferData(GL_COPY_WRITE_BUFFER, static_cast<GLsizeiptr>(bytes), initialData,
                 GL_DYNAMIC_COPY);
    if (glGetError() == GL_OUT_OF_MEMORY)
        fail(ExitCode::GlProblem, "out of GPU memory allocating a buffer of " +
                                      std::to_string(bytes >> 20) + " MiB");
}

GpuBuffer::~GpuBuffer() {
    if (id_) glDeleteBuffers(1, &id_);
}

GpuBuffer::GpuBuffer(GpuBuffer&& other) noexcept
    : id_(std::exchange(other.id_, 0)), bytes_(std::exchange(other.bytes_, 0)) {}

GpuBuffer& GpuBuffer::operator=(GpuBuffer&& other) noexcept {
    if (this != &other) {
        if (id_) glDeleteBuffers(1, &id_);
        id_ = std::exchange(other.id_, 0);
        bytes_ = std::exchange(other.bytes_, 0);
    }
    return *this;
}

// Binds the buffer to `binding` of `target`, after checking that this GL allows a
// block of its size (GL_MAX_..._BLOCK_SIZE, named `limitName` in the message).
void GpuBuffer::bindBlock(GLenum target, GLuint binding, GLenum limit,
                          const char* kind, const char* limitName) const {
    GLint64 maxBlockBytes = 0;
    glGetInteger64v(limit, &maxBlockBytes);
    if (maxBlockBytes > 0 && static_cast<GLint64>(bytes_) > maxBlockBytes)
        fail(ExitCode::GlProblem,
             std::string("a ") + kind + " of " + std::to_string(bytes_) +
                 " bytes exceeds this GL's " + limitName + " of " +
                 std::to_string(maxBlockBytes));
    glBindBufferBase(target, binding, id_);
}

void GpuBuffer::bindStorage(GLuint binding) const {
    bindBlock(GL_SHADER_STORAGE_BUFFER, binding, GL_MAX_SHADER_STORAGE_BLOCK_SIZE,
              "storage buffer", "GL_MAX_SHADER_STORAGE_BLOCK_SIZE");
}

void GpuBuffer::bindUniform(GLuint binding) const {
    bindBlock(GL_UNIFORM_BUFFER, binding, GL_MAX_UNIFORM_BLOCK_SIZE, "uniform buffer",
              "GL_MAX_UNIFORM_BLOCK_SIZE");
}

void GpuBuffer::write(const void* data, size_t bytes, size_t offset) {
    glBindBuffer(GL_COPY_WRITE_BUFFER, id_);
    glBufferSubData(GL_COPY_WRITE_BUFFER, static_cast<GLintptr>(offset),
                    static_cast<GLsizeiptr>(bytes), data);
}

void GpuBuffer::read(void* data, size_t bytes, size_t offset) const {
    // Compute shader writes must be visible to the copy that follows. (Before GL 4.2
    // no shader writes to buffers, and GL orders everything else itself.)
    if (GLAD_GL_VERSION_4_2) glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    glBindBuffer(GL_COPY_WRITE_BUFFER, id_);
    glGetBufferSubData(GL_COPY_WRITE_BUFFER, static_cast<GLintptr>(offset),
                       static_cast<GLsizeiptr>(bytes), data);
}

BufferTexture::BufferTexture(const GpuBuffer& buffer, const std::string& what) {
    GLint maxTexels = 0;
    glGetIntegerv(GL_MAX_TEXTURE_BUFFER_SIZE, &maxTexels);
    const size_t texels = buffer.bytes() / 16;
    if (texels > size_t(maxTexels))
        fail(ExitCode::GlProblem, what + " needs " + std::to_string(texels) +
                                      " texels, but this GL's buffer textures hold at most " +
                                      std::to_string(maxTexels) + " (GL_MAX_TEXTURE_BUFFER_SIZE)");
    glGenTextures(1, &id_);
    glBindTexture(GL_TEXTURE_BUFFER, id_);
    glTexBuffer(GL_TEXTURE_BUFFER, GL_RGBA32UI, buffer.id());
    glBindTexture(GL_TEXTURE_BUFFER, 0);
}

BufferTexture::~BufferTexture() {
    if (id_) glDeleteTextures(1, &id_);
}

BufferTexture::BufferTexture(BufferTexture&& other) noexcept
    : id_(std::exchange(other.id_, 0)) {}

BufferTexture& BufferTexture::operator=(BufferTexture&& other) noexcept {
    if (this != &other) {
        if (id_) glDeleteTextures(1, &id_);
        id_ = std::exchange(other.id_, 0);
    }
    return *this;
}

void BufferTexture::bind(GLuint unit) const {
    glActiveTexture(GL_TEXTURE0 + unit);
    glBindTexture(GL_TEXTURE_BUFFER, id_);
    glActiveTexture(GL_TEXTURE0);
}

void BufferTexture::bindImage(GLuint unit) const {
    glBindImageTexture(unit, id_, 0, GL_FALSE, 0, GL_READ_WRITE, GL_RGBA32UI);
}

ImageBuffer::ImageBuffer(int width, int height)
    : width(width), height(height),
      pixels(size_t(width) * size_t(height) * 4 * sizeof(float)) {}

}  // namespace course
