// Chapter 03: a pinhole camera. Every pixel gets a ray from the eye through its centre
// on a virtual sensor; the picture shows each ray's direction as a colour.
#include "camera.h"
#include "course/camera_options.h"
#include "course/session.h"
#include "shared.h"  // bindings and the tile size, shared with the shaders

int main(int argc, char** argv) {
    course::CommandLine cli("Chapter 03: one camera ray per pixel, its direction as colour");
    course::CameraOptions cameraOptions;
    cameraOptions.declare(cli);  // --camera-eye, --camera-look, ... (see --help)
    return course::run(cli, argc, argv, [&](course::Session& session) {
        const int width = session.options().width, height = session.options().height;

        // --8<-- [start:setup]
        // 1. The camera's basis, computed once on the CPU: every pixel uses the same
        //    three vectors, so there is no reason to rebuild them per invocation.
        Camera camera = makeCamera(cameraOptions.eye, cameraOptions.look, cameraOptions.up,
                                   cameraOptions.focalLength, cameraOptions.sensorWidth);

        // 2. The image, and the shader that traces one ray per pixel in 8x8 tiles.
        course::ImageBuffer image(width, height);
        image.pixels.bindStorage(PIXELS_BINDING);
        course::ShaderProgram& trace = session.loadCompute("trace.comp");
        setCamera(trace, camera);
        trace.set("imageSize", glm::uvec2(width, height));
        // --8<-- [end:setup]

        // 3. Trace, then write the PNG (headless) or show it (--window).
        auto render = [&] { trace.dispatchCovering(width, height); };
        session.timeRender(render);
        session.finish(image, render);
    });
}
