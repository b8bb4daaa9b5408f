// Chapter 09: random numbers. Every pixel gets its own generator, seeded once per image
// and kept in a storage buffer, so each dispatch continues where the last one stopped.
// With them: anti-aliasing (each sample's ray through a random point of the pixel),
// a running mean over dispatches, and two views that show whether the numbers are good.
#include <string>

#include "camera.h"
#include "course/loop_budget.h"
#include "course/session.h"
#include "normals.h"
#include "obj_loader.h"
#include "random_dump.h"
#include "scene.h"
#include "shared.h"  // bindings, the tile size and the triangle struct, shared with GLSL

// Without --obj: the teapot of 552 triangles the build tessellates (cmake/Assets.cmake).
const std::string kDefaultMesh = COURSE_GENERATED_ASSET_DIR "/meshes/teapot_552.obj";

int main(int argc, char** argv) {
    course::CommandLine cli("Chapter 09: random numbers, anti-aliasing, accumulation");
    cli.acceptObj();  // --obj FILE
    std::string seeding = "hashed", view = "shaded", dumpPath;
    cli.choice("--seeding", "how each pixel's generator starts from --seed",
               {"hashed", "naive"}, &seeding);
    cli.choice("--view", "shaded: the lit mesh; noise: each pixel's random numbers as "
               "grey; ao: ambient occlusion", {"shaded", "noise", "ao"}, &view);
    int batches = 1, count = 4;
    cli.option("--batches", "B", "render --spp in B groups of dispatches, waiting for "
               "the GPU between them (the same image)", &batches, 1, 1 << 20);
    cli.option("--dump-random", "FILE", "after the render, write the next --count "
               "numbers of every pixel as uint32", &dumpPath);
    cli.option("--count", "K", "how many numbers --dump-random writes", &count, 1, 4096);
    return course::run(cli, argc, argv, [&](course::Session& session) {
        const int width = session.options().width, height = session.options().height;
        const int spp = session.options().spp;

        // 1. The scene of chapter 08: the mesh with normals, floor, camera and light.
        const std::string& objOption = session.options().objPath;
        const std::string objPath = objOption.empty() ? kDefaultMesh : objOption;
        Mesh mesh = loadObj(objPath);
        session.stats().set("triangles", double(mesh.triangleCount()));
        // A sample loops over every triangle at most twice: the camera ray's nearest hit,
        // then the shadow ray (or --view ao's ray). Too many for the GL: exit code 4.
        course::checkLoopBudget({objPath, mesh.triangleCount() + 2,  // + the floor's 2
                                 "triangles (with the floor's 2)", 2,
                                 "Chapter 13's BVH renders this mesh."});
        if (mesh.normalIndices.empty()) {
            mesh.normals = areaWeightedNormals(mesh.positions, mesh.positionIndices);
            mesh.normalIndices = mesh.positionIndices;
        }
        Scene scene = sceneAround(mesh, objPath, width, height);
        auto positions = course::GpuBuffer::fromVector(scene.positions);
        positions.bindStorage(POSITIONS_BINDING);
        auto triangles = course::GpuBuffer::fromVector(scene.triangles);
        triangles.bindStorage(TRIANGLES_BINDING);
        auto normals = course::GpuBuffer::fromVector(scene.normals);
        normals.bindStorage(NORMALS_BINDING);

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
        setCamera(trace, scene.camera);
        trace.set("imageSize", glm::uvec2(width, height));
        trace.set("lightPosition", scene.lightPosition);
        trace.set("shadowOffset", scene.shadowOffset);
        trace.set("view", view == "noise" ? VIEW_NOISE : view == "ao" ? VIEW_AO : VIEW_SHADED);
        trace.set("aoDistance", 0.5f * scene.radius);

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
