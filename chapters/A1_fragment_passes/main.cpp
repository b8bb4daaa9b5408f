// Appendix A1: chapter 12's path tracer as a fragment shader, the first step towards
// machines without compute shaders (appendix A2). Each sample is a pass that draws one
// triangle over the whole image, so that the fragment shader runs once per pixel; two
// framebuffers take turns holding the running mean, the generators and the ray counts.
// The scene stays in chapter 12's storage buffers (OpenGL 4.3).
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
#include "scene_support.h"  // kSceneSupport: what it reads, from its manifest
#include "shared.h"  // bindings and std430 structs, shared with GLSL

int main(int argc, char** argv) {
    course::CommandLine cli("Appendix A1: the path tracer as a fragment shader");
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
    return course::run(cli, argc, argv, [&](course::Session& session) {
        const course::Options& options = session.options();
        const int width = options.width, height = options.height;
        if (direct) depth = 1;

        // 1. The scene file, its meshes, and the packed arrays (exit code 3 on mistakes).
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
        session.stats().set("emitters", double(scene.emitters.size()));

        // --8<-- [start:upload]
        // 2. Chapter 12's storage buffers for the scene; the two framebuffers that take
        //    turns; the image buffer the session writes or shows.
        auto spheres = course::GpuBuffer::fromVector(scene.spheres);
        auto quads = course::GpuBuffer::fromVector(scene.quads);
        auto triangles = course::GpuBuffer::fromVector(scene.triangles);
        auto positions = course::GpuBuffer::fromVector(scene.positions);
        auto normals = course::GpuBuffer::fromVector(scene.normals);
        auto materials = course::GpuBuffer::fromVector(scene.materials);
        auto emitters = course::GpuBuffer::fromVector(scene.emitters);
        Accumulation accumulation(width, height);
        course::ImageBuffer image(width, height);
        spheres.bindStorage(SPHERES_BINDING);
        quads.bindStorage(QUADS_BINDING);
        triangles.bindStorage(TRIANGLES_BINDING);
        positions.bindStorage(POSITIONS_BINDING);
        normals.bindStorage(NORMALS_BINDING);
        materials.bindStorage(MATERIALS_BINDING);
        emitters.bindStorage(EMITTERS_BINDING);
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
            accumulation.draw(path);  // no barrier: GL orders draws and texture reads
        };
        auto render = [&] {
            parameterBuffer.write(&parameters, sizeof parameters);
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
    });
}
