// Chapter 02: the GPU paints an image. A compute shader writes one colour per pixel
// into a storage buffer; the course's display shows that buffer in a window, or the
// program writes it to a PNG when headless.
#include <string>

#include "course/session.h"
#include "shared.h"  // bindings and work-group sizes, shared with the shaders

int main(int argc, char** argv) {
    course::CommandLine cli("Chapter 02: a compute shader paints a test pattern");
    std::string dispatch = "1d";
    cli.choice("--dispatch", "1d: one invocation per pixel in a line; 2d: 8x8 tiles",
               {"1d", "2d"}, &dispatch);
    return course::run(cli, argc, argv, [&](course::Session& session) {
        const int width = session.options().width, height = session.options().height;

        // --8<-- [start:image]
        // 1. The image lives on the GPU: width * height vec4s in a storage buffer.
        course::ImageBuffer image(width, height);
        image.pixels.bindStorage(PIXELS_BINDING);
        // --8<-- [end:image]

        // --8<-- [start:dispatch]
        // 2. The same pattern, painted by either dispatch shape.
        course::ShaderProgram& paint =
            session.loadCompute(dispatch == "1d" ? "pattern_1d.comp" : "pattern_2d.comp");
        paint.set("imageSize", glm::uvec2(width, height));
        auto render = [&] {
            if (dispatch == "1d")
                paint.dispatchCovering(width * height);  // groups of 64 along x
            else
                paint.dispatchCovering(width, height);  // 8x8 tiles over x and y
        };
        // --8<-- [end:dispatch]

        // 3. Paint, then write the PNG (headless) or show it (--window).
        session.timeRender(render);
        session.finish(image, render);
    });
}
