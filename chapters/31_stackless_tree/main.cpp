// Chapter 31: a tree without a stack. Chapter 30's path tracer walks the mesh's tree box
// after box in an order laid out for the ray's direction, each box saying where to go
// on if the ray misses it (threaded_tree.h, bvh_traversal.glsl).
#include <chrono>
#include <optional>
#include <string>

#include "camera.h"
#include "checked_dispatch.h"
#include "course/fly_camera.h"
#include "course/log.h"
#include "course/scene_file.h"
#include "course/session.h"
#include "display.h"
#include "environment.h"
#include "gpu_scene.h"
#include "gpu_timer.h"
#include "kernel_options.h"
#include "scene_code.h"
#include "scene_support.h"  // kSceneSupport: what it reads, from its manifest
#include "shared.h"  // bindings and std430 structs, shared with GLSL
#include "wavefront.h"

int main(int argc, char** argv) {
    course::CommandLine cli("Chapter 31: a tree without a stack");
    cli.acceptScene();  // --scene NAME|FILE, default sky_showcase
    int depth = 6;
    cli.option("--depth", "N", "surface bounces a path may make (1: direct light)", &depth,
               1, 1000);
    bool direct = false;
    cli.flag("--direct", "direct illumination only: the same as --depth 1", &direct);
    std::string estimator = "mis";
    cli.choice("--estimator", "how light reaching a surface is found",
               {"nee", "bsdf", "mis"}, &estimator);
    KernelOptions kernel;
    declareKernelOptions(cli, kernel);  // --kernel, --paths, --samples-per-dispatch, ...
    bool bruteForce = false;
    cli.flag("--brute-force", "test every triangle for every ray, without the tree "
             "(chapter 12's way: for comparisons)", &bruteForce);
    std::string view = "radiance";
    declareViewOption(cli, view);  // --view: radiance, normals, ..., cost, bounce
    DisplayOptions display;
    declareDisplayOptions(cli, display);  // --exposure, --tone-map
    SceneCodeOptions codeOptions;
    declareSceneCodeOptions(cli, codeOptions);  // --scene-memory, --bvh-memory, --generic
    bool scriptCameraMove = false;
    cli.flag("--script-camera-move", "window mode: step forward at frame 2 (tests)",
             &scriptCameraMove);
    return course::run(cli, argc, argv, [&](course::Session& session) {
        const course::Options& options = session.options();
        const int width = options.width, height = options.height;
        if (direct) depth = 1;
        if (kernel.kernel == Kernel::Wavefront && view != "radiance")
            course::fail(course::ExitCode::BadUsage, "--kernel wavefront traces paths only: "
                         "--view " + view + " needs the megakernel (see --help)");

        // 1. The scene file, its meshes, images and environment, and the packed arrays
        //    (exit code 3 on mistakes); the environment's radiance after the images' texels.
        course::SceneFile sceneFile =
            course::loadSceneFile(session.scenePath("sky_showcase"),
                                  {COURSE_GENERATED_ASSET_DIR}, kSceneSupport);
        GpuScene scene = packScene(sceneFile, codeOptions.tree);
        EnvironmentMap environment = loadEnvironment(sceneFile);
        gpu::PathParameters parameters{};
        addEnvironment(environment, sceneFile, !scene.emitters.empty(), scene.texels,
                       parameters);
        course::logInfo(describeBvh(scene.bvh.stats));
        recordSceneStats(scene, session.stats());  // shapes, triangles, the tree ...
        auto search = bruteForce ? TriangleSearch::EveryTriangle : TriangleSearch::Tree;
        bool wholePaths = view == "radiance" && kernel.kernel == Kernel::Megakernel;
        PathLoops loops{sceneFile.path, bruteForce ? scene.shapeCount()
                                                   : scene.spheres.size() + scene.quads.size(),
                        scene.triangles.empty() ? TriangleSearch::None : search, depth,
                        wholePaths ? Invocation::WholePaths : Invocation::OneRay};
        checkPathLoops(loops);  // exit code 4 if the GL's loop limit would cut them short
        const int perDispatch = samplesPerDispatch(kernel, loops, size_t(width) * height);
        // --8<-- [start:scene_code]
        // The shader's part written for this scene (scene_code.glsl), and how it reads
        // the scene: constants for a small scene, buffer textures otherwise.
        SceneCodeChoice choice = chooseSceneCode(codeOptions, scene, sceneFile.path);
        std::string sceneCode = writeSceneCode(
            scene, choice, sceneFile.hasEnvironment(), sceneFile.camera.lensRadius > 0);
        recordSceneCode(choice, session.stats());
        // --8<-- [end:scene_code]

        // --8<-- [start:upload]
        // 2. Storage buffers: the scene (chapter 17's, and the environment's tables; each
        //    bound by uploadScene, and seen as the scene code says), the image (the
        //    running mean), each pixel's random number state and ray count; and where
        //    the GL may cut a dispatch short, a copy of the last three to go back to.
        SceneBuffers sceneBuffers = uploadScene(scene, environment.distributions,
                                                choice.sceneMemory, choice.bvhMemory);
        course::GpuBuffer bounceStarts(size_t(width) * height * 2 * sizeof(glm::vec4));
        course::ImageBuffer image(width, height);
        course::GpuBuffer randomStates(size_t(width) * height * sizeof(glm::uvec4));
        course::GpuBuffer rayCounts(size_t(width) * height * sizeof(uint32_t));
        bounceStarts.bindStorage(BOUNCE_START_BINDING);
        image.pixels.bindStorage(PIXELS_BINDING);
        randomStates.bindStorage(RANDOM_BINDING);
        rayCounts.bindStorage(RAY_COUNT_BINDING);
        CheckedDispatch checked({&image.pixels, &randomStates, &rayCounts}, perDispatch,
                                dispatchesNeedChecks(loops), sceneFile.path);
        // --8<-- [end:upload]

        // --8<-- [start:dispatch]
        // 3. Chapter 09's seeding and progressive loop, with the path tracer as the
        //    sample: a dispatch of the megakernel adds up to perDispatch samples to each
        //    pixel (fewer after a cut), the wavefront one. What a dispatch reads besides
        //    the buffers is one uniform block, gpu::PathParameters (shared.h).
        course::ShaderProgram& seed = session.loadCompute("seed.comp");
        course::ShaderProgram* path = nullptr;  // the megakernel, or
        std::optional<Wavefront> wavefront;     // --kernel wavefront: its kernels, queues
        if (kernel.kernel == Kernel::Wavefront)
            wavefront.emplace(session, scene, sceneCode, width, height, kernel.paths);
        else path = &session.loadCompute("path.comp", {{"scene_code.glsl", sceneCode}});
        const course::SceneCamera& c = sceneFile.camera;
        course::FlyCamera fly = course::FlyCamera::looking(c.eye, c.look, 0.25f * scene.size);
        parameters.imageSize = glm::uvec2(width, height);
        parameters.seed = options.seed;
        parameters.maxBounces = depth;
        parameters.estimator = estimatorCode(estimator);
        parameters.view = viewCode(view);
        parameters.occlusionDistance = 0.25f * scene.size;
        parameters.bruteForce = bruteForce;
        parameters.exposure = display.exposure;
        parameters.toneMap = toneMapCode(display.toneMap);
        parameters.loopCanary = 2;  // path.comp's loopsCutShort()
        course::GpuBuffer parameterBuffer(sizeof parameters);
        parameterBuffer.bindUniform(PARAMETERS_BINDING);
        unsigned samples = 0;
        auto addSamples = [&](unsigned wanted) {  // a dispatch adds up to `wanted`
            parameters.camera = thinLensCamera(
                makeCamera(fly.eye, fly.forward(), c.up, c.focalLength, c.sensorWidth),
                c.lensRadius, c.focusDistance);
            samples += checked.add(int(wanted), [&](int count) {
                parameters.sampleIndex = samples;
                parameters.samplesThisDispatch = count;
                parameterBuffer.write(&parameters, sizeof parameters);
                if (wavefront) wavefront->addSample(depth);  // count is 1
                else path->dispatchCovering(width, height);
            });
        };
        GpuTimer gpuTimer;  // the render as the GPU timed it
        auto render = [&] {
            gpuTimer.start();
            parameterBuffer.write(&parameters, sizeof parameters);
            seed.dispatchCovering(width, height);
            samples = 0;
            for (int batch = 0; batch < kernel.batches; ++batch) {
                int end = options.spp * (batch + 1) / kernel.batches;  // --batches: the
                while (int(samples) < end)  // same dispatches, the GPU idle between
                    addSamples(end - int(samples));
                course::waitForGpu();
            }
            gpuTimer.stop();
        };
        // --8<-- [end:dispatch]

        // --8<-- [start:display]
        // 4. What the eye sees: display.comp exposes and tone maps the running mean into
        //    a second image, which the window shows and a PNG holds (sRGB-encoded); a
        //    PFM or EXR holds the radiance itself.
        course::ShaderProgram& toDisplay = session.loadCompute("display.comp");
        course::ImageBuffer displayed(width, height);
        displayed.pixels.bindStorage(DISPLAY_BINDING);
        session.setDisplay(displayed, [&] {
            parameterBuffer.write(&parameters, sizeof parameters);
            toDisplay.dispatchCovering(width, height);
        });
        // --8<-- [end:display]

        // 5. Render --spp samples; headless, write the image.
        session.timeRender(render, samples);

        // --8<-- [start:window]
        // 6. Window: one more sample each frame; moving the camera starts over; - and =
        //    change the exposure by half a stop, T the tone mapping.
        glm::dvec2 lastCursor(-1.0);
        course::KeyPresses keys;
        auto lastFrame = std::chrono::steady_clock::now();
        auto eachFrame = [&](int frame) {
            auto now = std::chrono::steady_clock::now();
            float seconds = std::chrono::duration<float>(now - lastFrame).count();
            lastFrame = now;
            course::FlyInput input =
                course::readFlyInput(session.context().window(), lastCursor, seconds);
            if (scriptCameraMove && frame == 2) input = {{0, 0, 1}, {0, 0}, 1.0f};
            if (fly.update(input)) samples = 0;  // start over; the streams go on
            adjustDisplay(session.context().window(), keys, parameters);
            addSamples(1);  // a frame adds one sample, and comes back soon
        };
        // --8<-- [end:window]
        session.finish(image, render, eachFrame);

        // 7. Statistics: samples and rays (every one the shaders traced) per second.
        recordSpeed(session, rayCounts, samples, gpuTimer);
        checked.record(session.stats(), options.spp);  // samples_per_dispatch, ...
        if (scriptCameraMove) session.stats().set("camera_z", double(fly.eye.z));
    });
}
