// Chapter 28: denoising. Chapter 18's path tracer also writes each path's first surface
// (albedo, normal, depth) and the light it received; an edge-avoiding filter (denoiser.cpp,
// denoise.comp) averages that light over neighbours that look alike, albedo put back.
#include <algorithm>
#include <chrono>
#include <numeric>
#include <string>

#include "camera.h"
#include "course/fly_camera.h"
#include "course/log.h"
#include "course/loop_budget.h"
#include "course/scene_file.h"
#include "course/session.h"
#include "denoiser.h"
#include "display.h"
#include "environment.h"
#include "gpu_scene.h"
#include "scene_support.h"  // kSceneSupport: what it reads, from its manifest
#include "shared.h"  // bindings and std430 structs, shared with GLSL

int main(int argc, char** argv) {
    course::CommandLine cli("Chapter 28: denoising");
    cli.acceptScene();  // --scene NAME|FILE, default sky_showcase
    int depth = 6, batches = 1;
    cli.option("--depth", "N", "surface bounces a path may make (1: direct light)", &depth,
               1, 1000);
    bool direct = false;
    cli.flag("--direct", "direct illumination only: the same as --depth 1", &direct);
    std::string estimator = "mis";
    cli.choice("--estimator", "how light reaching a surface is found",
               {"nee", "bsdf", "mis"}, &estimator);
    cli.option("--batches", "B", "render --spp in B groups of dispatches, waiting for "
               "the GPU between them (the same image)", &batches, 1, 1 << 20);
    bool bruteForce = false;
    cli.flag("--brute-force", "test every triangle for every ray, without the tree "
             "(chapter 12's way: for comparisons)", &bruteForce);
    std::string view = "radiance";
    cli.choice("--view", "what the image shows: the path traced light, what the camera "
               "rays hit (normals, distance in metres, albedo with textures, texture "
               "coordinates uv), the traversal's work per pixel (cost) or random bounce "
               "rays (bounce: ambient occlusion)",
               {"radiance", "normals", "distance", "albedo", "uv", "cost", "bounce"}, &view);
    DisplayOptions display;
    declareDisplayOptions(cli, display);  // --exposure, --tone-map
    DenoiseOptions denoise;
    declareDenoiseOptions(cli, denoise);  // --denoise, --denoise-passes, --aux-out
    bool scriptCameraMove = false;
    cli.flag("--script-camera-move", "window mode: step forward at frame 2 (tests)",
             &scriptCameraMove);
    return course::run(cli, argc, argv, [&](course::Session& session) {
        const course::Options& options = session.options();
        const int width = options.width, height = options.height;
        if (direct) depth = 1;

        // 1. The scene file, its meshes, images and environment, and the packed arrays
        //    (exit code 3 on mistakes). The environment's radiance follows the images'
        //    texels.
        course::SceneFile sceneFile =
            course::loadSceneFile(session.scenePath("sky_showcase"),
                                  {COURSE_GENERATED_ASSET_DIR}, kSceneSupport);
        GpuScene scene = packScene(sceneFile);
        EnvironmentMap environment = loadEnvironment(sceneFile);
        gpu::PathParameters parameters{};
        addEnvironment(environment, sceneFile, !scene.emitters.empty(), scene.texels,
                       parameters);
        course::logInfo(describeBvh(scene.bvh.stats));
        recordBvhStats(scene.bvh.stats, session.stats());
        // Each bounce tests the shapes in loops twice (nearest hit, shadow ray; the
        // other views trace at most two rays): with the tree, only spheres and quads
        // are looped over, and its own steps are a few hundred per ray.
        size_t looped = scene.spheres.size() + scene.quads.size();
        if (bruteForce) looped = scene.shapeCount();
        size_t rounds = view == "radiance" ? size_t(depth) + 1 : 1;
        const char* wayOut = bruteForce ? "Without --brute-force, the tree renders it."
                                        : "Fewer spheres and quads, or a lower --depth, fit.";
        course::checkLoopBudget({sceneFile.path, looped, "shapes tested in loops",
                                 2 * rounds, wayOut});
        session.stats().set("shapes", double(scene.shapeCount()));
        session.stats().set("triangles", double(scene.triangles.size()));
        session.stats().set("emitters", double(scene.emitters.size()));
        session.stats().set("textures", double(scene.textures.size()));
        session.stats().set("texels", double(scene.texels.size()));

        // --8<-- [start:upload]
        // 2. Storage buffers: the scene (chapter 17's, and the environment's tables; each
        //    bound by uploadScene), the image (the running mean), each pixel's random
        //    number state and ray count.
        SceneBuffers sceneBuffers = uploadScene(scene, environment.distributions);
        course::GpuBuffer bounceStarts(size_t(width) * height * 2 * sizeof(glm::vec4));
        course::ImageBuffer image(width, height);
        course::GpuBuffer randomStates(size_t(width) * height * sizeof(glm::uvec4));
        course::GpuBuffer rayCounts(size_t(width) * height * sizeof(uint32_t));
        bounceStarts.bindStorage(BOUNCE_START_BINDING);
        image.pixels.bindStorage(PIXELS_BINDING);
        randomStates.bindStorage(RANDOM_BINDING);
        rayCounts.bindStorage(RAY_COUNT_BINDING);
        // --8<-- [end:upload]

        // --8<-- [start:dispatch]
        // 3. Chapter 09's seeding and progressive loop, with the path tracer as the
        //    sample. What a dispatch reads besides the buffers is one uniform block,
        //    gpu::PathParameters (shared.h), written before each dispatch: the sample
        //    count grows, and the fly camera may have moved.
        course::ShaderProgram& seed = session.loadCompute("seed.comp");
        course::ShaderProgram& path = session.loadCompute("path.comp");
        const course::SceneCamera& c = sceneFile.camera;
        course::FlyCamera fly = course::FlyCamera::looking(c.eye, c.look, 0.25f * scene.size);
        parameters.imageSize = glm::uvec2(width, height);
        parameters.seed = options.seed;
        parameters.maxBounces = depth;
        parameters.estimator = estimator == "nee"    ? ESTIMATOR_NEE
                               : estimator == "bsdf" ? ESTIMATOR_BSDF : ESTIMATOR_MIS;
        parameters.view = viewCode(view);
        parameters.occlusionDistance = 0.25f * scene.size;
        parameters.bruteForce = bruteForce;
        parameters.exposure = display.exposure;
        parameters.toneMap = toneMapCode(display.toneMap);
        course::GpuBuffer parameterBuffer(sizeof parameters);
        parameterBuffer.bindUniform(PARAMETERS_BINDING);
        // The denoiser, whose buffers the path tracer writes into (the views: as they are).
        if (view != "radiance") denoise.filter = "none";
        Denoiser denoiser(session, width, height, denoise);
        unsigned samples = 0;
        auto addSample = [&] {
            glMemoryBarrier(kShaderWrites);  // read what the last wrote
            parameters.camera = thinLensCamera(
                makeCamera(fly.eye, fly.forward(), c.up, c.focalLength, c.sensorWidth),
                c.lensRadius, c.focusDistance);
            parameters.sampleIndex = samples++;
            parameterBuffer.write(&parameters, sizeof parameters);
            path.dispatchCovering(width, height);
        };
        auto render = [&] {
            parameterBuffer.write(&parameters, sizeof parameters);
            seed.dispatchCovering(width, height);
            samples = 0;
            for (int batch = 0; batch < batches; ++batch) {
                int end = options.spp * (batch + 1) / batches;  // --batches: the same
                while (int(samples) < end) addSample();         // dispatches, the GPU
                course::waitForGpu();                           // idle in between
            }
            denoiser.run(samples);
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
            denoiser.picture(image).pixels.bindStorage(PIXELS_BINDING);  // what is shown
            toDisplay.dispatchCovering(width, height);
            image.pixels.bindStorage(PIXELS_BINDING);  // the path tracer's, again
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
            addSample();
            denoiser.run(samples);  // every frame: the picture shown is the denoised one
        };
        // --8<-- [end:window]
        session.finish(denoiser.picture(image), render, eachFrame);
        denoiser.writeAuxiliary(samples);

        // 6. Statistics: every ray the shader traced (camera, bounce and shadow rays).
        std::vector<uint32_t> counts = rayCounts.readAll<uint32_t>();
        double rays = std::accumulate(counts.begin(), counts.end(), 0.0);
        double seconds = session.stats().number("wall_ms") / 1000.0;
        session.stats().set("samples_per_pixel", double(samples));
        session.stats().set("rays", rays);
        if (!session.isWindow()) {
            double all = double(width) * height * samples;
            session.stats().set("samples_per_second", all / seconds);
            session.stats().set("rays_per_second", rays / seconds);
        }
        if (scriptCameraMove) session.stats().set("camera_z", double(fly.eye.z));
    });
}
