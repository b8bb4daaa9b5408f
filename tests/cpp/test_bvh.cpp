// Chapter 14's BVH builder (the binned SAH), on the CPU: the tree's invariants on many
// meshes (every triangle in exactly one leaf, boxes nested and tight, leaves and depth
// bounded), determinism, degenerate and bad inputs, and rays: the traversal of
// bvh_traversal.glsl, ported to C++, finds exactly what testing every triangle finds.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <iostream>
#include <set>

#include "bvh_test_support.h"
#include "course/error.h"
#include "course/stats.h"

using namespace bvh_test;

namespace {

// ---------------------------------------------------------------------------------------
// Meshes
// ---------------------------------------------------------------------------------------

// n copies of one triangle: all centroids equal, no plane separates any two.
TestMesh identicalTriangles(int n) {
    TestMesh mesh{"identical_" + std::to_string(n)};
    for (int i = 0; i < n; ++i) mesh.add({0, 0, 0}, {1, 0, 0}, {0, 1, 0});
    return mesh;
}

// Zero-area triangles: points and segments scattered in the unit cube, and a few real
// triangles among them.
TestMesh zeroAreaTriangles(int n, uint64_t seed) {
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

std::vector<TestMesh> variedMeshes() {
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
// The invariants
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

Box3 triangleBox(const TestMesh& mesh, uint32_t triangle) {
    Box3 box;
    for (int k = 0; k < 3; ++k) box.grow(mesh.positions[mesh.indices[3 * triangle + k]]);
    return box;
}

// Walks the whole tree from the root and checks everything a traversal relies on.
class TreeChecker {
public:
    TreeChecker(const Bvh& bvh, const TestMesh& mesh, const BvhOptions& options)
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
        const BvhStats& stats = bvh_.stats;
        EXPECT_EQ(stats.triangleCount, n);
        EXPECT_EQ(stats.nodeCount, bvh_.nodes.size());
        EXPECT_EQ(stats.leafCount, leaves_);
        EXPECT_EQ(stats.maxDepth, maxDepth_);
        EXPECT_EQ(stats.maxLeafSize, maxLeaf_);
        EXPECT_LE(stats.maxDepth, options_.maxDepth);
        EXPECT_LE(stats.maxLeafSize, options_.maxLeafSize);
        EXPECT_EQ(bvh_.nodes.size(), leaves_ <= 1 ? 1 : leaves_ - 1)
            << "a binary tree: one node fewer than leaves (the root wraps a lone leaf)";
        EXPECT_EQ(stats.memoryBytes, bvh_.nodes.size() * 64 + n * 4);
        // The SAH cost, summed again from the tree.
        double rootArea = everything.halfArea();
        if (rootArea > 0.0)
            EXPECT_NEAR(stats.sahCost, sah_ / rootArea, 1e-9 * stats.sahCost);
        else
            EXPECT_EQ(stats.sahCost, 0.0);
    }

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
        sah_ += options_.nodeCost * parentBox.halfArea();
        struct Slot {
            glm::vec3 min, max;
            uint32_t index, count;
        } slots[2] = {{node.leftMin, node.leftMax, node.leftIndex, node.leftCount},
                      {node.rightMin, node.rightMax, node.rightIndex, node.rightCount}};
        for (int c = 0; c < 2; ++c) {
            const Slot& slot = slots[c];
            Box3 box{slot.min, slot.max};
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
                sah_ += options_.triangleCost * slot.count * box.halfArea();
            }
            unionBox.grow(box);
        }
        return unionBox;
    }

    const Bvh& bvh_;
    const TestMesh& mesh_;
    const BvhOptions& options_;
    std::vector<int> triangleSeen_, nodeSeen_;
    size_t leaves_ = 0;
    int maxDepth_ = 0, maxLeaf_ = 0;
    double sah_ = 0.0;
};

void expectValidTree(const TestMesh& mesh, const BvhOptions& options = {}) {
    SCOPED_TRACE(mesh.name);
    Bvh bvh = buildBvh(mesh.positions, mesh.indices, options);
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

void crossCheckInto(const TestMesh& mesh, const Bvh& bvh, size_t rayCount, uint64_t seed,
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
    EXPECT_LE(result.worst.maxStack, bvh.stats.maxDepth) << "stack bound";
}

CrossCheck crossCheck(const TestMesh& mesh, const Bvh& bvh, size_t rayCount, uint64_t seed) {
    SCOPED_TRACE(mesh.name);
    CrossCheck result;
    crossCheckInto(mesh, bvh, rayCount, seed, result);
    return result;
}

}  // namespace

// ---------------------------------------------------------------------------------------
// Invariants
// ---------------------------------------------------------------------------------------

TEST(Bvh, InvariantsHoldOnVariedMeshes) {
    for (const TestMesh& mesh : variedMeshes()) expectValidTree(mesh);
}

TEST(Bvh, InvariantsHoldForEveryOption) {
    TestMesh soup = randomSoup(3000, 11);
    TestMesh teapot = loadTeapot("teapot_552");
    for (int leaf = 1; leaf <= BVH_MAX_LEAF_SIZE; ++leaf)
        for (int bins : {2, 5, 16, 64}) {
            BvhOptions options;
            options.maxLeafSize = leaf;
            options.binCount = bins;
            options.allAxes = (bins % 2 == 0);
            SCOPED_TRACE("leaf " + std::to_string(leaf) + ", bins " + std::to_string(bins));
            expectValidTree(soup, options);
            if (!teapot.positions.empty()) expectValidTree(teapot, options);
        }
    BvhOptions cheapNodes;  // nodes cost little: deeper trees, smaller leaves
    cheapNodes.nodeCost = 0.1f;
    expectValidTree(soup, cheapNodes);
    BvhOptions dearNodes;  // nodes cost a lot: leaves as full as allowed
    dearNodes.nodeCost = 100.0f;
    expectValidTree(soup, dearNodes);
    Bvh full = buildBvh(soup.positions, soup.indices, dearNodes);
    EXPECT_EQ(full.stats.maxLeafSize, BVH_MAX_LEAF_SIZE);
}

TEST(Bvh, DepthLimitHoldsWhereTheSahWouldGoDeeper) {
    // Without a limit the SAH would peel one triangle at a time: depth 79.
    TestMesh chain = peelingChain(80);
    BvhOptions twoBins;
    twoBins.binCount = 2;
    Bvh bvh = buildBvh(chain.positions, chain.indices, twoBins);
    EXPECT_EQ(bvh.stats.maxDepth, BVH_MAX_DEPTH);
    EXPECT_GT(bvh.stats.depthLimitedSplits, 0u);
    expectValidTree(chain, twoBins);
    crossCheck(chain, bvh, 2000, 3);
    // A tight limit: exactly what halving needs, so every split must halve.
    TestMesh soup = randomSoup(1000, 3);
    BvhOptions tight;
    tight.maxDepth = 8;  // 1000 -> 500 -> ... -> 4 in 8 halvings
    Bvh shallow = buildBvh(soup.positions, soup.indices, tight);
    EXPECT_LE(shallow.stats.maxDepth, 8);
    EXPECT_GT(shallow.stats.depthLimitedSplits, 0u);
    expectValidTree(soup, tight);
    tight.maxDepth = 7;  // cannot be done
    EXPECT_THROW(buildBvh(soup.positions, soup.indices, tight), course::Failure);
}

TEST(Bvh, TeapotTreesAreShallowAndCheap) {
    TestMesh teapot = loadTeapot("teapot_6320");
    ASSERT_FALSE(teapot.positions.empty()) << "teapot_6320.obj not built";
    Bvh bvh = buildBvh(teapot.positions, teapot.indices);
    std::cout << describeBvh(bvh.stats) << "\n";
    EXPECT_EQ(bvh.stats.depthLimitedSplits, 0u);
    EXPECT_LE(bvh.stats.maxDepth, 32);
    // A ray crossing the teapot's box costs well under 1% of testing all 6320.
    EXPECT_LT(bvh.stats.sahCost, 0.01 * 6320);
    // Three axes are never worse than the longest one alone, here.
    BvhOptions longest;
    longest.allAxes = false;
    Bvh longestOnly = buildBvh(teapot.positions, teapot.indices, longest);
    EXPECT_LE(bvh.stats.sahCost, longestOnly.stats.sahCost);
}

// ---------------------------------------------------------------------------------------
// Determinism
// ---------------------------------------------------------------------------------------

TEST(Bvh, TwoBuildsAreByteIdentical) {
    for (const TestMesh& mesh : variedMeshes()) {
        SCOPED_TRACE(mesh.name);
        Bvh first = buildBvh(mesh.positions, mesh.indices);
        Bvh second = buildBvh(mesh.positions, mesh.indices);
        ASSERT_EQ(first.nodes.size(), second.nodes.size());
        EXPECT_EQ(std::memcmp(first.nodes.data(), second.nodes.data(),
                              first.nodes.size() * sizeof(gpu::BvhNode)),
                  0);
        EXPECT_EQ(first.triangleOrder, second.triangleOrder);
        EXPECT_EQ(first.stats.sahCost, second.stats.sahCost);
    }
}

// ---------------------------------------------------------------------------------------
// Degenerate and bad inputs
// ---------------------------------------------------------------------------------------

TEST(Bvh, NoTrianglesGiveARootWithoutChildren) {
    TestMesh empty{"empty"};
    Bvh bvh = buildBvh(empty.positions, empty.indices);
    ASSERT_EQ(bvh.nodes.size(), 1u);
    EXPECT_EQ(bvh.stats.leafCount, 0u);
    EXPECT_TRUE(bvh.triangleOrder.empty());
    expectValidTree(empty);
    Ray ray{{0, 0, -1}, {0, 0, 1}};
    EXPECT_FALSE(traverse(bvh, empty, ray, 0.0f, 1e30f, false).found);
}

TEST(Bvh, OneTriangleIsALeafInTheRoot) {
    TestMesh one{"one"};
    one.add({0, 0, 0}, {1, 0, 0}, {0, 1, 0});
    Bvh bvh = buildBvh(one.positions, one.indices);
    ASSERT_EQ(bvh.nodes.size(), 1u);
    EXPECT_EQ(bvh.nodes[0].leftCount, 1u);
    EXPECT_EQ(bvh.nodes[0].rightCount, 0u);
    EXPECT_GT(bvh.nodes[0].rightMin.x, bvh.nodes[0].rightMax.x) << "the missing child: empty";
    EXPECT_EQ(bvh.stats.maxDepth, 1);
    expectValidTree(one);
    // Rays from every side, including straight at the empty child's "box".
    for (glm::vec3 direction : {glm::vec3(0, 0, 1), glm::vec3(0, 0, -1), glm::vec3(1, 0, 0),
                                glm::vec3(-1, -1, -1)}) {
        Ray ray{glm::vec3(0.2f, 0.2f, 0.0f) - 2.0f * direction, direction};
        RayHit hit = traverse(bvh, one, ray, 0.0f, 1e30f, false);
        EXPECT_EQ(hit.found, direction.z != 0.0f);
    }
    crossCheck(one, bvh, 400, 5);
}

TEST(Bvh, DegenerateMeshesStillGiveValidTrees) {
    // All centroids equal: the list is halved down to leaves.
    TestMesh same = identicalTriangles(10000);
    Bvh bvh = buildBvh(same.positions, same.indices);
    EXPECT_EQ(bvh.stats.maxDepth, 12);  // 10000 -> 5000 -> ... -> 3: 12 halvings
    EXPECT_EQ(bvh.stats.maxLeafSize, BVH_MAX_LEAF_SIZE);
    expectValidTree(same);
    // Points, segments and thin triangles.
    expectValidTree(zeroAreaTriangles(5000, 9));
    // Everything on one line: no area at all.
    TestMesh line{"line"};
    for (int i = 0; i < 100; ++i)
        line.add({float(i), 0, 0}, {i + 0.5f, 0, 0}, {float(i), 0, 0});
    Bvh lineBvh = buildBvh(line.positions, line.indices);
    EXPECT_EQ(lineBvh.stats.sahCost, 0.0);
    expectValidTree(line);
    // Centroids a subnormal distance apart: too close to bin, so the list is halved.
    TestMesh tiny{"tiny"};
    for (int i = 0; i < 9; ++i) tiny.add({i * 1e-44f, 0, 0}, {i * 1e-44f, 1, 0}, {0, 0, 1});
    expectValidTree(tiny);
    // Huge coordinates: areas beyond float's range must not turn into inf or NaN.
    TestMesh huge{"huge"};
    huge.add({-3e38f, -3e38f, -3e38f}, {3e38f, -3e38f, 0}, {0, 3e38f, 3e38f});
    huge.add({-1, -1, -1}, {1, -1, 0}, {0, 1, 1});
    huge.add({3e38f, 3e38f, 3e38f}, {3e38f, 3e38f, 2e38f}, {2e38f, 3e38f, 3e38f});
    Bvh hugeBvh = buildBvh(huge.positions, huge.indices);
    EXPECT_TRUE(std::isfinite(hugeBvh.stats.sahCost));
    expectValidTree(huge);
}

TEST(Bvh, BadInputIsRefusedWithAMessage) {
    auto failure = [](const std::vector<glm::vec3>& positions,
                      const std::vector<uint32_t>& indices, BvhOptions options = {}) {
        try {
            buildBvh(positions, indices, options);
        } catch (const course::Failure& failure) {
            return std::to_string(int(failure.code())) + " " + failure.what();
        }
        return std::string("built");
    };
    std::vector<glm::vec3> three = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    EXPECT_EQ(failure(three, {0, 1}), "3 buildBvh: 2 triangle indices: not 3 per triangle");
    EXPECT_EQ(failure(three, {0, 1, 2, 0, 1, 3}),
              "3 buildBvh: triangle 1 corner 2: index 3, but there are only 3 positions");
    std::vector<glm::vec3> nan = three;
    nan[1].y = std::nanf("");
    EXPECT_EQ(failure(nan, {0, 1, 2}),
              "3 buildBvh: position 1 (triangle 0) is not a finite number");
    auto optionFailure = [&](BvhOptions options) { return failure(three, {0, 1, 2}, options); };
    BvhOptions options;
    options.maxLeafSize = BVH_MAX_LEAF_SIZE + 1;
    EXPECT_NE(optionFailure(options).find("2 buildBvh: maxLeafSize"), std::string::npos);
    options = {};
    options.binCount = 1;
    EXPECT_NE(optionFailure(options).find("2 buildBvh: binCount"), std::string::npos);
    options = {};
    options.nodeCost = 0.0f;
    EXPECT_NE(optionFailure(options).find("2 buildBvh: nodeCost"), std::string::npos);
    options = {};
    options.maxDepth = BVH_MAX_DEPTH + 1;
    EXPECT_NE(optionFailure(options).find("2 buildBvh: maxDepth"), std::string::npos);
}

// ---------------------------------------------------------------------------------------
// Rays: the tree finds what brute force finds
// ---------------------------------------------------------------------------------------

TEST(Bvh, TraversalFindsWhatBruteForceFinds) {
    for (const TestMesh& mesh : variedMeshes()) {
        Bvh bvh = buildBvh(mesh.positions, mesh.indices);
        size_t rays = mesh.triangleCount() > 5000 ? 1000 : 4000;
        CrossCheck check = crossCheck(mesh, bvh, rays, 1234);
        std::cout << mesh.name << ": " << check.rays << " rays, " << check.hits << " hits, "
                  << check.ties << " ties; loop iterations per ray mean "
                  << check.meanIterations << ", max " << check.worst.loopIterations
                  << "; stack max " << check.worst.maxStack << "\n";
    }
}

TEST(Bvh, TraversalWorksForEveryLeafSize) {
    TestMesh teapot = loadTeapot("teapot_552");
    if (teapot.positions.empty()) teapot = randomSoup(552, 552);
    for (int leaf = 1; leaf <= BVH_MAX_LEAF_SIZE; ++leaf) {
        BvhOptions options;
        options.maxLeafSize = leaf;
        crossCheck(teapot, buildBvh(teapot.positions, teapot.indices, options), 2000, leaf);
    }
}

// ---------------------------------------------------------------------------------------
// Helpers for the chapter
// ---------------------------------------------------------------------------------------

TEST(Bvh, StatsGoToVerboseAndJson) {
    TestMesh soup = randomSoup(500, 8);
    Bvh bvh = buildBvh(soup.positions, soup.indices);
    std::string line = describeBvh(bvh.stats);
    EXPECT_NE(line.find("500 triangles -> " + std::to_string(bvh.stats.nodeCount) + " nodes"),
              std::string::npos)
        << line;
    course::Stats json;
    recordBvhStats(bvh.stats, json);
    EXPECT_EQ(json.number("bvh_nodes"), double(bvh.stats.nodeCount));
    EXPECT_EQ(json.number("bvh_max_depth"), double(bvh.stats.maxDepth));
    EXPECT_NE(json.toJson().find("\"bvh_sah_cost\""), std::string::npos);
}

// The big teapots, when they are there: build time, tree, and a few rays.
TEST(Bvh, BigTeapotsBuildValidTrees) {
    bool any = false;
    for (const char* name : {"teapot_102080", "teapot_1015056"}) {
        TestMesh teapot = loadTeapot(name);
        if (teapot.positions.empty()) continue;
        any = true;
        Bvh bvh = buildBvh(teapot.positions, teapot.indices);
        std::cout << name << ": " << describeBvh(bvh.stats) << "\n";
        EXPECT_EQ(bvh.stats.depthLimitedSplits, 0u);
        TreeChecker(bvh, teapot, BvhOptions{}).check();
        CrossCheck check = crossCheck(teapot, bvh, 40, 77);  // brute force is slow here
        std::cout << name << ": loop iterations per ray mean " << check.meanIterations
                  << ", max " << check.worst.loopIterations << "\n";
    }
    // The build makes them for these tests (bvh_tests.cmake): missing is a failure.
    ASSERT_TRUE(any) << "no big teapots in " << meshDir();
}
