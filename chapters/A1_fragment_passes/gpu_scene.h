// A scene file (course/scene_file.h) turned into the arrays the shaders read: spheres,
// quads, materials, the triangles as chapter 09 kept its mesh, corner indices into
// positions and normals (meshes placed in the world), and the list of emitters that
// next-event estimation samples.
#pragma once
#include <cstddef>
#include <string>
#include <vector>

#include "course/scene_file.h"
#include "shared.h"  // the gpu:: structs, laid out as the shaders read them

struct GpuScene {
    std::vector<gpu::Sphere> spheres;
    std::vector<gpu::Quad> quads;
    std::vector<gpu::Triangle> triangles;
    std::vector<glm::vec4> positions;  // the triangles' corners, in the world; w unused
    std::vector<glm::vec4> normals;    // the normals at the corners, unit; w unused
    std::vector<gpu::Material> materials;
    std::vector<gpu::Emitter> emitters;
    float size = 1.0f;  // the diagonal of the scene's bounding box: how fast to fly

    size_t shapeCount() const { return spheres.size() + quads.size() + triangles.size(); }
};

// Loads the scene's meshes (chapter 07's OBJ loader; exit code 3 with file:line) and
// packs everything.
GpuScene packScene(const course::SceneFile& scene);
