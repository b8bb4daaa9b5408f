#include "course/display.h"

#include <algorithm>
#include <string>

#include "course/shader_program.h"

namespace course {
namespace {

// Three vertices from gl_VertexID, no vertex buffer: a triangle twice the size of the
// screen, clipped to exactly cover it. (GLSL 3.30 and 4.30 read it alike.)
const char* kVertexShader = R"(
void main() {
    vec2 corner = vec2((gl_VertexID << 1) & 2, gl_VertexID & 2);
    gl_Position = vec4(corner * 2.0 - 1.0, 0.0, 1.0);
}
)";

// How the fragment shader reads a pixel: from the storage buffer itself (GL 4.3), or,
// on the GL 3.3 appendix's contexts, from a texture the buffer was copied into.
const char* kReadFromBuffer = R"(
layout(std430, binding = 15) readonly buffer ImagePixels { vec4 pixels[]; };
uniform ivec2 imageSize;
vec4 readPixel(ivec2 pixel) { return pixels[pixel.y * imageSize.x + pixel.x]; }
)";
const char* kReadFromTexture = R"(
uniform sampler2D image;  // texture row 0 is the image's top row, as in the buffer
uniform ivec2 imageSize;
vec4 readPixel(ivec2 pixel) { return texelFetch(image, pixel, 0); }
)";

const char* kFragmentShader = R"(
uniform ivec4 viewport;   // where the image lands: x, y, width, height
uniform float scale;
out vec4 fragmentColor;

vec3 linearToSrgb(vec3 linear) {
    vec3 x = clamp(linear, 0.0, 1.0);
    return mix(12.92 * x, 1.055 * pow(x, vec3(1.0 / 2.4)) - 0.055, step(0.0031308, x));
}

void main() {
    vec2 inView = (gl_FragCoord.xy - vec2(viewport.xy)) / vec2(viewport.zw);
    if (any(lessThan(inView, vec2(0.0))) || any(greaterThanEqual(inView, vec2(1.0)))) {
        fragmentColor = vec4(0.08, 0.08, 0.08, 1.0);
        return;
    }
    // GL's window y grows upwards, the image's rows go downwards.
    ivec2 pixel = ivec2(inView.x * imageSize.x, (1.0 - inView.y) * imageSize.y);
    pixel = min(pixel, imageSize - 1);
    vec3 linear = readPixel(pixel).rgb * scale;
    fragmentColor = vec4(linearToSrgb(linear), 1.0);
}
)";

}  // namespace

ImageDisplay::ImageDisplay() : fromTexture_(!GLAD_GL_VERSION_4_3) {
    const std::string version = fromTexture_ ? "#version 330 core\n" : "#version 430 core\n";
    const char* read = fromTexture_ ? kReadFromTexture : kReadFromBuffer;
    program_ = buildProgramFromText({{GL_VERTEX_SHADER, version + kVertexShader},
                                     {GL_FRAGMENT_SHADER, version + read + kFragmentShader}},
                                    "common/display.cpp");
    glGenVertexArrays(1, &emptyVertexArray_);
    if (fromTexture_) {
        glGenTextures(1, &texture_);
        glBindTexture(GL_TEXTURE_2D, texture_);
        // No mipmaps: without these the texture counts as incomplete and reads as black.
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    }
}

ImageDisplay::~ImageDisplay() {
    if (texture_) glDeleteTextures(1, &texture_);
    glDeleteVertexArrays(1, &emptyVertexArray_);
    glDeleteProgram(program_);
}

void ImageDisplay::draw(const ImageBuffer& image, int framebufferWidth,
                        int framebufferHeight, float scale) const {
    // Largest rectangle of the image's aspect ratio that fits, centred.
    float fit = std::min(float(framebufferWidth) / image.width,
                         float(framebufferHeight) / image.height);
    int width = std::max(1, int(image.width * fit)), height = std::max(1, int(image.height * fit));
    int x = (framebufferWidth - width) / 2, y = (framebufferHeight - height) / 2;

    glViewport(0, 0, framebufferWidth, framebufferHeight);
    glUseProgram(program_);
    glUniform2i(glGetUniformLocation(program_, "imageSize"), image.width, image.height);
    glUniform4i(glGetUniformLocation(program_, "viewport"), x, y, width, height);
    glUniform1f(glGetUniformLocation(program_, "scale"), scale);
    if (!fromTexture_) {
        // The compute shader's writes must land before the fragment shader reads them.
        glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kDisplayImageBinding, image.pixels.id());
    } else {
        // GL 3.3: the buffer is copied into the texture on the GPU. With a buffer bound
        // to GL_PIXEL_UNPACK_BUFFER, glTexImage2D reads from it, and its last argument
        // is an offset into the buffer instead of a pointer.
        glActiveTexture(GL_TEXTURE0);
        glBindTexture(GL_TEXTURE_2D, texture_);
        glBindBuffer(GL_PIXEL_UNPACK_BUFFER, image.pixels.id());
        glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA32F, image.width, image.height, 0, GL_RGBA,
                     GL_FLOAT, nullptr);
        glBindBuffer(GL_PIXEL_UNPACK_BUFFER, 0);
        glUniform1i(glGetUniformLocation(program_, "image"), 0);
    }
    glBindVertexArray(emptyVertexArray_);
    glDrawArrays(GL_TRIANGLES, 0, 3);
}

}  // namespace course
