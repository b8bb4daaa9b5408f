// Chapter 07: a mesh from a file. A hand-written OBJ reader turns the teapot into
// positions and triangle indices, two storage buffers carry them to the GPU, and the
// camera frames whatever mesh it is given.
#include <string>

#include "camera.h"
#include "course/loop_budget.h"
#include "course/session.h"
#include "obj_loader.h"
#include "scene.h"
#include "shared.h"  // bindings, the tile size and the triangle struct, shared with GLSL

// Without --obj: the teapot of 552 triangles the build tessellates (cmake/Assets.cmake).
const std::string kDefaultMesh = COURSE_GENERATED_ASSET_DIR "/meshes/teapot_552.obj";

int main(int argc, char** argv) {
    course::CommandLine cli("Chapter 07: a triangle mesh from an OBJ file, framed for you");
    cli.acceptObj();  // --obj FILE
    bool packedVec3Bug = false;
    cli.flag("--packed-vec3", "upload positions as 12-byte glm::vec3s: the std430 bug",
             &packedVec3Bug);
    bool noShadowOffset = false;
    cli.flag("--no-shadow-offset", "start shadow rays on the surface: shadow acne",
             &noShadowOffset);
    bool noNormalFlip = false;
    cli.flag("--no-normal-flip", "keep triangle normals as wound, even seen from behind",
             &noNormalFlip);
    return course::run(cli, argc, argv, [&](course::Session& session) {
        const int width = session.options().width, height = session.options().height;

        // --8<-- [start:load]
        // 1. Read the mesh. Any problem in the file is exit code 3 with file:line.
        const std::string& objOption = session.options().objPath;
        const std::string objPath = objOption.empty() ? kDefaultMesh : objOption;
        Mesh mesh = loadObj(objPath);
        session.stats().set("triangles", double(mesh.triangleCount()));

        //    Every ray tests every triangle in a loop: up to two loops over them all per
        //    pixel (the camera ray's, the shadow ray's). Where the GL ends long loops
        //    silently (Mesa 22's llvmpipe: 65535 iterations), a mesh too big for that
        //    is refused (exit code 4) rather than drawn wrong.
        course::checkLoopBudget({objPath, mesh.triangleCount() + 2,  // + the floor's 2
                                 "triangles (with the floor's 2)", 2,
                                 "Chapter 13's BVH renders this mesh."});

        //    The scene around the mesh, from its bounds: camera, floor and light.
        Scene scene = sceneAround(mesh, objPath, width, height);
        // --8<-- [end:load]

        // --8<-- [start:upload]
        // 2. Two storage buffers: positions as vec4 (w unused), because a std430 array
        //    of vec3 has a 16-byte stride too, and triangles as three indices each.
        auto positions = course::GpuBuffer::fromVector(scene.positions);
        if (packedVec3Bug)  // the mistake, on purpose: vertex i lands 4 * i bytes early
            positions = course::GpuBuffer::fromVector(packedVec3(scene.positions));
        positions.bindStorage(POSITIONS_BINDING);
        auto triangles = course::GpuBuffer::fromVector(scene.triangles);
        triangles.bindStorage(TRIANGLES_BINDING);
        // --8<-- [end:upload]

        // --8<-- [start:setup]
        // 3. The image, and the shader that traces one ray per pixel in 8x8 tiles.
        course::ImageBuffer image(width, height);
        image.pixels.bindStorage(PIXELS_BINDING);
        course::ShaderProgram& trace = session.loadCompute("trace.comp");
        setCamera(trace, scene.camera);
        trace.set("imageSize", glm::uvec2(width, height));
        trace.set("lightPosition", scene.lightPosition);
        trace.set("shadowOffset", noShadowOffset ? 0.0f : scene.shadowOffset);
        trace.set("flipNormals", int(!noNormalFlip));  // two-sided triangles
        // --8<-- [end:setup]

        // 4. Trace, then write the PNG (headless) or show it (--window).
        auto render = [&] { trace.dispatchCovering(width, height); };
        session.timeRender(render);
        session.finish(image, render);
    });
}
