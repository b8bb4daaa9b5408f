#include "gpu_scene.h"

#include <cmath>

#include "normals.h"
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

// --8<-- [start:mesh]
// A mesh joins the scene as chapter 09 drew it: its positions and normals appended to
// the scene's, its triangles' indices shifted past what was there before. A file
// without normals gets chapter 08's computed ones.
void addMesh(GpuScene& gpu, const course::SceneFile& scene, const Mesh& mesh,
             const glm::mat4& worldFromMesh, uint32_t material) {
    const uint32_t firstPosition = uint32_t(gpu.positions.size());
    const uint32_t firstNormal = uint32_t(gpu.normals.size());
    for (const glm::vec3& p : mesh.positions)
        gpu.positions.push_back(worldFromMesh * glm::vec4(p, 1.0f));
    // The scene file scales uniformly and turns about y: directions turn with the
    // matrix (a non-uniform scale would need its inverse transpose).
    bool computed = mesh.normalIndices.empty();
    const std::vector<glm::vec3> normals =
        computed ? areaWeightedNormals(mesh.positions, mesh.positionIndices) : mesh.normals;
    for (const glm::vec3& n : normals) {
        glm::vec3 turned = glm::mat3(worldFromMesh) * n;
        float length = glm::length(turned);
        gpu.normals.push_back(glm::vec4(length > 0.0f ? turned / length : turned, 0.0f));
    }
    const std::vector<uint32_t>& corners = mesh.positionIndices;
    const std::vector<uint32_t>& cornerNormals = computed ? corners : mesh.normalIndices;
    for (size_t i = 0; i < corners.size(); i += 3) {
        glm::uvec3 corner = firstPosition + glm::uvec3(corners[i], corners[i + 1],
                                                       corners[i + 2]);
        glm::vec3 p0(gpu.positions[corner.x]), p1(gpu.positions[corner.y]);
        glm::vec3 p2(gpu.positions[corner.z]);
        float area = 0.5f * glm::length(glm::cross(p1 - p0, p2 - p0));
        uint32_t emitter =
            addEmitter(gpu, scene, material, SHAPE_TRIANGLE, gpu.triangles.size(), area);
        gpu.triangles.push_back(
            {corner, material,
             firstNormal + glm::uvec3(cornerNormals[i], cornerNormals[i + 1],
                                      cornerNormals[i + 2]),
             emitter});
    }
}
// --8<-- [end:mesh]

}  // namespace

GpuScene packScene(const course::SceneFile& scene) {
    GpuScene gpu;
    for (const course::SceneMaterial& m : scene.materials)
        gpu.materials.push_back({glm::vec4(m.albedo, 0), glm::vec4(m.emission, 0)});

    for (const course::SceneSphere& s : scene.spheres) {
        float area = 4.0f * kPi * s.radius * s.radius;
        uint32_t emitter =
            addEmitter(gpu, scene, s.material, SHAPE_SPHERE, gpu.spheres.size(), area);
        gpu.spheres.push_back({s.center, s.radius, s.material, emitter, 0u, 0u});
    }
    for (const course::SceneQuad& q : scene.quads) {
        float area = glm::length(glm::cross(q.edge1, q.edge2));
        uint32_t emitter =
            addEmitter(gpu, scene, q.material, SHAPE_QUAD, gpu.quads.size(), area);
        gpu.quads.push_back({q.origin, q.material, q.edge1, emitter, q.edge2, 0u});
    }
    // A lone triangle is a mesh of one, flat: its three corners share its own normal.
    for (const course::SceneTriangle& t : scene.triangles) {
        glm::vec3 normal = glm::cross(t.p1 - t.p0, t.p2 - t.p0);
        if (glm::length(normal) > 0.0f) normal = glm::normalize(normal);
        Mesh one{{t.p0, t.p1, t.p2}, {normal}, {0, 1, 2}, {0, 0, 0}};
        addMesh(gpu, scene, one, glm::mat4(1.0f), t.material);
    }
    for (const course::SceneMesh& sceneMesh : scene.meshes)
        addMesh(gpu, scene, loadObj(sceneMesh.path), sceneMesh.worldFromMesh(),
                sceneMesh.material);

    glm::vec3 low(INFINITY), high(-INFINITY);
    auto grow = [&](glm::vec3 p) { low = glm::min(low, p); high = glm::max(high, p); };
    for (const gpu::Sphere& s : gpu.spheres) grow(s.center - s.radius), grow(s.center + s.radius);
    for (const gpu::Quad& q : gpu.quads)
        for (glm::vec3 p : {q.origin, q.origin + q.edge1, q.origin + q.edge2,
                            q.origin + q.edge1 + q.edge2})
            grow(p);
    for (const glm::vec4& p : gpu.positions) grow(glm::vec3(p));
    gpu.size = glm::length(high - low);
    return gpu;
}
