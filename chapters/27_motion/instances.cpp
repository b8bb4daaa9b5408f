#include "instances.h"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>
#include <utility>

#include <glm/gtc/matrix_access.hpp>
#include <glm/gtc/matrix_transform.hpp>

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
PackedObject addObject(GpuScene& gpu, const course::SceneFile& scene,
                       const course::SceneObject& object, InstanceStats& stats) {
    const size_t firstPosition = gpu.positions.size(), firstNormal = gpu.normals.size();
    PackedObject packed;
    gpu::Instance& where = packed.where;
    glm::vec3& low = packed.low;
    glm::vec3& high = packed.high;
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
    packed.firstTriangle = first, packed.triangleCount = gpu.triangles.size() - first;
    packed.firstPosition = firstPosition;
    packed.positionCount = gpu.positions.size() - firstPosition;
    packed.firstNormal = firstNormal, packed.normalCount = gpu.normals.size() - firstNormal;
    where.root = addObjectTree(gpu, first, stats);
    packed.firstNode = where.root, packed.nodeCount = gpu.bvh.nodes.size() - where.root;
    return packed;
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
    for (const course::SceneObject& object : scene.objects)
        gpu.objects.push_back(addObject(gpu, scene, object, stats));

    // 2. The instances, over the whole shutter: their top level after the objects' trees.
    gpu.instanceRoot = uint32_t(gpu.bvh.nodes.size());
    const auto [placedLow, placedHigh] = placeInstances(gpu, scene, kWholeShutter);
    low = glm::min(low, placedLow), high = glm::max(high, placedHigh);
    stats.objects = scene.objects.size();
    stats.instances = scene.instances.size();
    stats.memoryBytes = gpu.bytes() - bytesBefore;
}
// --8<-- [end:add_instances]

// --8<-- [start:place_instances]
std::pair<glm::vec3, glm::vec3> placeInstances(GpuScene& gpu, const course::SceneFile& scene,
                                               float instant) {
    // 1. Each instance: the map from the world to its object (the inverse of the
    //    placement, moved on to the instant), and its box in the world: the object
    //    box's eight corners, placed. Over the whole shutter, the walk moves it (its
    //    motion in the object's space), and its box is swept: it holds the box at the
    //    opening and the same box moved as far as the instance goes.
    const auto start = std::chrono::steady_clock::now();
    const bool whole = instant == kWholeShutter;
    std::vector<gpu::Instance> table;
    std::vector<glm::vec3> boxMin, boxMax;
    glm::vec3 low(INFINITY), high(-INFINITY);
    gpu.instanceStats.placedTriangles = 0;
    for (const course::SceneInstance& instance : scene.instances) {
        const PackedObject& object = gpu.objects[instance.object];
        const glm::vec3 moved = whole ? glm::vec3(0.0f) : instant * instance.motion;
        const glm::mat4 worldFromObject =
            glm::translate(glm::mat4(1.0f), moved) * instance.worldFromObject();
        const glm::mat4 objectFromWorld = glm::inverse(worldFromObject);
        gpu::Instance placed = object.where;
        placed.objectFromWorld0 = glm::row(objectFromWorld, 0);
        placed.objectFromWorld1 = glm::row(objectFromWorld, 1);
        placed.objectFromWorld2 = glm::row(objectFromWorld, 2);
        if (whole)
            placed.objectMotion = glm::vec4(glm::mat3(objectFromWorld) * instance.motion, 0.0f);
        table.push_back(placed);
        glm::vec3 placedLow(INFINITY), placedHigh(-INFINITY);
        for (int corner = 0; corner < 8; ++corner) {
            const glm::vec3 p(corner & 1 ? object.high.x : object.low.x,
                              corner & 2 ? object.high.y : object.low.y,
                              corner & 4 ? object.high.z : object.low.z);
            const glm::vec3 world(worldFromObject * glm::vec4(p, 1.0f));
            placedLow = glm::min(placedLow, world);
            placedHigh = glm::max(placedHigh, world);
        }
        if (whole) {
            placedLow = glm::min(placedLow, placedLow + instance.motion);
            placedHigh = glm::max(placedHigh, placedHigh + instance.motion);
        }
        boxMin.push_back(placedLow);
        boxMax.push_back(placedHigh);
        low = glm::min(low, placedLow), high = glm::max(high, placedHigh);
        gpu.instanceStats.placedTriangles += object.triangleCount;
    }

    // 2. The top level: the same builder over the instances' boxes, one instance a leaf
    //    (entering an instance costs a whole walk of its object's tree); its leaves
    //    marked, the table put in its leaf order. It replaces the one before: its
    //    nodes are the last in the array.
    BvhOptions options;
    options.maxLeafSize = 1;
    const Bvh tree = buildBvhOverBoxes(boxMin, boxMax, options);
    gpu.bvh.nodes.resize(gpu.instanceRoot);
    appendTree(gpu.bvh.nodes, tree, 0u, INSTANCE_LEAF);
    gpu.instances.clear();
    for (uint32_t input : tree.triangleOrder) gpu.instances.push_back(table[input]);
    gpu.instanceStats.instanceTreeMilliseconds =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
            .count();
    gpu.instanceStats.instanceNodes = tree.nodes.size();
    return {low, high};
}
// --8<-- [end:place_instances]

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
