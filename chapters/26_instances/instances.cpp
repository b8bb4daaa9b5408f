#include "instances.h"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>
#include <utility>

#include <glm/gtc/matrix_access.hpp>

#include "course/error.h"
#include "gpu_scene.h"
#include "obj_loader.h"

namespace {

// --8<-- [start:append_tree]
// A tree built on its own (nodes and leaves from 0) appended to the node array: its
// children's node indices move past the nodes already there, its leaves' first item past
// `firstLeafItem`; `leafMark` marks the instances' leaves. Returns where its root went.
uint32_t appendTree(std::vector<gpu::BvhNode>& nodes, const Bvh& tree, uint32_t firstLeafItem,
                    uint32_t leafMark) {
    const uint32_t root = uint32_t(nodes.size());
    for (gpu::BvhNode node : tree.nodes) {
        node.leftIndex += node.leftCount == 0 ? root : firstLeafItem;
        node.rightIndex += node.rightCount == 0 ? root : firstLeafItem;
        if (node.leftCount > 0) node.leftCount |= leafMark;
        if (node.rightCount > 0) node.rightCount |= leafMark;
        nodes.push_back(node);
    }
    return root;
}
// --8<-- [end:append_tree]

// The triangles from `first` on, one object's, put under a tree of their own and into
// its leaf order. Returns the root.
uint32_t addObjectTree(GpuScene& gpu, size_t first, InstanceStats& stats) {
    std::vector<glm::vec3> positions(gpu.positions.begin(), gpu.positions.end());
    std::vector<uint32_t> corners;
    for (size_t i = first; i < gpu.triangles.size(); ++i) {
        const glm::uvec3 c = gpu.triangles[i].corners;
        corners.insert(corners.end(), {c.x, c.y, c.z});
    }
    const Bvh tree = buildBvh(positions, corners);
    std::vector<gpu::Triangle> inputOrder(gpu.triangles.begin() + std::ptrdiff_t(first),
                                          gpu.triangles.end());
    for (size_t i = 0; i < tree.triangleOrder.size(); ++i)
        gpu.triangles[first + i] = inputOrder[tree.triangleOrder[i]];
    stats.objectNodes += tree.nodes.size();
    return appendTree(gpu.bvh.nodes, tree, uint32_t(first), 0u);
}

// --8<-- [start:object]
// One object's shapes, in its own space: its spheres after the world's, its triangles
// as chapter 09 packs a mesh (a quad as two triangles with their (a, b) as texture
// coordinates), under their own tree. Its materials emit nothing (the reader checks).
gpu::Instance addObject(GpuScene& gpu, const course::SceneFile& scene,
                        const course::SceneObject& object, InstanceStats& stats,
                        glm::vec3& low, glm::vec3& high) {
    const size_t firstPosition = gpu.positions.size();
    gpu::Instance where{};
    where.firstSphere = uint32_t(gpu.spheres.size());
    low = glm::vec3(INFINITY), high = glm::vec3(-INFINITY);  // its box, in its own space
    for (const course::SceneSphere& s : object.spheres) {
        gpu.spheres.push_back({s.center, s.radius, s.material, NO_EMITTER, 0u, 0u});
        low = glm::min(low, s.center - s.radius), high = glm::max(high, s.center + s.radius);
    }
    where.sphereCount = uint32_t(object.spheres.size());

    const size_t first = gpu.triangles.size();
    for (const course::SceneTriangle& t : object.triangles) {
        const glm::vec3 normal = glm::normalize(glm::cross(t.p1 - t.p0, t.p2 - t.p0));
        addMesh(gpu, scene, Mesh{{t.p0, t.p1, t.p2}, {normal}, {}, {0, 1, 2}, {0, 0, 0}, {}},
                glm::mat4(1.0f), t.material);
    }
    for (const course::SceneQuad& q : object.quads) {
        const glm::vec3 normal = glm::normalize(glm::cross(q.edge1, q.edge2));
        Mesh two{{q.origin, q.origin + q.edge1, q.origin + q.edge1 + q.edge2, q.origin + q.edge2},
                 {normal}, {{0, 0}, {1, 0}, {1, 1}, {0, 1}}, {0, 1, 2, 0, 2, 3},
                 {0, 0, 0, 0, 0, 0}, {0, 1, 2, 0, 2, 3}};
        addMesh(gpu, scene, two, glm::mat4(1.0f), q.material);
    }
    for (const course::SceneMesh& m : object.meshes)
        addMesh(gpu, scene, loadObj(m.path), m.worldFromMesh(), m.material);
    for (size_t i = firstPosition; i < gpu.positions.size(); ++i)
        low = glm::min(low, glm::vec3(gpu.positions[i])),
        high = glm::max(high, glm::vec3(gpu.positions[i]));
    stats.objectTriangles += gpu.triangles.size() - first;
    where.root = addObjectTree(gpu, first, stats);
    return where;
}
// --8<-- [end:object]

}  // namespace

// --8<-- [start:add_instances]
void addInstances(GpuScene& gpu, const course::SceneFile& scene, glm::vec3& low,
                  glm::vec3& high) {
    InstanceStats& stats = gpu.instanceStats;
    gpu.worldSphereCount = uint32_t(gpu.spheres.size());
    gpu.worldTriangleCount = uint32_t(gpu.triangles.size());

    // 1. Each object once, with its box in its own space.
    const size_t bytesBefore = gpu.bytes();
    std::vector<gpu::Instance> objects;
    std::vector<std::pair<glm::vec3, glm::vec3>> objectBoxes(scene.objects.size());
    std::vector<size_t> objectTriangles;
    for (size_t i = 0; i < scene.objects.size(); ++i) {
        const size_t first = gpu.triangles.size();
        objects.push_back(addObject(gpu, scene, scene.objects[i], stats, objectBoxes[i].first,
                                    objectBoxes[i].second));
        objectTriangles.push_back(gpu.triangles.size() - first);
    }

    // 2. Each instance: the map from the world to its object (the inverse of the
    //    placement), and its box in the world: the object box's eight corners, placed.
    const auto start = std::chrono::steady_clock::now();
    std::vector<gpu::Instance> table;
    std::vector<glm::vec3> boxMin, boxMax;
    for (const course::SceneInstance& instance : scene.instances) {
        const glm::mat4 worldFromObject = instance.worldFromObject();
        const glm::mat4 objectFromWorld = glm::inverse(worldFromObject);
        gpu::Instance placed = objects[instance.object];
        placed.objectFromWorld0 = glm::row(objectFromWorld, 0);
        placed.objectFromWorld1 = glm::row(objectFromWorld, 1);
        placed.objectFromWorld2 = glm::row(objectFromWorld, 2);
        table.push_back(placed);
        const auto& [objectLow, objectHigh] = objectBoxes[instance.object];
        glm::vec3 placedLow(INFINITY), placedHigh(-INFINITY);
        for (int corner = 0; corner < 8; ++corner) {
            const glm::vec3 p(corner & 1 ? objectHigh.x : objectLow.x,
                              corner & 2 ? objectHigh.y : objectLow.y,
                              corner & 4 ? objectHigh.z : objectLow.z);
            const glm::vec3 world(worldFromObject * glm::vec4(p, 1.0f));
            placedLow = glm::min(placedLow, world);
            placedHigh = glm::max(placedHigh, world);
        }
        boxMin.push_back(placedLow);
        boxMax.push_back(placedHigh);
        low = glm::min(low, placedLow);
        high = glm::max(high, placedHigh);
        stats.placedTriangles += objectTriangles[instance.object];
    }

    // 3. The top level: the same builder over the instances' boxes, one instance a leaf
    //    (entering an instance costs a whole walk of its object's tree); its leaves
    //    marked, the table put in its leaf order.
    BvhOptions options;
    options.maxLeafSize = 1;
    const Bvh tree = buildBvhOverBoxes(boxMin, boxMax, options);
    gpu.instanceRoot = appendTree(gpu.bvh.nodes, tree, 0u, INSTANCE_LEAF);
    for (uint32_t input : tree.triangleOrder) gpu.instances.push_back(table[input]);
    stats.instanceTreeMilliseconds =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
            .count();
    stats.objects = scene.objects.size();
    stats.instances = scene.instances.size();
    stats.instanceNodes = tree.nodes.size();
    stats.memoryBytes = gpu.bytes() - bytesBefore;
}
// --8<-- [end:add_instances]

void setInstanceParameters(const GpuScene& gpu, bool bruteForce, gpu::PathParameters& p) {
    if (bruteForce && !gpu.instances.empty())
        throw course::Failure(course::ExitCode::BadUsage,
                              "--brute-force tests the world's own triangles one by one; "
                              "instances are found through the trees only");
    p.instanceCount = uint32_t(gpu.instances.size());
    p.instanceRoot = gpu.instanceRoot;
    p.worldSphereCount = gpu.worldSphereCount;
    p.worldTriangleCount = gpu.worldTriangleCount;
}

std::string describeInstances(const InstanceStats& s) {
    char text[256];
    std::snprintf(text, sizeof text, "instances: %zu of %zu objects (%zu triangles once, %zu "
                  "placed), trees %zu + %zu nodes, %.1f MiB, top level built in %.2f ms",
                  s.instances, s.objects, s.objectTriangles, s.placedTriangles, s.objectNodes,
                  s.instanceNodes, double(s.memoryBytes) / (1 << 20), s.instanceTreeMilliseconds);
    return text;
}

void recordInstanceStats(const InstanceStats& stats, course::Stats& json) {
    json.set("objects", double(stats.objects));
    json.set("instances", double(stats.instances));
    json.set("object_triangles", double(stats.objectTriangles));
    json.set("placed_triangles", double(stats.placedTriangles));
    json.set("instance_tree_ms", stats.instanceTreeMilliseconds);
    json.set("instance_bytes", double(stats.memoryBytes));
}
