// What the BVH tests of every tree share (test_bvh*.cpp, one executable per tree:
// bvh_tests.cmake): the tree's API as the tests use it, the meshes, the walk that checks
// a tree's invariants, and the rays that compare the chapter's traversal with brute force.
#pragma once
#include <gtest/gtest.h>

#include <algorithm>
#include <functional>
#include <string>
#include <vector>

#include "bvh_test_support.h"

namespace bvh_test {

// ---------------------------------------------------------------------------------------
// The tree's API. bvh_tests.cmake defines BVH_TEST_OPTIONS where the chapter's bvh.h
// has BvhOptions and BvhStats (the SAH builders, chapter 14 on), and
// BVH_TEST_PRICED_LEAVES where BvhOptions can price a leaf by its count or as written
// out (chapter 21 on). Chapter 13's median builder takes no options and reports no
// stats: its TreeOptions are only its fixed limits, which the checks read.
// ---------------------------------------------------------------------------------------

#ifdef BVH_TEST_OPTIONS
using TreeOptions = BvhOptions;
inline Bvh buildTree(const TestMesh& mesh, const TreeOptions& options = {}) {
    return buildBvh(mesh.positions, mesh.indices, options);
}
#else
struct TreeOptions {
    int maxLeafSize = BVH_MAX_LEAF_SIZE;
    int maxDepth = BVH_MAX_DEPTH;
};
inline Bvh buildTree(const TestMesh& mesh, const TreeOptions& = {}) {
    return buildBvh(mesh.positions, mesh.indices);
}
#endif

#ifdef BVH_TEST_OPTIONS
// The triangle tests the SAH charges a ray entering a leaf of `count` triangles: the
// count (chapter 14), or all that the traversal writes out (chapter 21's default).
inline double leafTests(uint32_t count, const TreeOptions& options) {
#ifdef BVH_TEST_PRICED_LEAVES
    if (!options.leavesByCount) return BVH_MAX_LEAF_SIZE;
#endif
    (void)options;
    return count;
}

// The tree with each leaf price the builder knows: chapter 14's (a leaf costs its
// triangles) and, where there is one, chapter 21's (a leaf costs the tests written out).
inline std::vector<TreeOptions> everyLeafPrice(const TreeOptions& options) {
#ifdef BVH_TEST_PRICED_LEAVES
    TreeOptions byCount = options, writtenOut = options;
    byCount.leavesByCount = true;
    writtenOut.leavesByCount = false;
    return {byCount, writtenOut};
#else
    return {options};
#endif
}
#endif

// ---------------------------------------------------------------------------------------
// Meshes
// ---------------------------------------------------------------------------------------

// n copies of one triangle: all centroids equal, no plane separates any two.
inline TestMesh identicalTriangles(int n) {
    TestMesh mesh{"identical_" + std::to_string(n)};
    for (int i = 0; i < n; ++i) mesh.add({0, 0, 0}, {1, 0, 0}, {0, 1, 0});
    return mesh;
}

// Zero-area triangles: points and segments scattered in the unit cube, and a few real
// triangles among them.
inline TestMesh zeroAreaTriangles(int n, uint64_t seed) {
    TestMesh mesh{"zero_area_" + std::to_string(n)};
    Random random(seed);
    for (int i = 0; i < n; ++i) {
        glm::vec3 a = random.inBox(glm::vec3(0.0f), glm::vec3(1.0f));
        glm::vec3 b = random.inBox(glm::vec3(0.0f), glm::vec3(1.0f));
        if (i % 3 == 0) mesh.add(a, a, a);                  // a point
        else if (i % 3 == 1) mesh.add(a, b, 0.5f * (a + b));  // a segment
        else mesh.add(a, b, a + glm::vec3(0.0f, 0.0f, 0.05f));
    }
    return mesh;
}

// Two triangles, flat in z = 0, whose boxes are unit squares: [0,1] x [0,1] and, `gap`
// further along x, [1 + gap, 2 + gap] x [0,1]. Box half areas (SAH units) by hand:
// 1 each, 2 + gap together. Nothing but x separates them.
inline TestMesh twoTrianglesApart(float gap) {
    TestMesh mesh{"two_apart_" + std::to_string(gap)};
    const float x = 1.0f + gap;
    mesh.add({0, 0, 0}, {1, 0, 0}, {0, 1, 0});
    mesh.add({x, 0, 0}, {x + 1, 0, 0}, {x, 1, 0});
    return mesh;
}

inline std::vector<TestMesh> variedMeshes() {
    std::vector<TestMesh> meshes = {randomSoup(1, 1),          randomSoup(2, 2),
                                    randomSoup(3, 3),          randomSoup(5, 5),
                                    randomSoup(17, 17),        randomSoup(1000, 7),
                                    randomSoup(20000, 8, 0.02f), flatGrid(30),
                                    peelingChain(80),          identicalTriangles(1000),
                                    zeroAreaTriangles(999, 4)};
    for (const char* name : {"teapot_552", "teapot_6320"}) {
        TestMesh teapot = loadTeapot(name);
        EXPECT_FALSE(teapot.positions.empty()) << name << ".obj: build course_assets";
        if (!teapot.positions.empty()) meshes.push_back(teapot);
    }
    return meshes;
}

// ---------------------------------------------------------------------------------------
// The tree as the tests read it
// ---------------------------------------------------------------------------------------

struct Box3 {
    glm::vec3 min{std::numeric_limits<float>::max()}, max{-std::numeric_limits<float>::max()};
    void grow(glm::vec3 p) { min = glm::min(min, p), max = glm::max(max, p); }
    void grow(const Box3& b) { min = glm::min(min, b.min), max = glm::max(max, b.max); }
    bool empty() const { return min.x > max.x || min.y > max.y || min.z > max.z; }
    bool inside(const Box3& outer) const {
        return empty() || (glm::all(glm::greaterThanEqual(min, outer.min)) &&
                           glm::all(glm::lessThanEqual(max, outer.max)));
    }
    bool operator==(const Box3& o) const { return min == o.min && max == o.max; }
    double halfArea() const {
        if (empty()) return 0.0;
        glm::dvec3 s = glm::dvec3(max) - glm::dvec3(min);
        return s.x * s.y + s.y * s.z + s.z * s.x;
    }
};

inline Box3 triangleBox(const TestMesh& mesh, uint32_t triangle) {
    Box3 box;
    for (int k = 0; k < 3; ++k) box.grow(mesh.positions[mesh.indices[3 * triangle + k]]);
    return box;
}

// A child slot of a node: its box, and a node index (count 0) or a leaf's triangles.
struct Slot {
    Box3 box;
    uint32_t index = 0, count = 0;
    bool isLeaf() const { return count > 0; }
};
inline Slot leftSlot(const gpu::BvhNode& node) {
    return {{node.leftMin, node.leftMax}, node.leftIndex, node.leftCount};
}
inline Slot rightSlot(const gpu::BvhNode& node) {
    return {{node.rightMin, node.rightMax}, node.rightIndex, node.rightCount};
}

// The input triangles under a slot (Bvh::triangleOrder of its leaves), in leaf order.
inline void collectTriangles(const Bvh& bvh, const Slot& slot, std::vector<uint32_t>& out) {
    if (slot.box.empty()) return;
    if (slot.isLeaf()) {
        for (uint32_t i = slot.index; i < slot.index + slot.count; ++i)
            out.push_back(bvh.triangleOrder.at(i));
        return;
    }
    const gpu::BvhNode& node = bvh.nodes.at(slot.index);
    collectTriangles(bvh, leftSlot(node), out);
    collectTriangles(bvh, rightSlot(node), out);
}
inline std::vector<uint32_t> trianglesUnder(const Bvh& bvh, const Slot& slot) {
    std::vector<uint32_t> triangles;
    collectTriangles(bvh, slot, triangles);
    return triangles;
}

// Node fetches to reach the deepest leaf (the root's slots are 1 fetch down).
inline int deepestLeaf(const Bvh& bvh, uint32_t node = 0, int depth = 1) {
    int deepest = 0;
    for (const Slot& slot : {leftSlot(bvh.nodes.at(node)), rightSlot(bvh.nodes.at(node))}) {
        if (slot.box.empty()) continue;
        deepest = std::max(deepest, slot.isLeaf() ? depth : deepestLeaf(bvh, slot.index,
                                                                        depth + 1));
    }
    return deepest;
}

// ---------------------------------------------------------------------------------------
// The invariants
// ---------------------------------------------------------------------------------------

// Walks the whole tree from the root and checks everything a traversal relies on, and
// the stats the builder reports, where it reports any.
class TreeChecker {
public:
    TreeChecker(const Bvh& bvh, const TestMesh& mesh, const TreeOptions& options)
        : bvh_(bvh), mesh_(mesh), options_(options) {}

    void check() {
        const size_t n = mesh_.triangleCount();
        ASSERT_EQ(bvh_.triangleOrder.size(), n);
        ASSERT_FALSE(bvh_.nodes.empty()) << "the root always exists";
        // triangleOrder is a permutation of the input triangles.
        std::vector<uint32_t> sorted = bvh_.triangleOrder;
        std::sort(sorted.begin(), sorted.end());
        for (size_t i = 0; i < n; ++i) ASSERT_EQ(sorted[i], i) << "triangleOrder";

        triangleSeen_.assign(n, 0);
        nodeSeen_.assign(bvh_.nodes.size(), 0);
        Box3 everything;
        for (uint32_t i = 0; i < n; ++i) everything.grow(triangleBox(mesh_, i));
        Box3 root = visitNode(0, everything, 1);
        EXPECT_TRUE(root == everything) << "the root's children hold the whole mesh";

        for (size_t i = 0; i < n; ++i)
            EXPECT_EQ(triangleSeen_[i], 1) << "leaf-order triangle " << i << " in "
                                           << triangleSeen_[i] << " leaves";
        for (size_t i = 0; i < nodeSeen_.size(); ++i)
            EXPECT_EQ(nodeSeen_[i], 1) << "node " << i << " reached " << nodeSeen_[i]
                                       << " times";
        EXPECT_LE(maxDepth_, options_.maxDepth);
        EXPECT_LE(maxDepth_, BVH_MAX_DEPTH) << "deeper than the traversal's stack";
        EXPECT_LE(maxLeaf_, options_.maxLeafSize);
        EXPECT_EQ(bvh_.nodes.size(), leaves_ <= 1 ? 1 : leaves_ - 1)
            << "a binary tree: one node fewer than leaves (the root wraps a lone leaf)";
#ifdef BVH_TEST_OPTIONS
        const BvhStats& stats = bvh_.stats;
        EXPECT_EQ(stats.triangleCount, n);
        EXPECT_EQ(stats.nodeCount, bvh_.nodes.size());
        EXPECT_EQ(stats.leafCount, leaves_);
        EXPECT_EQ(stats.maxDepth, maxDepth_);
        EXPECT_EQ(stats.maxLeafSize, maxLeaf_);
        EXPECT_EQ(stats.memoryBytes, bvh_.nodes.size() * 64 + n * 4);
        // The SAH cost, summed again from the tree.
        double rootArea = everything.halfArea();
        if (rootArea > 0.0)
            EXPECT_NEAR(stats.sahCost, sah_ / rootArea, 1e-9 * stats.sahCost);
        else
            EXPECT_EQ(stats.sahCost, 0.0);
#endif
    }

    // What the walk counted.
    size_t leaves() const { return leaves_; }
    int maxDepth() const { return maxDepth_; }
    int maxLeafSize() const { return maxLeaf_; }

private:
    // Checks node `index`, reached through a slot with box `parentBox`; returns the
    // union of its children's boxes.
    Box3 visitNode(uint32_t index, const Box3& parentBox, int depth) {
        Box3 unionBox;
        if (index >= bvh_.nodes.size()) {
            ADD_FAILURE() << "node index " << index << " out of range";
            return unionBox;
        }
        if (nodeSeen_[index]++) {
            ADD_FAILURE() << "node " << index << " reached twice";
            return unionBox;
        }
        const gpu::BvhNode& node = bvh_.nodes[index];
#ifdef BVH_TEST_OPTIONS
        sah_ += options_.nodeCost * parentBox.halfArea();
#endif
        const Slot slots[2] = {leftSlot(node), rightSlot(node)};
        for (int c = 0; c < 2; ++c) {
            const Slot& slot = slots[c];
            const Box3& box = slot.box;
            if (box.empty()) {  // a missing child: only in a root over 0 or 1 leaf
                EXPECT_EQ(index, 0u) << "an empty child below the root";
                EXPECT_EQ(slot.count, 0u);
                EXPECT_EQ(slot.index, 0u);
                EXPECT_LE(mesh_.triangleCount(), size_t(options_.maxLeafSize));
                EXPECT_TRUE(c == 1 || mesh_.triangleCount() == 0);
                continue;
            }
            EXPECT_TRUE(box.inside(parentBox)) << "child box of node " << index
                                               << " sticks out of its parent";
            if (slot.count == 0) {
                if (c == 0) EXPECT_EQ(slot.index, index + 1) << "depth first: left child next";
                else EXPECT_GT(slot.index, index);
                Box3 inner = visitNode(slot.index, box, depth + 1);
                EXPECT_TRUE(inner == box) << "node " << slot.index << ": box not tight";
            } else {
                ++leaves_;
                maxDepth_ = std::max(maxDepth_, depth);
                maxLeaf_ = std::max(maxLeaf_, int(slot.count));
                EXPECT_LE(slot.count, uint32_t(options_.maxLeafSize));
                EXPECT_LE(size_t(slot.index) + slot.count, mesh_.triangleCount());
                Box3 contents;
                for (uint32_t i = slot.index;
                     i < slot.index + slot.count && i < mesh_.triangleCount(); ++i) {
                    ++triangleSeen_[i];
                    Box3 triangle = triangleBox(mesh_, bvh_.triangleOrder[i]);
                    EXPECT_TRUE(triangle.inside(box)) << "triangle outside its leaf";
                    contents.grow(triangle);
                }
                EXPECT_TRUE(contents == box) << "leaf box not tight";
#ifdef BVH_TEST_OPTIONS
                sah_ += options_.triangleCost * leafTests(slot.count, options_) *
                        box.halfArea();
#endif
            }
            unionBox.grow(box);
        }
        return unionBox;
    }

    const Bvh& bvh_;
    const TestMesh& mesh_;
    const TreeOptions options_;
    std::vector<int> triangleSeen_, nodeSeen_;
    size_t leaves_ = 0;
    int maxDepth_ = 0, maxLeaf_ = 0;
    double sah_ = 0.0;
};

inline void expectValidTree(const TestMesh& mesh, const TreeOptions& options = {}) {
    SCOPED_TRACE(mesh.name);
    Bvh bvh = buildTree(mesh, options);
    TreeChecker(bvh, mesh, options).check();
}

// Rays against the tree and against every triangle: the same nearest hit (the same
// triangle at the same t, or a tie: another triangle at exactly that t, as on a shared
// edge), and the same answer to "anything in the way?".
struct CrossCheck {
    size_t rays = 0, hits = 0, ties = 0;
    TraversalCount worst;
    double meanIterations = 0.0, meanNodes = 0.0, meanTriangles = 0.0;
};

inline void crossCheckInto(const TestMesh& mesh, const Bvh& bvh, size_t rayCount, uint64_t seed,
                    CrossCheck& result) {
    TestMesh leafOrder = reordered(mesh, bvh);
    Bounds bounds = boundsOf(mesh);
    const float scale = std::max(1.0f, glm::length(bounds.max - bounds.min));
    const float tMin = 1e-5f * scale;
    for (const Ray& ray : testRays(mesh, rayCount, seed)) {
        ++result.rays;
        RayHit expected = bruteForce(mesh, ray, tMin, 1e30f, false);
        TraversalCount count;
        RayHit got = traverse(bvh, leafOrder, ray, tMin, 1e30f, false, &count);
        result.worst.loopIterations =
            std::max(result.worst.loopIterations, count.loopIterations);
        result.worst.maxStack = std::max(result.worst.maxStack, count.maxStack);
        result.meanIterations += count.loopIterations;
        result.meanNodes += count.nodeFetches;
        result.meanTriangles += count.triangleTests;
        ASSERT_EQ(got.found, expected.found)
            << "ray " << result.rays << " from (" << ray.origin.x << ", " << ray.origin.y
            << ", " << ray.origin.z << ")";
        if (expected.found) {
            ++result.hits;
            ASSERT_EQ(got.t, expected.t) << "ray " << result.rays;
            uint32_t gotInput = bvh.triangleOrder[got.triangle];
            if (gotInput == expected.triangle) {
                EXPECT_EQ(got.uv, expected.uv);
            } else {  // a tie: brute force must see this triangle at the same t too
                ++result.ties;
                float t;
                glm::vec2 uv;
                EXPECT_TRUE(hitMeshTriangle(mesh, gotInput, ray, tMin, 1e30f, t, uv) &&
                            t == expected.t)
                    << "ray " << result.rays << ": triangle " << gotInput << " is no tie";
            }
        }
        // Any hit: up to the nearest hit's distance, the shadow-ray question, and
        // beyond it; the triangle it reports must really be hit.
        for (float tMax : {expected.found ? expected.t : 1.0f, 1e30f}) {
            RayHit any = traverse(bvh, leafOrder, ray, tMin, tMax, true);
            ASSERT_EQ(any.found, bruteForce(mesh, ray, tMin, tMax, true).found);
            if (any.found) {
                float t;
                glm::vec2 uv;
                EXPECT_TRUE(hitMeshTriangle(leafOrder, any.triangle, ray, tMin, tMax, t, uv));
            }
        }
    }
    result.meanIterations /= double(result.rays);
    result.meanNodes /= double(result.rays);
    result.meanTriangles /= double(result.rays);
    EXPECT_LE(result.worst.maxStack, deepestLeaf(bvh)) << "stack bound";
}

inline CrossCheck crossCheck(const TestMesh& mesh, const Bvh& bvh, size_t rayCount,
                             uint64_t seed) {
    SCOPED_TRACE(mesh.name);
    CrossCheck result;
    crossCheckInto(mesh, bvh, rayCount, seed, result);
    return result;
}


}  // namespace bvh_test
