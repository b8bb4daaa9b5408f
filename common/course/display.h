// Shows an ImageBuffer in the window: one triangle that covers the screen, and a
// fragment shader that reads the pixel's colour from the storage buffer (on a GL 3.3
// context, which has none in shaders, from a texture the buffer is copied into).
#pragma once
#include "course/gl.h"
#include "course/gpu_buffer.h"

namespace course {

class ImageDisplay {
public:
    ImageDisplay();
    ~ImageDisplay();
    ImageDisplay(const ImageDisplay&) = delete;
    ImageDisplay& operator=(const ImageDisplay&) = delete;

    // Draws `image` (colours multiplied by `scale`, e.g. 1/samples for a running sum)
    // to fit a framebuffer of the given size, keeping the aspect ratio.
    void draw(const ImageBuffer& image, int framebufferWidth, int framebufferHeight,
              float scale = 1.0f) const;

private:
    GLuint program_ = 0;
    GLuint emptyVertexArray_ = 0;  // core profile draws need one bound, even unused
    bool fromTexture_ = false;     // below GL 4.3: read a texture, not the buffer
    GLuint texture_ = 0;
};

// The binding the display reads the image from; chapters' shared.h stay clear of it.
constexpr GLuint kDisplayImageBinding = 15;

}  // namespace course
