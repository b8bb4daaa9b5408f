// A scene file (course/scene_file.h) turned into the arrays the shaders read: spheres,
// quads, the triangles as chapter 09 kept its mesh (corner indices into positions and
// normals, meshes placed in the world), materials, the emitters that next-event
// estimation samples, and the bounding volume hierarchy over the triangles.
#pragma once
#include <cstddef>
#include <string>
#include <vector>

#include "bvh.h"
#include "course/scene_file.h"
#include "obj_loader.h"
#include "shared.h"  // the gpu:: structs, laid out as the shaders read them

struct GpuScene {
    std::vector<gpu::Sphere> spheres;
    std::vector<gpu::Quad> quads;
    std::vector<gpu::Triangle> triangles;  // in the tree's leaf order
    std::vector<glm::vec4> positions;      // the triangles' corners, in the world; w unused
    std::vector<glm::vec4> normals;        // the normals at the corners, unit; w unused
    std::vector<gpu::Material> materials;
    std::vector<gpu::Emitter> emitters;
    Bvh bvh;            // over `triangles`: its nodes go to BVH_NODES_BINDING
    float size = 1.0f;  // the diagonal of the scene's bounding box: how fast to fly

    size_t shapeCount() const { return spheres.size() + quads.size() + triangles.size(); }
};

// The OBJ files the scene's `mesh` lines name, in their order (chapter 07's loader;
// exit code 3 with file:line).
std::vector<Mesh> loadMeshes(const course::SceneFile& scene);

// --obj: one more mesh in the scene, of the scene's first non-emitting material,
// standing on the floor (the lowest point of the quads) in the middle of the room,
// scaled to half of the room's width or depth, whichever is smaller.
void placeMeshInRoom(course::SceneFile& scene, std::vector<Mesh>& meshes, Mesh mesh,
                     const std::string& path);

// Packs everything, builds the tree over all triangles (meshes included) and puts the
// triangles in its leaf order.
GpuScene packScene(const course::SceneFile& scene, const std::vector<Mesh>& meshes,
                   const BvhOptions& bvhOptions = {});
