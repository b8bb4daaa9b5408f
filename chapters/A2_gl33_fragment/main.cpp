// Appendix A2: appendix A1's fragment-shader path tracer on OpenGL 3.3, for machines
// without compute shaders or storage buffers (macOS stops at 4.1). The shapes are in a
// buffer texture, the materials and lights in a uniform buffer; as in A1, a fragment
// shader draws one sample per pixel per pass, and two framebuffers take turns.
#include <algorithm>
#include <chrono>
#include <numeric>
#include <string>

#include "accumulation.h"
#include "camera.h"
#include "course/fly_camera.h"
#include "course/loop_budget.h"
#include "course/scene_file.h"
#include "course/session.h"
#include "gpu_scene.h"
#include "scene_buffers.h"
#include "scene_support.h"  // kSceneSupport: what it reads, from its manifest
#include "shared.h"  // texture units, outputs and the std140 block, shared with GLSL

int main(int argc, char** argv) {
    course::CommandLine cli("Appendix A2: the path tracer as an OpenGL 3.3 fragment shader");
    cli.acceptScene();  // --scene NAME|FILE, default cornell_spheres
    int depth = 6, batches = 1, frameSamples = 4;
    cli.option("--depth", "N", "surface bounces a path may make (1: direct light)", &depth,
               1, 1000);
    bool direct = false;
    cli.flag("--direct", "direct illumination only: the same as --depth 1", &direct);
    std::string estimator = "mis";
    cli.choice("--estimator", "how light reaching a surface is found",
               {"nee", "bsdf", "mis"}, &estimator);
    cli.option("--batches", "B", "render --spp in B groups of passes, waiting for "
               "the GPU between them (the same image)", &batches, 1, 1 << 20);
    cli.option("--frame-samples", "N", "window mode: samples added per frame", &frameSamples,
               1, 64);
    bool scriptCameraMove = false;
    cli.flag("--script-camera-move", "window mode: step forward at frame 2 (tests)",
             &scriptCameraMove);
    const course::GlVersion gl33{3, 3};  // no compute shaders, no storage buffers
    return course::run(cli, argc, argv, [&](course::Session& session) {
        const course::Options& options = session.options();
        const int width = options.width, height = options.height;
        if (direct) depth = 1;

        // 1. The scene file, its meshes, and the packed texels and uniform block (exit
        //    code 3 on mistakes, or when the block's arrays are too small).
        course::SceneFile sceneFile = course::loadSceneFile(
            session.scenePath("cornell_spheres"), {COURSE_GENERATED_ASSET_DIR},
            kSceneSupport);
        GpuScene scene = packScene(sceneFile);
        // The camera ray and each bounce loop over every shape twice (nearest hit,
        // shadow ray): a GL's loop limit caps shapes x bounces (chapter 07), and it is
        // measured for fragment shaders here.
        course::checkLoopBudget({sceneFile.path, scene.shapeCount(),
                                 "shapes at --depth " + std::to_string(depth),
                                 2 * (size_t(depth) + 1), "A lower --depth renders it.",
                                 GL_FRAGMENT_SHADER});
        session.stats().set("shapes", double(scene.shapeCount()));
        session.stats().set("emitters", double(scene.block->emitterCount));

        // --8<-- [start:upload]
        // 2. The scene in a buffer texture and a uniform buffer; the two framebuffers
        //    that take turns; the image buffer the session writes or shows.
        SceneBuffers sceneBuffers(scene, sceneFile.path);
        Accumulation accumulation(width, height);
        course::ImageBuffer image(width, height);
        // --8<-- [end:upload]

        // --8<-- [start:passes]
        // 3. Chapter 12's seeding and progressive loop, a pass where it had a dispatch,
        //    and its PathParameters block, written before each pass.
        course::ShaderProgram& seed = session.loadProgram(
            {{GL_FRAGMENT_SHADER, "seed.frag"}, {GL_VERTEX_SHADER, "fullscreen.vert"}});
        course::ShaderProgram& path = session.loadProgram(
            {{GL_FRAGMENT_SHADER, "path.frag"}, {GL_VERTEX_SHADER, "fullscreen.vert"}});
        const course::SceneCamera& c = sceneFile.camera;
        course::FlyCamera fly = course::FlyCamera::looking(c.eye, c.look, 0.25f * scene.size);
        gpu::PathParameters parameters{};
        parameters.imageSize = glm::uvec2(width, height);
        parameters.seed = options.seed;
        parameters.maxBounces = depth;
        parameters.estimator = estimator == "nee"    ? ESTIMATOR_NEE
                               : estimator == "bsdf" ? ESTIMATOR_BSDF
                                                     : ESTIMATOR_MIS;
        course::GpuBuffer parameterBuffer(sizeof parameters);
        parameterBuffer.bindUniform(PARAMETERS_BINDING);
        unsigned samples = 0;
        auto addSample = [&] {
            parameters.camera = pinholeCamera(
                makeCamera(fly.eye, fly.forward(), c.up, c.focalLength, c.sensorWidth));
            parameters.sampleIndex = samples++;
            parameterBuffer.write(&parameters, sizeof parameters);
            // GLSL 3.30 has no layout(binding): blocks are connected by name, every pass,
            // as a hot-reloaded program starts without that.
            path.bindUniformBlock("PathParameters", PARAMETERS_BINDING);
            sceneBuffers.bind(path);
            accumulation.draw(path);  // no barrier: GL orders draws and texture reads
        };
        auto render = [&] {
            parameterBuffer.write(&parameters, sizeof parameters);
            seed.bindUniformBlock("PathParameters", PARAMETERS_BINDING);
            accumulation.draw(seed);
            samples = 0;
            for (int batch = 0; batch < batches; ++batch) {
                int end = options.spp * (batch + 1) / batches;  // --batches: the same
                while (int(samples) < end) addSample();         // passes, the GPU
                course::waitForGpu();                           // idle in between
            }
            accumulation.copyMeanTo(image);
        };
        // --8<-- [end:passes]

        // 4. Render --spp samples; headless, write the image (PFM: the linear mean;
        //    PNG: clamped to [0, 1] and sRGB-encoded).
        session.timeRender(render, samples);

        // --8<-- [start:window]
        // 5. Window: a few samples each frame, so the picture keeps up with the camera;
        //    moving the camera starts over.
        glm::dvec2 lastCursor(-1.0);
        auto lastFrame = std::chrono::steady_clock::now();
        auto eachFrame = [&](int frame) {
            auto now = std::chrono::steady_clock::now();
            float seconds = std::chrono::duration<float>(now - lastFrame).count();
            lastFrame = now;
            course::FlyInput input =
                course::readFlyInput(session.context().window(), lastCursor, seconds);
            if (scriptCameraMove && frame == 2) input = {{0, 0, 1}, {0, 0}, 1.0f};
            if (fly.update(input)) samples = 0;  // start over; the streams go on
            for (int i = 0; i < frameSamples; ++i) addSample();
            accumulation.copyMeanTo(image);
        };
        // --8<-- [end:window]
        session.finish(image, render, eachFrame);

        // 6. Statistics: every ray the shader traced (camera, bounce and shadow rays).
        std::vector<uint32_t> counts = accumulation.readRayCounts();
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
    }, gl33);
}
