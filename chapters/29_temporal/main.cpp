// Chapter 29: temporal accumulation. Each frame's samples are blended with the frames
// before, found again where the camera has moved (temporal.cpp, temporal.comp), and the
// blend is denoised: a moving camera keeps a clean picture instead of starting over.
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
#include "temporal.h"

int main(int argc, char** argv) {
    course::CommandLine cli("Chapter 29: temporal accumulation");
    cli.acceptScene();  // --scene NAME|FILE, default sky_showcase
    int depth = 6;
    cli.option("--depth", "N", "surface bounces a path may make (1: direct light)", &depth,
               1, 1000);
    bool direct = false;
    cli.flag("--direct", "direct illumination only: the same as --depth 1", &direct);
    std::string estimator = "mis";
    cli.choice("--estimator", "how light reaching a surface is found",
               {"nee", "bsdf", "mis"}, &estimator);
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
    TemporalOptions temporal;
    declareTemporalOptions(cli, temporal);  // --blend, --move, --move-frames, --frames-out
    return course::run(cli, argc, argv, [&](course::Session& session) {
        const course::Options& options = session.options();
        const int width = options.width, height = options.height;
        if (direct) depth = 1;
        checkTemporalOptions(temporal);

        // 1. The scene file, its meshes, images and environment, and the packed arrays
        //    (exit code 3 on mistakes).
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
        // 3. Chapter 09's seeding, and frames of samples: what a dispatch reads besides
        //    the buffers is gpu::PathParameters (shared.h), written before each one.
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
        // The frames' blend, into the denoiser's inputs (the views: each frame as it is).
        const bool blending = view == "radiance";
        if (!blending) denoise.filter = "none";
        Denoiser denoiser(session, width, height, denoise);
        TemporalAccumulator accumulator(session, width, height, temporal.blend,
                                        denoiser.features(), denoiser.reflected());
        const course::ImageBuffer& picture =
            denoiser.picture(blending ? accumulator.picture() : image);
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
        // One frame: `count` samples from where the camera is, blended, denoised.
        auto drawFrame = [&](int count) {
            samples = 0;  // this frame's own means start over; the streams go on
            while (int(samples) < count) addSample();
            course::waitForGpu();  // a frame at a time (chapter 28's --batches)
            if (blending) accumulator.blend(parameters.camera, samples);
            denoiser.run(samples);
        };
        // Headless: --move-frames frames of --spp samples, the camera stepping --move
        // between them (one frame standing still is chapter 28's picture).
        auto render = [&] {
            parameterBuffer.write(&parameters, sizeof parameters);
            seed.dispatchCovering(width, height);
            accumulator.restart();
            for (int number = 1; number <= temporal.moveFrames; ++number) {
                if (number > 1) fly.eye += temporal.move;
                drawFrame(options.spp);
                writeFrame(temporal.framesOut, number, picture);  // --frames-out, if given
            }
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
            picture.pixels.bindStorage(PIXELS_BINDING);  // what is shown
            toDisplay.dispatchCovering(width, height);
            image.pixels.bindStorage(PIXELS_BINDING);  // the path tracer's, again
        });
        // --8<-- [end:display]
        session.timeRender(render, samples);  // 5. The frames; headless, --out the last.
        // --8<-- [start:window]
        // 6. Window: a frame of one sample each time, blended (the camera may move, or
        //    --move it); - and = change the exposure by half a stop, T the tone mapping.
        glm::dvec2 lastCursor(-1.0);
        course::KeyPresses keys;
        auto lastFrame = std::chrono::steady_clock::now();
        auto eachFrame = [&](int frame) {
            auto now = std::chrono::steady_clock::now();
            float seconds = std::chrono::duration<float>(now - lastFrame).count();
            lastFrame = now;
            fly.update(course::readFlyInput(session.context().window(), lastCursor, seconds));
            fly.eye += temporal.move;
            adjustDisplay(session.context().window(), keys, parameters);
            drawFrame(1);  // every frame: the picture shown is the blend, denoised
        };
        // --8<-- [end:window]
        session.finish(picture, render, eachFrame);
        denoiser.writeAuxiliary(samples);
        // 7. Statistics: the last frame's rays and samples, and its pixels without history.
        std::vector<uint32_t> counts = rayCounts.readAll<uint32_t>();
        session.stats().set("rays", std::accumulate(counts.begin(), counts.end(), 0.0));
        session.stats().set("samples_per_pixel", double(samples));
        if (blending) session.stats().set("fresh_pixels", double(accumulator.freshPixels()));
        if (!session.isWindow()) {  // every frame's samples, over the whole render's time
            double all = double(width) * height * samples * temporal.moveFrames;
            session.stats().set("frames", double(temporal.moveFrames));
            session.stats().set("samples_per_second",
                                all / (session.stats().number("wall_ms") / 1000.0));
        }
    });
}
