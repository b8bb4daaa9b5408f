// A scene file (course/scene_file.h) turned into what the shaders read: the shapes as
// texels of one buffer texture (spheres, quads, and the triangles as chapter 09 kept its
// mesh, corner indices into positions and normals, meshes placed in the world), and the
// materials and the emitters that next-event estimation samples as one uniform block.
#pragma once
#include <cstddef>
#include <memory>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "course/scene_file.h"
#include "shared.h"  // the texel layout and gpu::SceneBlock, as the shaders read them

struct GpuScene {
    std::vector<glm::vec4> texels;  // SPHERE_TEXELS per sphere, then quads, ... (shared.h)
    std::unique_ptr<gpu::SceneBlock> block = std::make_unique<gpu::SceneBlock>();
    float size = 1.0f;  // the diagonal of the scene's bounding box: how fast to fly

    size_t shapeCount() const {
        return size_t(block->sphereCount) + block->quadCount + block->triangleCount;
    }
};

// Loads the scene's meshes (chapter 07's OBJ loader; exit code 3 with file:line) and
// packs everything. More materials or emitters than the uniform block holds
// (MAX_MATERIALS, MAX_EMITTERS), or more than 2^24 corners, is exit code 3, naming the
// scene file.
GpuScene packScene(const course::SceneFile& scene);
