#include "gpu_scene.h"

#include <cmath>

#include "obj_loader.h"

GpuScene packScene(const course::SceneFile& scene) {
    GpuScene gpu;
    for (const course::SceneMaterial& m : scene.materials)
        gpu.materials.push_back({glm::vec4(m.albedo, 0), glm::vec4(m.emission, 0)});
    glm::vec3 low(INFINITY), high(-INFINITY);
    auto grow = [&](glm::vec3 p) { low = glm::min(low, p); high = glm::max(high, p); };

    for (const course::SceneSphere& s : scene.spheres) {
        gpu.spheres.push_back({s.center, s.radius, s.material, 0u, 0u, 0u});
        grow(s.center - s.radius);
        grow(s.center + s.radius);
    }
    for (const course::SceneQuad& q : scene.quads) {
        gpu.quads.push_back({q.origin, q.material, q.edge1, 0u, q.edge2, 0u});
        grow(q.origin);
        grow(q.origin + q.edge1 + q.edge2);
        grow(q.origin + q.edge1);
        grow(q.origin + q.edge2);
    }
    for (const course::SceneTriangle& t : scene.triangles) {
        gpu.triangles.push_back({t.p0, t.material, t.p1, 0u, t.p2, 0u});
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
                gpu.triangles.push_back(
                    {corners[0], sceneMesh.material, corners[1], 0u, corners[2], 0u});
        }
    }
    gpu.size = glm::length(high - low);
    return gpu;
}
