// A scene file (course/scene_file.h) turned into the arrays the shaders read: spheres,
// quads, materials, the triangles as chapter 09 kept its mesh, corner indices into
// positions and normals (meshes placed in the world), and the list of emitters that
// next-event estimation samples. And the bounding volume hierarchy over the triangles,
// the meshes' texture coordinates, and the textures (textures.h). And the objects that
// instances place, with the instances and the tree over them (instances.h).
#pragma once
#include <cstddef>
#include <string>
#include <vector>

#include "bvh.h"
#include "course/gpu_buffer.h"
#include "course/scene_file.h"
#include "instances.h"
#include "obj_loader.h"
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
    Bvh bvh;  // over `triangles`, which are in its leaf order; nodes: BVH_NODES_BINDING
    float size = 1.0f;  // the diagonal of the scene's bounding box: how fast to fly
    // The world's own spheres and triangles first, the objects' after (their trees too).
    uint32_t worldSphereCount = 0, worldTriangleCount = 0;
    std::vector<PackedObject> objects;     // each once, in the scene file's order
    std::vector<gpu::Instance> instances;  // in the leaf order of the instances' tree
    uint32_t instanceRoot = 0;             // that tree's root in bvh.nodes
    InstanceStats instanceStats;

    size_t shapeCount() const { return spheres.size() + quads.size() + triangles.size(); }
    size_t bytes() const;  // what the GPU keeps of the shapes, their trees and instances
};

// Chapter 09's packing of a mesh placed by worldFromMesh (an object's meshes: in the
// object's space).
void addMesh(GpuScene& gpu, const course::SceneFile& scene, const Mesh& mesh,
             const glm::mat4& worldFromMesh, uint32_t material);

// Loads the scene's meshes (chapter 07's OBJ loader; exit code 3 with file:line) and
// packs everything, then builds the tree over the triangles and puts them in its order.
GpuScene packScene(const course::SceneFile& scene, const BvhOptions& bvhOptions = {});

// The scene's storage buffers, each bound at its binding point (shared.h), with the
// environment's sampling tables (environment.h).
struct SceneBuffers {
    course::GpuBuffer spheres, quads, triangles, positions, normals, materials, emitters,
        bvhNodes, uvs, textures, texels, environmentCdf, instances;
    course::BufferTexture instanceTable;  // `instances` as the shaders read it
};
SceneBuffers uploadScene(const GpuScene& scene, const std::vector<float>& environmentCdf);
