// Chapter 13: a bounding volume hierarchy. Testing every triangle for every ray costs
// time in proportion to the mesh; a tree of boxes, built once on the CPU, lets a ray
// skip every triangle in a box it misses, and a million triangles render like a few
// thousand. Chapter 12's path tracer, its triangles found through the tree.
#include <algorithm>
#include <chrono>
#include <numeric>
#include <string>

#include "camera.h"
#include "course/fly_camera.h"
#include "course/loop_budget.h"
#include "course/scene_file.h"
#include "course/session.h"
#include "gpu_scene.h"
#include "scene_support.h"  // kSceneSupport: what it reads, from its manifest
#include "shared.h"  // bindings and std430 structs, shared with GLSL

int main(int argc, char** argv) {
    course::CommandLine cli("Chapter 13: path tracing through a bounding volume hierarchy");
    cli.acceptScene();  // --scene NAME|FILE, default cornell_teapot
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
    std::string view = "radiance";
    cli.choice("--view", "what the image shows: the path traced light, what the camera "
               "rays hit (normals, distance in metres) or the traversal's work per pixel "
               "(cost)", {"radiance", "normals", "distance", "cost"}, &view);
    bool scriptCameraMove = false;
    cli.flag("--script-camera-move", "window mode: step forward at frame 2 (tests)",
             &scriptCameraMove);
    return course::run(cli, argc, argv, [&](course::Session& session) {
        const course::Options& options = session.options();
        const int width = options.width, height = options.height;
        if (direct) depth = 1;

        // 1. The scene file, its meshes, and the packed arrays (exit code 3 on mistakes).
        course::SceneFile sceneFile = course::loadSceneFile(
            session.scenePath("cornell_teapot"), {COURSE_GENERATED_ASSET_DIR},
            kSceneSupport);
        GpuScene scene = packScene(sceneFile);
        // The camera ray and each bounce loop over the spheres and quads twice (nearest
        // hit, shadow ray); the tree finds the triangles in a few hundred steps a ray.
        course::checkLoopBudget({sceneFile.path, scene.spheres.size() + scene.quads.size(),
                                 "spheres and quads at --depth " + std::to_string(depth),
                                 2 * (size_t(depth) + 1),
                                 "A lower --depth, or fewer spheres and quads, fit."});
        session.stats().set("shapes", double(scene.shapeCount()));
        session.stats().set("triangles", double(scene.triangles.size()));
        session.stats().set("emitters", double(scene.emitters.size()));

        // --8<-- [start:upload]
        // 2. Storage buffers: the scene (the triangles' corners and normals as in
        //    chapter 09), the image (the running mean), each pixel's random number
        //    state and ray count.
        auto spheres = course::GpuBuffer::fromVector(scene.spheres);
        auto quads = course::GpuBuffer::fromVector(scene.quads);
        auto triangles = course::GpuBuffer::fromVector(scene.triangles);
        auto positions = course::GpuBuffer::fromVector(scene.positions);
        auto normals = course::GpuBuffer::fromVector(scene.normals);
        auto materials = course::GpuBuffer::fromVector(scene.materials);
        auto emitters = course::GpuBuffer::fromVector(scene.emitters);
        auto bvhNodes = course::GpuBuffer::fromVector(scene.bvh.nodes);
        course::ImageBuffer image(width, height);
        course::GpuBuffer randomStates(size_t(width) * height * sizeof(glm::uvec4));
        course::GpuBuffer rayCounts(size_t(width) * height * sizeof(uint32_t));
        spheres.bindStorage(SPHERES_BINDING);
        quads.bindStorage(QUADS_BINDING);
        triangles.bindStorage(TRIANGLES_BINDING);
        positions.bindStorage(POSITIONS_BINDING);
        normals.bindStorage(NORMALS_BINDING);
        materials.bindStorage(MATERIALS_BINDING);
        emitters.bindStorage(EMITTERS_BINDING);
        bvhNodes.bindStorage(BVH_NODES_BINDING);
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
        gpu::PathParameters parameters{};
        parameters.imageSize = glm::uvec2(width, height);
        parameters.seed = options.seed;
        parameters.maxBounces = depth;
        parameters.estimator = estimator == "nee"    ? ESTIMATOR_NEE
                               : estimator == "bsdf" ? ESTIMATOR_BSDF
                                                     : ESTIMATOR_MIS;
        parameters.view = view == "normals"    ? VIEW_NORMALS
                          : view == "distance" ? VIEW_DISTANCE
                          : view == "cost"     ? VIEW_COST
                                               : VIEW_RADIANCE;
        course::GpuBuffer parameterBuffer(sizeof parameters);
        parameterBuffer.bindUniform(PARAMETERS_BINDING);
        unsigned samples = 0;
        auto addSample = [&] {
            glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);  // read what the last wrote
            parameters.camera = pinholeCamera(
                makeCamera(fly.eye, fly.forward(), c.up, c.focalLength, c.sensorWidth));
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
        };
        // --8<-- [end:dispatch]

        // 4. Render --spp samples; headless, write the image (PFM: the linear mean;
        //    PNG: clamped to [0, 1] and sRGB-encoded).
        session.timeRender(render, samples);

        // --8<-- [start:window]
        // 5. Window: one more sample each frame; moving the camera starts over.
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
            addSample();
        };
        // --8<-- [end:window]
        session.finish(image, render, eachFrame);

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
