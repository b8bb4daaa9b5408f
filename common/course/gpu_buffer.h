// A GPU buffer that frees itself: a shader storage buffer (SSBO) or a uniform buffer.
// Move-only, like the GL object it owns. Sizes are checked against what the driver
// allows, so a too-large scene fails with a message instead of a black picture.
#pragma once
#include <cstddef>
#include <string>
#include <vector>

#include "course/gl.h"

namespace course {

class GpuBuffer {
public:
    GpuBuffer() = default;
    explicit GpuBuffer(size_t bytes, const void* initialData = nullptr);
    template <class T>
    static GpuBuffer fromVector(const std::vector<T>& items) {
        return GpuBuffer(items.size() * sizeof(T), items.data());
    }
    ~GpuBuffer();
    GpuBuffer(GpuBuffer&& other) noexcept;
    GpuBuffer& operator=(GpuBuffer&& other) noexcept;
    GpuBuffer(const GpuBuffer&) = delete;
    GpuBuffer& operator=(const GpuBuffer&) = delete;

    // Makes the buffer visible to shaders as `layout(std430, binding = N) buffer`.
    void bindStorage(GLuint binding) const;
    // Makes the buffer the uniform block at binding point N: `layout(std140, binding = N)
    // uniform`, or a block that ShaderProgram::bindUniformBlock connected to N (GL 3.3).
    void bindUniform(GLuint binding) const;
    void write(const void* data, size_t bytes, size_t offset = 0);
    void read(void* data, size_t bytes, size_t offset = 0) const;
    template <class T>
    std::vector<T> readAll() const {
        std::vector<T> items(bytes_ / sizeof(T));
        read(items.data(), items.size() * sizeof(T));
        return items;
    }

    GLuint id() const { return id_; }
    size_t bytes() const { return bytes_; }

private:
    void bindBlock(GLenum target, GLuint binding, GLenum limit, const char* kind,
                   const char* limitName) const;
    GLuint id_ = 0;
    size_t bytes_ = 0;
};

// A buffer seen as a row of texels by a `usamplerBuffer` (texelFetch): a buffer texture.
// It views the buffer's own bytes, so the same buffer can be a storage buffer too.
// RGBA32UI: 16 bytes a texel, four uints with the bytes' bits as they are, so a std430
// struct whose size is a multiple of 16 is a whole number of texels; its floats come
// back through uintBitsToFloat. (Through an RGBA32F view a driver may flush a uint
// that looks like a denormal float to zero, or change a NaN's bits.) More texels than
// the GL's GL_MAX_TEXTURE_BUFFER_SIZE is exit code 4, naming `what`.
class BufferTexture {
public:
    BufferTexture() = default;
    BufferTexture(const GpuBuffer& buffer, const std::string& what);
    ~BufferTexture();
    BufferTexture(BufferTexture&& other) noexcept;
    BufferTexture& operator=(BufferTexture&& other) noexcept;
    BufferTexture(const BufferTexture&) = delete;
    BufferTexture& operator=(const BufferTexture&) = delete;

    // Makes it the texture of `layout(binding = unit) uniform usamplerBuffer`.
    void bind(GLuint unit) const;
    // Makes it the image of `layout(rgba32ui, binding = unit) uniform uimageBuffer`,
    // which a shader may read and write texel by texel (imageLoad, imageStore; GL 4.2):
    // a way to write a buffer from a shader whose storage blocks are all taken.
    void bindImage(GLuint unit) const;

private:
    GLuint id_ = 0;
};

// The image every ray-tracing chapter renders into: one linear RGBA vec4 per pixel,
// row 0 at the top. Window mode shows it; headless mode writes it to --out.
struct ImageBuffer {
    int width = 0, height = 0;
    GpuBuffer pixels;
    ImageBuffer() = default;
    ImageBuffer(int width, int height);
};

}  // namespace course
