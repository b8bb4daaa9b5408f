#include "gpu_scene.h"

#include <cmath>
#include <utility>

#include "course/text_file.h"
#include "normals.h"
#include "obj_loader.h"
#include "textures.h"
#include "threaded_tree.h"

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

// --8<-- [start:material]
// A material as the shaders read it: a mirror keeps its reflectance where a diffuse
// surface keeps its albedo; a metal, its complex index and its roughness; glass, its
// index of refraction and its roughness.
gpu::Material packMaterial(const course::SceneMaterial& m) {
    gpu::Material packed{m.albedo, MATERIAL_DIFFUSE, m.emission, 0.0f, m.eta, 1.0f, m.k,
                         m.texture};  // NO_TEXTURE (-1) when it has none
    if (m.kind == course::MaterialKind::Mirror) {
        packed.kind = MATERIAL_MIRROR;
        packed.albedo = m.reflectance;
    } else if (m.kind == course::MaterialKind::Conductor) {
        packed.kind = MATERIAL_CONDUCTOR;
        packed.roughness = m.roughness;
    } else if (m.kind == course::MaterialKind::Dielectric) {
        packed.kind = MATERIAL_DIELECTRIC;
        packed.ior = m.ior;
        packed.roughness = m.roughness;
    }
    return packed;
}
// --8<-- [end:material]

// --8<-- [start:mesh]
// A mesh joins the scene as chapter 09 drew it: its positions, normals and texture
// coordinates appended to the scene's, its triangles' indices shifted past what was
// there before. A file without normals gets chapter 08's computed ones; one without
// texture coordinates points every corner at the scene's first, (0, 0).
void addMesh(GpuScene& gpu, const course::SceneFile& scene, const Mesh& mesh,
             const glm::mat4& worldFromMesh, uint32_t material) {
    const uint32_t firstPosition = uint32_t(gpu.positions.size());
    const uint32_t firstNormal = uint32_t(gpu.normals.size());
    const bool textured = !mesh.texcoordIndices.empty();
    const uint32_t firstUv = textured ? uint32_t(gpu.uvs.size()) : 0u;
    gpu.uvs.insert(gpu.uvs.end(), mesh.texcoords.begin(), mesh.texcoords.end());
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
        glm::uvec3 cornerUvs(0u);
        if (textured)
            cornerUvs = firstUv + glm::uvec3(mesh.texcoordIndices[i],
                                             mesh.texcoordIndices[i + 1],
                                             mesh.texcoordIndices[i + 2]);
        gpu.triangles.push_back(
            {corner, material,
             firstNormal + glm::uvec3(cornerNormals[i], cornerNormals[i + 1],
                                      cornerNormals[i + 2]),
             emitter, cornerUvs, 0u});
    }
}
// --8<-- [end:mesh]

// --8<-- [start:leaf_order]
// Builds the tree over the triangles and stores them in its leaf order, so that each
// leaf is one run of the buffer, and threads its boxes for the walk without a stack.
// Emitters that are triangles follow theirs.
void buildTree(GpuScene& gpu, const BvhOptions& options) {
    std::vector<glm::vec3> positions(gpu.positions.begin(), gpu.positions.end());
    std::vector<uint32_t> corners;
    corners.reserve(3 * gpu.triangles.size());
    for (const gpu::Triangle& t : gpu.triangles)
        corners.insert(corners.end(), {t.corners.x, t.corners.y, t.corners.z});
    gpu.bvh = buildBvh(positions, corners, options);
    gpu.boxes = threadTree(gpu.bvh);

    std::vector<gpu::Triangle> inputOrder = std::move(gpu.triangles);
    std::vector<uint32_t> leafPosition(inputOrder.size());
    gpu.triangles.clear();
    for (uint32_t input : gpu.bvh.triangleOrder) {
        leafPosition[input] = uint32_t(gpu.triangles.size());
        gpu.triangles.push_back(inputOrder[input]);
    }
    for (gpu::Emitter& emitter : gpu.emitters)
        if (emitter.shape == SHAPE_TRIANGLE) emitter.index = leafPosition[emitter.index];
}
// --8<-- [end:leaf_order]

}  // namespace

void recordSceneStats(const GpuScene& scene, course::Stats& stats) {
    recordBvhStats(scene.bvh.stats, stats);
    stats.set("bvh_box_bytes", double(scene.boxes.size() * sizeof(gpu::BvhBox)));
    stats.set("shapes", double(scene.shapeCount()));
    stats.set("triangles", double(scene.triangles.size()));
    stats.set("emitters", double(scene.emitters.size()));
    stats.set("textures", double(scene.textures.size()));
    stats.set("texels", double(scene.texels.size()));
}

GpuScene packScene(const course::SceneFile& scene, const BvhOptions& bvhOptions) {
    GpuScene gpu;
    for (const course::SceneMaterial& m : scene.materials)
        gpu.materials.push_back(packMaterial(m));
    for (const course::SceneTexture& t : scene.textures)
        addTexture(gpu.textures, gpu.texels, t);
    gpu.uvs.push_back(glm::vec2(0.0f));  // for corners without texture coordinates

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
        Mesh one{{t.p0, t.p1, t.p2}, {normal}, {}, {0, 1, 2}, {0, 0, 0}, {}};
        addMesh(gpu, scene, one, glm::mat4(1.0f), t.material);
    }
    for (const course::SceneMesh& sceneMesh : scene.meshes) {
        Mesh mesh = loadObj(sceneMesh.path);
        const course::SceneMaterial& material = scene.materials[sceneMesh.material];
        if (material.texture >= 0 && mesh.texcoordIndices.empty())
            course::failAtLine(scene.path, sceneMesh.line,
                               "material " + course::inQuotes(material.name) +
                                   " is textured, and " + sceneMesh.writtenPath +
                                   " has no texture coordinates ('vt' at every face corner)");
        addMesh(gpu, scene, mesh, sceneMesh.worldFromMesh(), sceneMesh.material);
    }

    glm::vec3 low(INFINITY), high(-INFINITY);
    auto grow = [&](glm::vec3 p) { low = glm::min(low, p); high = glm::max(high, p); };
    for (const gpu::Sphere& s : gpu.spheres) grow(s.center - s.radius), grow(s.center + s.radius);
    for (const gpu::Quad& q : gpu.quads)
        for (glm::vec3 p : {q.origin, q.origin + q.edge1, q.origin + q.edge2,
                            q.origin + q.edge1 + q.edge2})
            grow(p);
    for (const glm::vec4& p : gpu.positions) grow(glm::vec3(p));
    gpu.size = glm::length(high - low);
    buildTree(gpu, bvhOptions);
    return gpu;
}

// --8<-- [start:uniform]
// A uniform block of the items, at least one (scene_code.glsl sizes its array so).
template <class T>
course::GpuBuffer uniformBlock(const std::vector<T>& items, GLuint binding) {
    course::GpuBuffer block = items.empty() ? course::GpuBuffer::fromVector(std::vector<T>(1))
                                            : course::GpuBuffer::fromVector(items);
    block.bindUniform(binding);  // exit code 4 when larger than GL_MAX_UNIFORM_BLOCK_SIZE
    return block;
}
// --8<-- [end:uniform]

SceneBuffers uploadScene(const GpuScene& scene, const std::vector<float>& environmentCdf,
                         int sceneMemory, int bvhMemory) {
    using course::GpuBuffer;
    SceneBuffers buffers{GpuBuffer::fromVector(scene.spheres),
                         GpuBuffer::fromVector(scene.quads),
                         GpuBuffer::fromVector(scene.triangles),
                         GpuBuffer::fromVector(scene.positions),
                         GpuBuffer::fromVector(scene.normals),
                         GpuBuffer::fromVector(scene.materials),
                         GpuBuffer::fromVector(scene.emitters),
                         GpuBuffer::fromVector(scene.boxes),
                         GpuBuffer::fromVector(scene.uvs),
                         GpuBuffer::fromVector(scene.textures),
                         GpuBuffer::fromVector(scene.texels),
                         GpuBuffer::fromVector(environmentCdf),
                         GpuBuffer()};
    buffers.spheres.bindStorage(SPHERES_BINDING);
    buffers.quads.bindStorage(QUADS_BINDING);
    buffers.triangles.bindStorage(TRIANGLES_BINDING);
    buffers.positions.bindStorage(POSITIONS_BINDING);
    buffers.normals.bindStorage(NORMALS_BINDING);
    buffers.materials.bindStorage(MATERIALS_BINDING);
    buffers.emitters.bindStorage(EMITTERS_BINDING);
    buffers.bvhBoxes.bindStorage(BVH_NODES_BINDING);
    buffers.uvs.bindStorage(UVS_BINDING);
    buffers.textures.bindStorage(TEXTURES_BINDING);
    buffers.texels.bindStorage(TEXELS_BINDING);
    buffers.environmentCdf.bindStorage(ENVIRONMENT_CDF_BINDING);

    // --8<-- [start:views]
    // The other ways to read the same arrays (scene_memory.glsl): a buffer texture is a
    // view of a buffer's bytes; a uniform block is a copy.
    auto view = [&](const course::GpuBuffer& buffer, const char* what, GLuint unit) {
        buffers.bufferTextures.emplace_back(buffer, what).bind(unit);
    };
    if (sceneMemory == MEMORY_TEXTURE) {
        view(buffers.spheres, "the spheres", SPHERES_UNIT);
        view(buffers.quads, "the quads", QUADS_UNIT);
        view(buffers.materials, "the materials", MATERIALS_UNIT);
        view(buffers.emitters, "the emitters", EMITTERS_UNIT);
    }
    if (bvhMemory == MEMORY_TEXTURE) {
        view(buffers.triangles, "the triangles", TRIANGLES_UNIT);
        view(buffers.positions, "the triangles' corners", POSITIONS_UNIT);
        view(buffers.bvhBoxes, "the tree's boxes", BVH_NODES_UNIT);
        // Each triangle's three corners copied out in leaf order: a leaf's corners are
        // one run of texels, read without going through the corner indices.
        std::vector<glm::vec4> leafCorners;
        leafCorners.reserve(3 * scene.triangles.size());
        for (const gpu::Triangle& t : scene.triangles)
            for (uint32_t corner : {t.corners.x, t.corners.y, t.corners.z})
                leafCorners.push_back(scene.positions[corner]);
        buffers.leafCorners = GpuBuffer::fromVector(leafCorners);
        view(buffers.leafCorners, "the triangles' corners in leaf order", LEAF_CORNERS_UNIT);
    }
    if (sceneMemory == MEMORY_UNIFORM) {
        buffers.uniformBlocks.push_back(uniformBlock(scene.spheres, SPHERES_BLOCK_BINDING));
        buffers.uniformBlocks.push_back(uniformBlock(scene.quads, QUADS_BLOCK_BINDING));
        buffers.uniformBlocks.push_back(uniformBlock(scene.materials, MATERIALS_BLOCK_BINDING));
        buffers.uniformBlocks.push_back(uniformBlock(scene.emitters, EMITTERS_BLOCK_BINDING));
    }
    // --8<-- [end:views]
    return buffers;
}
