#include "gpu_scene.h"

#include <algorithm>
#include <cmath>
#include <initializer_list>

#include "course/error.h"
#include "normals.h"
#include "obj_loader.h"

namespace {

constexpr float kPi = 3.14159265358979f;

// The last texel of a sphere or a quad: its indices as float numbers (shared.h).
glm::vec4 infoTexel(uint32_t material, int64_t emitter) {
    return {float(material), float(emitter), 0.0f, 0.0f};
}

// Every shape with a glowing material joins the emitter list; the shape remembers its
// place there, so that a ray hitting it can ask how likely light sampling was to pick it.
int64_t addEmitter(std::vector<gpu::Emitter>& emitters, const course::SceneFile& scene,
                   uint32_t material, uint32_t kind, size_t index, float area) {
    if (!scene.materials[material].emits()) return -1;
    emitters.push_back({kind, static_cast<uint32_t>(index), area, 0.0f});
    return int64_t(emitters.size()) - 1;
}

// A uniform block's arrays have a size fixed when the shader is compiled.
[[noreturn]] void tooMany(const course::SceneFile& scene, size_t count, const std::string& what,
                          int limit, const std::string& limitName) {
    course::fail(course::ExitCode::BadInput,
                 scene.path + ": " + std::to_string(count) + " " + what + ", but the "
                 "uniform block of this appendix holds at most " + std::to_string(limit) +
                 " (" + limitName + " in shaders/A2_gl33_fragment/shared.h)");
}

// Chapter 12's triangles, positions and normals, gathered mesh by mesh: they become
// runs of texels once every mesh is in (shared.h).
struct Meshes {
    std::vector<glm::vec4> triangles;  // TRIANGLE_TEXELS each
    std::vector<glm::vec4> positions;  // the triangles' corners, in the world; w unused
    std::vector<glm::vec4> normals;    // the normals at the corners, unit; w unused
};

// --8<-- [start:mesh]
// A mesh joins the scene as chapter 09 drew it: its positions and normals appended to
// the scene's, its triangles' indices shifted past what was there before. A file
// without normals gets chapter 08's computed ones.
void addMesh(Meshes& meshes, std::vector<gpu::Emitter>& emitters,
             const course::SceneFile& scene, const Mesh& mesh,
             const glm::mat4& worldFromMesh, uint32_t material) {
    const uint32_t firstPosition = uint32_t(meshes.positions.size());
    const uint32_t firstNormal = uint32_t(meshes.normals.size());
    for (const glm::vec3& p : mesh.positions)
        meshes.positions.push_back(worldFromMesh * glm::vec4(p, 1.0f));
    // The scene file scales uniformly and turns about y: directions turn with the
    // matrix (a non-uniform scale would need its inverse transpose).
    bool computed = mesh.normalIndices.empty();
    const std::vector<glm::vec3> normals =
        computed ? areaWeightedNormals(mesh.positions, mesh.positionIndices) : mesh.normals;
    for (const glm::vec3& n : normals) {
        glm::vec3 turned = glm::mat3(worldFromMesh) * n;
        float length = glm::length(turned);
        meshes.normals.push_back(glm::vec4(length > 0.0f ? turned / length : turned, 0.0f));
    }
    const std::vector<uint32_t>& corners = mesh.positionIndices;
    const std::vector<uint32_t>& cornerNormals = computed ? corners : mesh.normalIndices;
    for (size_t i = 0; i < corners.size(); i += 3) {
        glm::uvec3 corner = firstPosition + glm::uvec3(corners[i], corners[i + 1],
                                                       corners[i + 2]);
        glm::vec3 p0(meshes.positions[corner.x]), p1(meshes.positions[corner.y]);
        glm::vec3 p2(meshes.positions[corner.z]);
        float area = 0.5f * glm::length(glm::cross(p1 - p0, p2 - p0));
        size_t index = meshes.triangles.size() / TRIANGLE_TEXELS;
        int64_t emitter = addEmitter(emitters, scene, material, SHAPE_TRIANGLE, index, area);
        // Chapter 12's Triangle as two texels, its indices as float numbers.
        glm::uvec3 cornerNormal = firstNormal + glm::uvec3(cornerNormals[i],
                                                           cornerNormals[i + 1],
                                                           cornerNormals[i + 2]);
        meshes.triangles.push_back(glm::vec4(glm::vec3(corner), float(material)));
        meshes.triangles.push_back(glm::vec4(glm::vec3(cornerNormal), float(emitter)));
    }
}
// --8<-- [end:mesh]

}  // namespace

// --8<-- [start:pack]
GpuScene packScene(const course::SceneFile& scene) {
    GpuScene gpu;
    gpu::SceneBlock& block = *gpu.block;
    if (scene.materials.size() > MAX_MATERIALS)
        tooMany(scene, scene.materials.size(), "materials", MAX_MATERIALS, "MAX_MATERIALS");
    for (size_t i = 0; i < scene.materials.size(); ++i) {
        const course::SceneMaterial& m = scene.materials[i];
        block.materials[i] = {glm::vec4(m.albedo, 0), glm::vec4(m.emission, 0)};
    }
    std::vector<gpu::Emitter> emitters;
    glm::vec3 low(INFINITY), high(-INFINITY);
    auto grow = [&](glm::vec3 p) { low = glm::min(low, p); high = glm::max(high, p); };
    auto add = [&gpu](std::initializer_list<glm::vec4> texels) {
        gpu.texels.insert(gpu.texels.end(), texels);
    };

    block.firstSphereTexel = 0;
    for (size_t i = 0; i < scene.spheres.size(); ++i) {
        const course::SceneSphere& s = scene.spheres[i];
        int64_t emitter = addEmitter(emitters, scene, s.material, SHAPE_SPHERE, i,
                                     4.0f * kPi * s.radius * s.radius);
        add({glm::vec4(s.center, s.radius), infoTexel(s.material, emitter)});
        grow(s.center - s.radius);
        grow(s.center + s.radius);
    }
    block.firstQuadTexel = uint32_t(gpu.texels.size());
    for (size_t i = 0; i < scene.quads.size(); ++i) {
        const course::SceneQuad& q = scene.quads[i];
        int64_t emitter = addEmitter(emitters, scene, q.material, SHAPE_QUAD, i,
                                     glm::length(glm::cross(q.edge1, q.edge2)));
        add({glm::vec4(q.origin, 0), glm::vec4(q.edge1, 0), glm::vec4(q.edge2, 0),
             infoTexel(q.material, emitter)});
        grow(q.origin);
        grow(q.origin + q.edge1 + q.edge2);
        grow(q.origin + q.edge1);
        grow(q.origin + q.edge2);
    }
    Meshes meshes;
    // A lone triangle is a mesh of one, flat: its three corners share its own normal.
    for (const course::SceneTriangle& t : scene.triangles) {
        glm::vec3 normal = glm::cross(t.p1 - t.p0, t.p2 - t.p0);
        if (glm::length(normal) > 0.0f) normal = glm::normalize(normal);
        Mesh one{{t.p0, t.p1, t.p2}, {normal}, {0, 1, 2}, {0, 0, 0}};
        addMesh(meshes, emitters, scene, one, glm::mat4(1.0f), t.material);
    }
    for (const course::SceneMesh& sceneMesh : scene.meshes)
        addMesh(meshes, emitters, scene, loadObj(sceneMesh.path), sceneMesh.worldFromMesh(),
                sceneMesh.material);
    for (const glm::vec4& p : meshes.positions) grow(glm::vec3(p));
    // A float holds every integer up to 2^24 exactly, and not every one above.
    const size_t corners = std::max(meshes.positions.size(), meshes.normals.size());
    if (corners > (size_t(1) << 24))
        course::fail(course::ExitCode::BadInput,
                     scene.path + ": " + std::to_string(corners) + " corners, but the "
                     "texels of this appendix hold their indices as floats, exact to 2^24");
    // The triangles' run of texels, then the two runs they point into.
    block.firstTriangleTexel = uint32_t(gpu.texels.size());
    gpu.texels.insert(gpu.texels.end(), meshes.triangles.begin(), meshes.triangles.end());
    block.firstPositionTexel = uint32_t(gpu.texels.size());
    gpu.texels.insert(gpu.texels.end(), meshes.positions.begin(), meshes.positions.end());
    block.firstNormalTexel = uint32_t(gpu.texels.size());
    gpu.texels.insert(gpu.texels.end(), meshes.normals.begin(), meshes.normals.end());
    if (emitters.size() > MAX_EMITTERS)
        tooMany(scene, emitters.size(), "emitting shapes", MAX_EMITTERS, "MAX_EMITTERS");
    std::copy(emitters.begin(), emitters.end(), block.emitters);
    block.sphereCount = uint32_t(scene.spheres.size());
    block.quadCount = uint32_t(scene.quads.size());
    block.triangleCount = uint32_t(meshes.triangles.size() / TRIANGLE_TEXELS);
    block.emitterCount = uint32_t(emitters.size());
    gpu.size = glm::length(high - low);
    return gpu;
}
// --8<-- [end:pack]
