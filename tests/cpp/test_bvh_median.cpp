// Chapter 13's tree, split at the median (book/docs/chapters/13_bvh.md): a range of more
// than four triangles is halved by count, the triangles whose centroids come first
// along the longest side of the centroids' box going left (ties by input index); a
// range of four or fewer is a leaf. So the tree is balanced: no leaf deeper than
// log2(n / 4), rounded up. Built for every tree whose bvh.h has no BvhOptions
// (bvh_tests.cmake); what every tree promises is in test_bvh.cpp.
#include <gtest/gtest.h>

#include <algorithm>
#include <iostream>
#include <utility>

#include "bvh_tree_checks.h"

using namespace bvh_test;

namespace {

// The slot that holds the whole mesh: node 0, or the lone leaf it wraps.
Slot wholeMesh(const Bvh& bvh) {
    const gpu::BvhNode& root = bvh.nodes.at(0);
    if (rightSlot(root).box.empty()) return leftSlot(root);
    Box3 box = leftSlot(root).box;
    box.grow(rightSlot(root).box);
    return {box, 0, 0};
}

// Halvings until a range of n fits in a leaf (the larger half each time): the depth a
// median tree's leaves reach, counted in node fetches (at least 1: the root's).
int halvingDepth(size_t n) {
    int depth = 0;
    for (; n > BVH_MAX_LEAF_SIZE; n = (n + 1) / 2) ++depth;
    return std::max(depth, 1);
}

// A triangle's centroid as the builder takes it: the centre of its box.
glm::vec3 centroid(const TestMesh& mesh, uint32_t triangle) {
    Box3 box = triangleBox(mesh, triangle);
    return box.min * 0.5f + box.max * 0.5f;
}

// Checks the split rule at every node under `slot`; counts the nodes.
void expectMedianSplits(const TestMesh& mesh, const Bvh& bvh, const Slot& slot,
                        size_t& nodes) {
    const std::vector<uint32_t> triangles = trianglesUnder(bvh, slot);
    if (slot.isLeaf()) {
        EXPECT_LE(triangles.size(), size_t(BVH_MAX_LEAF_SIZE));
        return;
    }
    ++nodes;
    ASSERT_GT(triangles.size(), size_t(BVH_MAX_LEAF_SIZE))
        << "a node over a range that fits in a leaf";
    const gpu::BvhNode& node = bvh.nodes.at(slot.index);
    const std::vector<uint32_t> left = trianglesUnder(bvh, leftSlot(node));
    const std::vector<uint32_t> right = trianglesUnder(bvh, rightSlot(node));
    // Halves by count: the left one the smaller when the count is odd.
    ASSERT_EQ(left.size(), triangles.size() / 2);
    ASSERT_EQ(right.size(), triangles.size() - triangles.size() / 2);
    // The longest side of the centroids' box (the first of equally long ones) ...
    Box3 centroids;
    for (uint32_t triangle : triangles) centroids.grow(centroid(mesh, triangle));
    const glm::vec3 extent = centroids.max - centroids.min;
    int axis = 0;
    for (int a = 1; a < 3; ++a)
        if (extent[a] > extent[axis]) axis = a;
    // ... along which every left centroid comes before every right one (ties: by index).
    auto key = [&](uint32_t triangle) {
        return std::make_pair(centroid(mesh, triangle)[axis], triangle);
    };
    std::pair<float, uint32_t> lastLeft = key(left[0]), firstRight = key(right[0]);
    for (uint32_t triangle : left) lastLeft = std::max(lastLeft, key(triangle));
    for (uint32_t triangle : right) firstRight = std::min(firstRight, key(triangle));
    EXPECT_LT(lastLeft, firstRight) << "node " << slot.index << ": axis " << axis
                                    << ", left ends at triangle " << lastLeft.second
                                    << ", right starts at triangle " << firstRight.second;
    expectMedianSplits(mesh, bvh, leftSlot(node), nodes);
    expectMedianSplits(mesh, bvh, rightSlot(node), nodes);
}

// The input triangles of a leaf slot, in input order.
std::vector<uint32_t> leafTriangles(const Bvh& bvh, const Slot& slot) {
    EXPECT_TRUE(slot.isLeaf());
    std::vector<uint32_t> triangles = trianglesUnder(bvh, slot);
    std::sort(triangles.begin(), triangles.end());
    return triangles;
}

// A small triangle whose box is [p, p + 0.1] in x and y: its centroid is p + 0.05.
void addSmall(TestMesh& mesh, glm::vec3 p) {
    mesh.add(p, p + glm::vec3(0.1f, 0.0f, 0.0f), p + glm::vec3(0.0f, 0.1f, 0.0f));
}

}  // namespace

TEST(MedianSplit, EveryNodeHalvesItsRangeAlongTheCentroidsLongestSide) {
    for (const TestMesh& mesh : variedMeshes()) {
        SCOPED_TRACE(mesh.name);
        Bvh bvh = buildTree(mesh);
        size_t nodes = 0;
        expectMedianSplits(mesh, bvh, wholeMesh(bvh), nodes);
        EXPECT_EQ(nodes, mesh.triangleCount() <= BVH_MAX_LEAF_SIZE ? 0 : bvh.nodes.size());
    }
}

TEST(MedianSplit, NoLeafIsDeeperThanLog2OfNOverFourRoundedUp) {
    std::vector<TestMesh> meshes;
    for (size_t n = 1; n <= 70; ++n) meshes.push_back(randomSoup(n, 1000 + n));
    for (size_t n : {127, 128, 129, 1000, 4096, 4097}) meshes.push_back(randomSoup(n, n));
    for (const char* name : {"teapot_552", "teapot_6320"}) {
        meshes.push_back(loadTeapot(name));
        ASSERT_FALSE(meshes.back().positions.empty()) << name << ".obj: build course_assets";
    }
    for (const TestMesh& mesh : meshes) {
        SCOPED_TRACE(mesh.name);
        const size_t n = mesh.triangleCount();
        // Halving is as shallow as a tree of leaves of four can be: the deepest leaf is
        // exactly that far down.
        Bvh bvh = buildTree(mesh);
        TreeChecker checker(bvh, mesh, TreeOptions{});
        checker.check();
        EXPECT_EQ(checker.maxDepth(), halvingDepth(n));
        EXPECT_GE(checker.leaves(), (n + BVH_MAX_LEAF_SIZE - 1) / BVH_MAX_LEAF_SIZE);
    }
    // The page's figure for the teapot: 11 levels (6320 / 4 = 1580, 2^11 = 2048).
    EXPECT_EQ(deepestLeaf(buildTree(meshes.back())), 11);
}

// Five triangles in a row along x, at 0, 1, 2, 3 and far off at 100, given in a shuffled
// order: the median puts the two first along x left and the other three right (a split
// halfway along the box would put four left).
TEST(MedianSplit, TheFirstHalfAlongXGoesLeftWhateverTheInputOrder) {
    TestMesh row{"row"};
    for (float x : {100.0f, 2.0f, 0.0f, 3.0f, 1.0f}) addSmall(row, {x, 0.0f, 0.0f});
    Bvh bvh = buildTree(row);
    ASSERT_EQ(bvh.nodes.size(), 1u);
    EXPECT_EQ(leafTriangles(bvh, leftSlot(bvh.nodes[0])), (std::vector<uint32_t>{2, 4}));
    EXPECT_EQ(leafTriangles(bvh, rightSlot(bvh.nodes[0])), (std::vector<uint32_t>{0, 1, 3}));
    EXPECT_EQ(bvh.nodes[0].leftMax.x, 1.1f);
    EXPECT_EQ(bvh.nodes[0].rightMin.x, 2.0f);
}

// Six triangles spread 10 along y and 1 along x: split along y, the longest side, so
// the three lowest go left, though along x another three come first.
TEST(MedianSplit, TheSplitIsAlongTheLongestSideOfTheCentroidsBox) {
    TestMesh zigzag{"zigzag"};
    const float x[] = {1, 0, 1, 0, 1, 0}, y[] = {0, 10, 2, 8, 4, 6};
    for (int i = 0; i < 6; ++i) addSmall(zigzag, {x[i], y[i], 0.0f});
    Bvh bvh = buildTree(zigzag);
    ASSERT_EQ(bvh.nodes.size(), 1u);
    EXPECT_EQ(leafTriangles(bvh, leftSlot(bvh.nodes[0])), (std::vector<uint32_t>{0, 2, 4}));
    EXPECT_EQ(leafTriangles(bvh, rightSlot(bvh.nodes[0])), (std::vector<uint32_t>{1, 3, 5}));
}

// Centroids all in one place: no side is longer, x is taken, and ties go by input
// index: the first half of the input left.
TEST(MedianSplit, TiesGoByInputIndex) {
    TestMesh same{"same"};
    for (int i = 0; i < 6; ++i) addSmall(same, {0.0f, 0.0f, 0.0f});
    Bvh bvh = buildTree(same);
    ASSERT_EQ(bvh.nodes.size(), 1u);
    EXPECT_EQ(leafTriangles(bvh, leftSlot(bvh.nodes[0])), (std::vector<uint32_t>{0, 1, 2}));
    EXPECT_EQ(leafTriangles(bvh, rightSlot(bvh.nodes[0])), (std::vector<uint32_t>{3, 4, 5}));
}
