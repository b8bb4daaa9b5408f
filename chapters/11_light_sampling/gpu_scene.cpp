#include "gpu_scene.h"

#include <cmath>

#include "obj_loader.h"

namespace {

constexpr float kPi = 3.14159265358979f;

// Every shape with a glowing material joins the emitter list; the shape remembers its
// place there, so that a ray hitting it can ask how likely light sampling was to pick it.
uint32_t addEmitter(GpuScene& gpu, const course::SceneFile& scene, uint32_t material,
                    uint32_t kind, size_t index, float area) {
    if (!scene.materials[material].emits()) return NO_EMITTER;
    gpu.emitters.push_back({kind, static_cast<uint32_t>(index), area, 0.0f});
    return static_cast<uint32_t>(gpu.emitters.size() - 1);
}

void addTriangle(GpuScene& gpu, const course::SceneFile& scene, glm::vec3 a, glm::vec3 b,
                 glm::vec3 c, uint32_t material) {
    float area = 0.5f * glm::length(glm::cross(b - a, c - a));
    uint32_t emitter =
        addEmitter(gpu, scene, material, SHAPE_TRIANGLE, gpu.triangles.size(), area);
    gpu.triangles.push_back({a, material, b, emitter, c, 0u});
}

}  // namespace

GpuScene packScene(const course::SceneFile& scene) {
    GpuScene gpu;
    for (const course::SceneMaterial& m : scene.materials)
        gpu.materials.push_back({glm::vec4(m.albedo, 0), glm::vec4(m.emission, 0)});
    glm::vec3 low(INFINITY), high(-INFINITY);
    auto grow = [&](glm::vec3 p) { low = glm::min(low, p); high = glm::max(high, p); };

    for (const course::SceneSphere& s : scene.spheres) {
        float area = 4.0f * kPi * s.radius * s.radius;
        uint32_t emitter =
            addEmitter(gpu, scene, s.material, SHAPE_SPHERE, gpu.spheres.size(), area);
        gpu.spheres.push_back({s.center, s.radius, s.material, emitter, 0u, 0u});
        grow(s.center - s.radius);
        grow(s.center + s.radius);
    }
    for (const course::SceneQuad& q : scene.quads) {
        float area = glm::length(glm::cross(q.edge1, q.edge2));
        uint32_t emitter =
            addEmitter(gpu, scene, q.material, SHAPE_QUAD, gpu.quads.size(), area);
        gpu.quads.push_back({q.origin, q.material, q.edge1, emitter, q.edge2, 0u});
        grow(q.origin);
        grow(q.origin + q.edge1 + q.edge2);
        grow(q.origin + q.edge1);
        grow(q.origin + q.edge2);
    }
    for (const course::SceneTriangle& t : scene.triangles) {
        addTriangle(gpu, scene, t.p0, t.p1, t.p2, t.material);
        grow(t.p0), grow(t.p1), grow(t.p2);
    }
    // Meshes become plain triangles in world space: flat facets, no corner normals.
    for (const course::SceneMesh& sceneMesh : scene.meshes) {
        Mesh mesh = loadObj(sceneMesh.path);
        glm::mat4 worldFromMesh = sceneMesh.worldFromMesh();
        glm::vec3 corners[3];
        for (size_t i = 0; i < mesh.positionIndices.size(); ++i) {
            glm::vec3 p = mesh.positions[mesh.positionIndices[i]];
            corners[i % 3] = glm::vec3(worldFromMesh * glm::vec4(p, 1.0f));
            grow(corners[i % 3]);
            if (i % 3 == 2)
                addTriangle(gpu, scene, corners[0], corners[1], corners[2],
                            sceneMesh.material);
        }
    }
    gpu.size = glm::length(high - low);
    return gpu;
}
