// Chapter 06: triangles, the shape everything else is made of. A pyramid built from
// four of them joins the spheres, and the floor becomes two big ones.
#include "camera.h"
#include "course/camera_options.h"
#include "course/session.h"
#include "scene.h"
#include "shared.h"  // bindings, the tile size and the scene's structs, shared with GLSL

int main(int argc, char** argv) {
    course::CommandLine cli("Chapter 06: spheres and triangles, lit, with shadows");
    course::CameraOptions cameraOptions;
    cameraOptions.declare(cli);  // --camera-eye, --camera-look, ... (see --help)
    cli.acceptScene();           // --scene spheres|single
    bool noShadowOffset = false;
    cli.flag("--no-shadow-offset", "start shadow rays on the surface: shadow acne",
             &noShadowOffset);
    bool noNormalFlip = false;
    cli.flag("--no-normal-flip", "keep triangle normals as wound, even seen from behind",
             &noNormalFlip);
    return course::run(cli, argc, argv, [&](course::Session& session) {
        const int width = session.options().width, height = session.options().height;

        // 1. The camera's basis, computed once on the CPU: every pixel uses the same
        //    three vectors, so there is no reason to rebuild them per invocation.
        Camera camera = makeCamera(cameraOptions.eye, cameraOptions.look, cameraOptions.up,
                                   cameraOptions.focalLength, cameraOptions.sensorWidth);

        // --8<-- [start:scene]
        // 2. The scene goes to the GPU as arrays of Sphere and Triangle structs, laid out
        //    as the shader's std430 buffers expect (shared.h checks that at compile time).
        const std::string& sceneName = session.options().scene;
        Scene scene = builtInScene(sceneName.empty() ? sceneNames().front() : sceneName);
        auto spheres = course::GpuBuffer::fromVector(scene.spheres);
        spheres.bindStorage(SPHERES_BINDING);
        auto triangles = course::GpuBuffer::fromVector(scene.triangles);
        triangles.bindStorage(TRIANGLES_BINDING);
        // --8<-- [end:scene]

        // --8<-- [start:setup]
        // 3. The image, and the shader that traces one ray per pixel in 8x8 tiles.
        course::ImageBuffer image(width, height);
        image.pixels.bindStorage(PIXELS_BINDING);
        course::ShaderProgram& trace = session.loadCompute("trace.comp");
        setCamera(trace, camera);
        trace.set("imageSize", glm::uvec2(width, height));
        trace.set("lightPosition", scene.lightPosition);
        trace.set("shadowOffset", noShadowOffset ? 0.0f : float(SHADOW_OFFSET));
        trace.set("flipNormals", int(!noNormalFlip));  // two-sided triangles
        // --8<-- [end:setup]

        // 4. Trace, then write the PNG (headless) or show it (--window).
        auto render = [&] { trace.dispatchCovering(width, height); };
        session.timeRender(render);
        session.finish(image, render);
    });
}
