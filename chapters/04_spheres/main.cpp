// Chapter 04: spheres. Every camera ray looks for the nearest sphere it meets; the
// picture shows the surface normal there as a colour, and the sky where rays miss.
#include "camera.h"
#include "course/camera_options.h"
#include "course/session.h"
#include "scene.h"
#include "shared.h"  // bindings, the tile size and the Sphere struct, shared with GLSL

int main(int argc, char** argv) {
    course::CommandLine cli("Chapter 04: the nearest sphere along every ray, its normal");
    course::CameraOptions cameraOptions;
    cameraOptions.declare(cli);  // --camera-eye, --camera-look, ... (see --help)
    cli.acceptScene();           // --scene spheres|single
    bool firstHitOnly = false;
    cli.flag("--first-hit", "the classic bug: show the first sphere hit, not the nearest",
             &firstHitOnly);
    return course::run(cli, argc, argv, [&](course::Session& session) {
        const int width = session.options().width, height = session.options().height;

        // 1. The camera's basis, computed once on the CPU: every pixel uses the same
        //    three vectors, so there is no reason to rebuild them per invocation.
        Camera camera = makeCamera(cameraOptions.eye, cameraOptions.look, cameraOptions.up,
                                   cameraOptions.focalLength, cameraOptions.sensorWidth);

        // --8<-- [start:scene]
        // 2. The scene goes to the GPU as an array of Sphere structs, laid out as the
        //    shader's std430 buffer expects (shared.h checks that at compile time).
        const std::string& sceneName = session.options().scene;
        Scene scene = builtInScene(sceneName.empty() ? sceneNames().front() : sceneName);
        auto spheres = course::GpuBuffer::fromVector(scene.spheres);
        spheres.bindStorage(SPHERES_BINDING);
        // --8<-- [end:scene]

        // --8<-- [start:setup]
        // 3. The image, and the shader that traces one ray per pixel in 8x8 tiles.
        course::ImageBuffer image(width, height);
        image.pixels.bindStorage(PIXELS_BINDING);
        course::ShaderProgram& trace = session.loadCompute("trace.comp");
        setCamera(trace, camera);
        trace.set("imageSize", glm::uvec2(width, height));
        // --8<-- [end:setup]
        trace.set("firstHitOnly", int(firstHitOnly));

        // 4. Trace, then write the PNG (headless) or show it (--window).
        auto render = [&] { trace.dispatchCovering(width, height); };
        session.timeRender(render);
        session.finish(image, render);
    });
}
