// Chapter 10: scenes. A text file describes spheres, quads and meshes, each with a
// material, and the camera; the program packs them into storage buffers and the shader
// finds the nearest of every kind of shape. A preview shows them: each surface's glow,
// plus its colour darkened by chapter 09's ambient occlusion. Chapter 11 lights them.
#include <string>

#include "camera.h"
#include "course/loop_budget.h"
#include "course/scene_file.h"
#include "course/session.h"
#include "gpu_scene.h"
#include "random_dump.h"
#include "scene_support.h"  // kSceneSupport: what it reads, from its manifest
#include "shared.h"  // bindings and std430 structs, shared with GLSL

int main(int argc, char** argv) {
    course::CommandLine cli("Chapter 10: scenes from files, previewed with ambient occlusion");
    cli.acceptScene();  // --scene NAME|FILE, default cornell_spheres
    std::string seeding = "hashed", view = "shaded", dumpPath;
    cli.choice("--seeding", "how each pixel's generator starts from --seed",
               {"hashed", "naive"}, &seeding);
    cli.choice("--view", "shaded: glow plus colour times ambient occlusion; noise: each "
               "pixel's random numbers as grey; ao: ambient occlusion alone",
               {"shaded", "noise", "ao"}, &view);
    float aoDistance = 0.0f;
    cli.option("--ao-distance", "M", "how far an occluder counts, in metres (default: a "
               "quarter of the scene's size)", &aoDistance);
    int batches = 1, count = 4;
    cli.option("--batches", "B", "render --spp in B groups of dispatches, waiting for "
               "the GPU between them (the same image)", &batches, 1, 1 << 20);
    cli.option("--dump-random", "FILE", "after the render, write the next --count "
               "numbers of every pixel as uint32", &dumpPath);
    cli.option("--count", "K", "how many numbers --dump-random writes", &count, 1, 4096);
    return course::run(cli, argc, argv, [&](course::Session& session) {
        const int width = session.options().width, height = session.options().height;
        const int spp = session.options().spp;

        if (aoDistance < 0.0f)
            course::fail(course::ExitCode::BadUsage, "--ao-distance must not be negative");

        // 1. The scene file, its meshes, and the packed arrays (exit code 3 on mistakes).
        course::SceneFile sceneFile = course::loadSceneFile(
            session.scenePath("cornell_spheres"), {COURSE_GENERATED_ASSET_DIR},
            kSceneSupport);
        GpuScene scene = packScene(sceneFile);
        // The camera ray and the occlusion ray loop over every shape: a GL's loop limit
        // caps the shapes (chapter 07).
        course::checkLoopBudget({sceneFile.path, scene.shapeCount(), "shapes", 2,
                                 "Chapter 13's BVH renders it."});
        session.stats().set("shapes", double(scene.shapeCount()));

        // --8<-- [start:upload]
        // The scene in storage buffers: the triangles' corners and normals as in
        // chapter 09, spheres, quads and the materials all their shapes name.
        auto spheres = course::GpuBuffer::fromVector(scene.spheres);
        auto quads = course::GpuBuffer::fromVector(scene.quads);
        auto triangles = course::GpuBuffer::fromVector(scene.triangles);
        auto positions = course::GpuBuffer::fromVector(scene.positions);
        auto normals = course::GpuBuffer::fromVector(scene.normals);
        auto materials = course::GpuBuffer::fromVector(scene.materials);
        spheres.bindStorage(SPHERES_BINDING);
        quads.bindStorage(QUADS_BINDING);
        triangles.bindStorage(TRIANGLES_BINDING);
        positions.bindStorage(POSITIONS_BINDING);
        normals.bindStorage(NORMALS_BINDING);
        materials.bindStorage(MATERIALS_BINDING);
        // --8<-- [end:upload]

        // --8<-- [start:state]
        // 2. One generator state (a uvec4, 16 bytes) per pixel, on the GPU for the
        //    whole run, and the shader that seeds them all from --seed.
        course::GpuBuffer randomStates(size_t(width) * size_t(height) * 16);
        randomStates.bindStorage(RANDOM_BINDING);
        course::ShaderProgram& seed = session.loadCompute("seed.comp");
        seed.set("imageSize", glm::uvec2(width, height));
        seed.set("seed", unsigned(session.options().seed));
        seed.set("naiveSeeding", int(seeding == "naive"));
        // --8<-- [end:state]

        // 3. The image, which holds the mean of the samples so far, and the tracer.
        course::ImageBuffer image(width, height);
        image.pixels.bindStorage(PIXELS_BINDING);
        course::ShaderProgram& trace = session.loadCompute("trace.comp");
        const course::SceneCamera& c = sceneFile.camera;
        setCamera(trace, makeCamera(c.eye, c.look, c.up, c.focalLength, c.sensorWidth));
        trace.set("imageSize", glm::uvec2(width, height));
        trace.set("view", view == "noise" ? VIEW_NOISE : view == "ao" ? VIEW_AO : VIEW_SHADED);
        trace.set("aoDistance", aoDistance > 0.0f ? aoDistance : 0.25f * scene.size);

        // --8<-- [start:progressive]
        // 4. One sample per pixel per dispatch: Mesa 22's llvmpipe stops an invocation
        //    after 65535 loop iterations, so a dispatch must stay small. Every dispatch
        //    reads the state and the mean the one before wrote: a barrier between.
        unsigned samples = 0;
        auto addSample = [&] {
            glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
            trace.set("sampleIndex", samples++);
            trace.dispatchCovering(width, height);
        };
        // A new picture: seed every pixel's generator, forget the samples.
        auto startOver = [&] {
            seed.dispatchCovering(width, height);
            samples = 0;
        };
        auto render = [&] {
            startOver();
            for (int batch = 0; batch < batches; ++batch) {
                int end = spp * (batch + 1) / batches;  // --batches: the same dispatches,
                while (int(samples) < end) addSample();
                course::waitForGpu();                   // with the GPU idle in between
            }
        };
        // --8<-- [end:progressive]

        // 5. Render --spp samples; then headless: write the image (and --dump-random);
        //    --window: add one sample per frame, and start over after a hot reload.
        session.timeRender(render, samples);
        session.stats().set("samples_per_pixel", double(samples));
        if (!dumpPath.empty()) dumpRandomNumbers(session, width, height, count, dumpPath);
        session.finish(image, render, [&](int) { addSample(); });
    });
}
