// A scene file (course/scene_file.h) turned into the arrays the shaders read: spheres,
// quads, materials, the triangles as chapter 09 kept its mesh, corner indices into
// positions and normals (meshes placed in the world), and the list of emitters that
// next-event estimation samples. And the bounding volume hierarchy over the triangles,
// the meshes' texture coordinates, and the textures (textures.h).
#pragma once
#include <cstddef>
#include <string>
#include <vector>

#include "bvh.h"
#include "course/gpu_buffer.h"
#include "course/scene_file.h"
#include "course/stats.h"
#include "shared.h"  // the gpu:: structs, laid out as the shaders read them

struct GpuScene {
    std::vector<gpu::Sphere> spheres;
    std::vector<gpu::Quad> quads;
    std::vector<gpu::Triangle> triangles;
    std::vector<glm::vec4> positions;  // the triangles' corners, in the world; w unused
    std::vector<glm::vec4> normals;    // the normals at the corners, unit; w unused
    std::vector<glm::vec2> uvs;        // the corners' texture coordinates (OBJ vt)
    std::vector<gpu::Material> materials;
    std::vector<gpu::Emitter> emitters;
    std::vector<gpu::Texture> textures;
    std::vector<glm::vec4> texels;  // every image's texels, linear RGB; w unused
    Bvh bvh;  // over `triangles`, which are in its leaf order
    std::vector<gpu::BvhBox> boxes;  // its boxes threaded (threaded_tree.h): BVH_NODES_BINDING
    float size = 1.0f;  // the diagonal of the scene's bounding box: how fast to fly

    size_t shapeCount() const { return spheres.size() + quads.size() + triangles.size(); }
};

// The scene's sizes in --json: shapes, triangles, emitters, textures, texels, the
// tree's statistics (recordBvhStats) and its threaded boxes' bytes (bvh_box_bytes).
void recordSceneStats(const GpuScene& scene, course::Stats& stats);

// Loads the scene's meshes (chapter 07's OBJ loader; exit code 3 with file:line) and
// packs everything, then builds the tree over the triangles and puts them in its order.
GpuScene packScene(const course::SceneFile& scene, const BvhOptions& bvhOptions = {});

// The scene's storage buffers, each bound at its binding point (shared.h), with the
// environment's sampling tables (environment.h); and, as the scene code chose
// (scene_code.h), buffer textures over some of them or uniform blocks.
struct SceneBuffers {
    course::GpuBuffer spheres, quads, triangles, positions, normals, materials, emitters,
        bvhBoxes, uvs, textures, texels, environmentCdf, leafCorners;
    std::vector<course::BufferTexture> bufferTextures;
    std::vector<course::GpuBuffer> uniformBlocks;
};
SceneBuffers uploadScene(const GpuScene& scene, const std::vector<float>& environmentCdf,
                         int sceneMemory, int bvhMemory);
