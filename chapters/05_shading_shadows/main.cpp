// Chapter 05: light and shadow. A point light shines on spheres standing on a floor;
// a hit point is lit when a shadow ray from it reaches the light unobstructed.
#include "camera.h"
#include "course/camera_options.h"
#include "course/session.h"
#include "scene.h"
#include "shared.h"  // bindings, the tile size and the scene's structs, shared with GLSL

int main(int argc, char** argv) {
    course::CommandLine cli("Chapter 05: spheres on a floor, lit by a point light, shadows");
    course::CameraOptions cameraOptions;
    cameraOptions.declare(cli);  // --camera-eye, --camera-look, ... (see --help)
    cli.acceptScene();           // --scene spheres|single
    bool noShadowOffset = false;
    cli.flag("--no-shadow-offset", "start shadow rays on the surface: shadow acne",
             &noShadowOffset);
    return course::run(cli, argc, argv, [&](course::Session& session) {
        const int width = session.options().width, height = session.options().height;

        // 1. The camera's basis, computed once on the CPU: every pixel uses the same
        //    three vectors, so there is no reason to rebuild them per invocation.
        Camera camera = makeCamera(cameraOptions.eye, cameraOptions.look, cameraOptions.up,
                                   cameraOptions.focalLength, cameraOptions.sensorWidth);

        // --8<-- [start:scene]
        // 2. The scene goes to the GPU as arrays of Sphere and Plane structs, laid out as
        //    the shader's std430 buffers expect (shared.h checks that at compile time).
        const std::string& sceneName = session.options().scene;
        Scene scene = builtInScene(sceneName.empty() ? sceneNames().front() : sceneName);
        auto spheres = course::GpuBuffer::fromVector(scene.spheres);
        spheres.bindStorage(SPHERES_BINDING);
        auto planes = course::GpuBuffer::fromVector(scene.planes);
        planes.bindStorage(PLANES_BINDING);
        // --8<-- [end:scene]

        // --8<-- [start:setup]
        // 3. The image, and the shader that traces one ray per pixel in 8x8 tiles.
        course::ImageBuffer image(width, height);
        image.pixels.bindStorage(PIXELS_BINDING);
        course::ShaderProgram& trace = session.loadCompute("trace.comp");
        setCamera(trace, camera);
        trace.set("imageSize", glm::uvec2(width, height));
        // --8<-- [end:setup]

        // --8<-- [start:light]
        // 4. The light, and how far shadow rays start off the surface (shared.h).
        trace.set("lightPosition", scene.lightPosition);
        trace.set("shadowOffset", noShadowOffset ? 0.0f : float(SHADOW_OFFSET));
        // --8<-- [end:light]

        // 5. Trace, then write the PNG (headless) or show it (--window).
        auto render = [&] { trace.dispatchCovering(width, height); };
        session.timeRender(render);
        session.finish(image, render);
    });
}
