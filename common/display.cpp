#include "course/display.h"

#include <algorithm>
#include <string>

#include "course/shader_program.h"

namespace course {
namespace {

// Three vertices from gl_VertexID, no vertex buffer: a triangle twice the size of the
// screen, clipped to exactly cover it.
const char* kVertexShader = R"(#version 430 core
void main() {
    vec2 corner = vec2((gl_VertexID << 1) & 2, gl_VertexID & 2);
    gl_Position = vec4(corner * 2.0 - 1.0, 0.0, 1.0);
}
)";

const char* kFragmentShader = R"(#version 430 core
layout(std430, binding = 15) readonly buffer ImagePixels { vec4 pixels[]; };
uniform ivec2 imageSize;
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
    vec3 linear = pixels[pixel.y * imageSize.x + pixel.x].rgb * scale;
    fragmentColor = vec4(linearToSrgb(linear), 1.0);
}
)";

}  // namespace

ImageDisplay::ImageDisplay() {
    program_ = buildProgramFromText(
        {{GL_VERTEX_SHADER, kVertexShader}, {GL_FRAGMENT_SHADER, kFragmentShader}},
        "common/display.cpp");
    glGenVertexArrays(1, &emptyVertexArray_);
}

ImageDisplay::~ImageDisplay() {
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
    // The compute shader's writes must land before the fragment shader reads them.
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kDisplayImageBinding, image.pixels.id());
    glBindVertexArray(emptyVertexArray_);
    glDrawArrays(GL_TRIANGLES, 0, 3);
}

}  // namespace course
