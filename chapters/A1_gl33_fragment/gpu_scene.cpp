#include "gpu_scene.h"

#include <algorithm>
#include <cmath>
#include <initializer_list>

#include "course/error.h"
#include "obj_loader.h"

namespace {

constexpr float kPi = 3.14159265358979f;

// The fourth texel of every shape: its indices as float numbers (shared.h).
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
                 " (" + limitName + " in shaders/A1_gl33_fragment/shared.h)");
}

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
    block.firstTriangleTexel = uint32_t(gpu.texels.size());
    size_t triangles = 0;
    auto addTriangle = [&](glm::vec3 a, glm::vec3 b, glm::vec3 c, uint32_t material) {
        int64_t emitter = addEmitter(emitters, scene, material, SHAPE_TRIANGLE, triangles++,
                                     0.5f * glm::length(glm::cross(b - a, c - a)));
        add({glm::vec4(a, 0), glm::vec4(b, 0), glm::vec4(c, 0), infoTexel(material, emitter)});
        grow(a), grow(b), grow(c);
    };
    for (const course::SceneTriangle& t : scene.triangles)
        addTriangle(t.p0, t.p1, t.p2, t.material);
    // Meshes become plain triangles in world space: flat facets, no corner normals.
    for (const course::SceneMesh& sceneMesh : scene.meshes) {
        Mesh mesh = loadObj(sceneMesh.path);
        glm::mat4 worldFromMesh = sceneMesh.worldFromMesh();
        glm::vec3 corners[3];
        for (size_t i = 0; i < mesh.positionIndices.size(); ++i) {
            glm::vec3 p = mesh.positions[mesh.positionIndices[i]];
            corners[i % 3] = glm::vec3(worldFromMesh * glm::vec4(p, 1.0f));
            if (i % 3 == 2) addTriangle(corners[0], corners[1], corners[2], sceneMesh.material);
        }
    }
    if (emitters.size() > MAX_EMITTERS)
        tooMany(scene, emitters.size(), "emitting shapes", MAX_EMITTERS, "MAX_EMITTERS");
    std::copy(emitters.begin(), emitters.end(), block.emitters);
    block.sphereCount = uint32_t(scene.spheres.size());
    block.quadCount = uint32_t(scene.quads.size());
    block.triangleCount = uint32_t(triangles);
    block.emitterCount = uint32_t(emitters.size());
    gpu.size = glm::length(high - low);
    return gpu;
}
// --8<-- [end:pack]
