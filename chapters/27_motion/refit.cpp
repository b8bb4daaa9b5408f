#include "refit.h"

#include <cmath>

namespace {

bool isEmpty(const glm::vec3& low, const glm::vec3& high) { return low.x > high.x; }

// Half a box's surface area, as bvh.cpp's Box::halfArea (0 for an empty box).
double halfArea(const glm::vec3& low, const glm::vec3& high) {
    if (isEmpty(low, high)) return 0.0;
    const glm::dvec3 size = glm::dvec3(high) - glm::dvec3(low);
    return size.x * size.y + size.y * size.z + size.z * size.x;
}

}  // namespace

// --8<-- [start:twist]
void twistObjects(GpuScene& gpu, const RestPose& rest, float degrees) {
    for (const PackedObject& object : gpu.objects) {
        const glm::vec3 middle = 0.5f * (object.low + object.high);
        const float height = std::max(object.high.y - object.low.y, 1e-30f);
        auto turn = [&](glm::vec4 v, float y, bool isPoint) {
            const float angle = glm::radians(degrees) * (y - object.low.y) / height;
            const float c = std::cos(angle), s = std::sin(angle);
            const glm::vec3 from = isPoint ? glm::vec3(v) - middle : glm::vec3(v);
            const glm::vec3 to(c * from.x + s * from.z, from.y, -s * from.x + c * from.z);
            return glm::vec4(isPoint ? to + middle : to, v.w);
        };
        const size_t end = object.firstPosition + object.positionCount;
        for (size_t i = object.firstPosition; i < end; ++i)
            gpu.positions[i] = turn(rest.positions[i], rest.positions[i].y, true);
        // A normal turns with a corner that uses it (a smooth mesh's normals are each a
        // corner's).
        for (size_t t = 0; t < object.triangleCount; ++t) {
            const gpu::Triangle& triangle = gpu.triangles[object.firstTriangle + t];
            for (int k = 0; k < 3; ++k) {
                const uint32_t n = triangle.cornerNormals[k];
                gpu.normals[n] = turn(rest.normals[n], rest.positions[triangle.corners[k]].y,
                                      false);
            }
        }
    }
}
// --8<-- [end:twist]

// --8<-- [start:refit]
void refitTree(GpuScene& gpu, const PackedObject& object) {
    // Nodes are stored depth first, a child after its parent: walking them from the last
    // to the first refits every child before the node that holds its box.
    std::vector<gpu::BvhNode>& nodes = gpu.bvh.nodes;
    auto refit = [&](uint32_t index, uint32_t count, glm::vec3& low, glm::vec3& high) {
        if (isEmpty(low, high)) return;  // a child that is not there stays empty
        low = glm::vec3(INFINITY), high = glm::vec3(-INFINITY);
        if (count == 0) {  // a node: the box around both of its children's
            const gpu::BvhNode& child = nodes[index];
            low = glm::min(child.leftMin, child.rightMin);
            high = glm::max(child.leftMax, child.rightMax);
            return;
        }
        for (uint32_t t = index; t < index + count; ++t)  // a leaf: around its corners
            for (int k = 0; k < 3; ++k) {
                const glm::vec3 p(gpu.positions[gpu.triangles[t].corners[k]]);
                low = glm::min(low, p), high = glm::max(high, p);
            }
    };
    for (size_t i = object.firstNode + object.nodeCount; i-- > object.firstNode;) {
        gpu::BvhNode& node = nodes[i];
        refit(node.leftIndex, node.leftCount, node.leftMin, node.leftMax);
        refit(node.rightIndex, node.rightCount, node.rightMin, node.rightMax);
    }
}
// --8<-- [end:refit]

double treeSahCost(const std::vector<gpu::BvhNode>& nodes, size_t firstNode, size_t nodeCount) {
    double sum = 0.0;
    for (size_t i = firstNode; i < firstNode + nodeCount; ++i) {
        const gpu::BvhNode& node = nodes[i];
        sum += halfArea(glm::min(node.leftMin, node.rightMin),
                        glm::max(node.leftMax, node.rightMax));
        sum += node.leftCount * halfArea(node.leftMin, node.leftMax);
        sum += node.rightCount * halfArea(node.rightMin, node.rightMax);
    }
    const gpu::BvhNode& root = nodes[firstNode];
    const double rootArea = halfArea(glm::min(root.leftMin, root.rightMin),
                                     glm::max(root.leftMax, root.rightMax));
    return rootArea > 0.0 ? sum / rootArea : 0.0;
}
