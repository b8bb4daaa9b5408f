// What every BVH builder of the course promises, on the CPU (built once per distinct tree:
// bvh_tests.cmake): the tree's invariants on many meshes (every triangle in exactly one
// leaf, boxes nested and tight, leaves and depth bounded), determinism, degenerate and
// bad inputs, and rays: the chapter's traversal, ported to C++, finds exactly what
// testing every triangle finds. What only some trees promise is in test_bvh_median.cpp
// (chapter 13's split), test_bvh_sah.cpp (the SAH's options and stats) and
// test_bvh_priced.cpp (chapter 21's leaf prices).
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <iostream>

#include "bvh_tree_checks.h"
#include "course/error.h"

using namespace bvh_test;

// ---------------------------------------------------------------------------------------
// Invariants
// ---------------------------------------------------------------------------------------

TEST(Bvh, InvariantsHoldOnVariedMeshes) {
    for (const TestMesh& mesh : variedMeshes()) expectValidTree(mesh);
}

// ---------------------------------------------------------------------------------------
// Determinism
// ---------------------------------------------------------------------------------------

TEST(Bvh, TwoBuildsAreByteIdentical) {
    for (const TestMesh& mesh : variedMeshes()) {
        SCOPED_TRACE(mesh.name);
        Bvh first = buildTree(mesh);
        Bvh second = buildTree(mesh);
        ASSERT_EQ(first.nodes.size(), second.nodes.size());
        EXPECT_EQ(std::memcmp(first.nodes.data(), second.nodes.data(),
                              first.nodes.size() * sizeof(gpu::BvhNode)),
                  0);
        EXPECT_EQ(first.triangleOrder, second.triangleOrder);
#ifdef BVH_TEST_OPTIONS
        EXPECT_EQ(first.stats.sahCost, second.stats.sahCost);
#endif
    }
}

// ---------------------------------------------------------------------------------------
// Degenerate and bad inputs
// ---------------------------------------------------------------------------------------

TEST(Bvh, NoTrianglesGiveARootWithoutChildren) {
    TestMesh empty{"empty"};
    Bvh bvh = buildTree(empty);
    ASSERT_EQ(bvh.nodes.size(), 1u);
    EXPECT_TRUE(bvh.triangleOrder.empty());
#ifdef BVH_TEST_OPTIONS
    EXPECT_EQ(bvh.stats.leafCount, 0u);
#endif
    expectValidTree(empty);
    Ray ray{{0, 0, -1}, {0, 0, 1}};
    EXPECT_FALSE(traverse(bvh, empty, ray, 0.0f, 1e30f, false).found);
}

TEST(Bvh, OneTriangleIsALeafInTheRoot) {
    TestMesh one{"one"};
    one.add({0, 0, 0}, {1, 0, 0}, {0, 1, 0});
    Bvh bvh = buildTree(one);
    ASSERT_EQ(bvh.nodes.size(), 1u);
    EXPECT_EQ(bvh.nodes[0].leftCount, 1u);
    EXPECT_EQ(bvh.nodes[0].rightCount, 0u);
    EXPECT_GT(bvh.nodes[0].rightMin.x, bvh.nodes[0].rightMax.x) << "the missing child: empty";
    EXPECT_EQ(deepestLeaf(bvh), 1);
#ifdef BVH_TEST_OPTIONS
    EXPECT_EQ(bvh.stats.maxDepth, 1);
#endif
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
    Bvh bvh = buildTree(same);
    TreeChecker sameChecker(bvh, same, TreeOptions{});
    sameChecker.check();
    EXPECT_EQ(sameChecker.maxDepth(), 12);  // 10000 -> 5000 -> ... -> 3: 12 halvings
    EXPECT_EQ(sameChecker.maxLeafSize(), BVH_MAX_LEAF_SIZE);
    // Points, segments and thin triangles.
    expectValidTree(zeroAreaTriangles(5000, 9));
    // Everything on one line: no area at all.
    TestMesh line{"line"};
    for (int i = 0; i < 100; ++i)
        line.add({float(i), 0, 0}, {i + 0.5f, 0, 0}, {float(i), 0, 0});
    expectValidTree(line);
#ifdef BVH_TEST_OPTIONS
    EXPECT_EQ(buildTree(line).stats.sahCost, 0.0);
#endif
    // Centroids a subnormal distance apart: too close to bin, so the list is halved.
    TestMesh tiny{"tiny"};
    for (int i = 0; i < 9; ++i) tiny.add({i * 1e-44f, 0, 0}, {i * 1e-44f, 1, 0}, {0, 0, 1});
    expectValidTree(tiny);
    // Huge coordinates: areas beyond float's range must not turn into inf or NaN.
    TestMesh huge{"huge"};
    huge.add({-3e38f, -3e38f, -3e38f}, {3e38f, -3e38f, 0}, {0, 3e38f, 3e38f});
    huge.add({-1, -1, -1}, {1, -1, 0}, {0, 1, 1});
    huge.add({3e38f, 3e38f, 3e38f}, {3e38f, 3e38f, 2e38f}, {2e38f, 3e38f, 3e38f});
    expectValidTree(huge);
#ifdef BVH_TEST_OPTIONS
    EXPECT_TRUE(std::isfinite(buildTree(huge).stats.sahCost));
#endif
}

TEST(Bvh, BadInputIsRefusedWithAMessage) {
    auto failure = [](const std::vector<glm::vec3>& positions,
                      const std::vector<uint32_t>& indices) {
        try {
            buildTree({"bad", positions, indices});
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
    std::vector<glm::vec3> infinite = three;
    infinite[2].z = -INFINITY;
    EXPECT_EQ(failure(infinite, {0, 1, 2}),
              "3 buildBvh: position 2 (triangle 0) is not a finite number");
}

// ---------------------------------------------------------------------------------------
// Rays: the tree finds what brute force finds
// ---------------------------------------------------------------------------------------

TEST(Bvh, TraversalFindsWhatBruteForceFinds) {
    for (const TestMesh& mesh : variedMeshes()) {
        Bvh bvh = buildTree(mesh);
        size_t rays = mesh.triangleCount() > 5000 ? 1000 : 4000;
        CrossCheck check = crossCheck(mesh, bvh, rays, 1234);
        std::cout << mesh.name << ": " << check.rays << " rays, " << check.hits << " hits, "
                  << check.ties << " ties; loop iterations per ray mean "
                  << check.meanIterations << ", max " << check.worst.loopIterations
                  << "; stack max " << check.worst.maxStack << "\n";
    }
}

// A valid tree serves any correct traversal, not only its chapter's: the course's three
// (left first, nearer first, while-while) on the same tree, against brute force, and
// chapter 31's walk of the threaded boxes where the chapter has it.
TEST(Bvh, EveryTraversalFindsWhatBruteForceFinds) {
    TestMesh teapot = loadTeapot("teapot_552");
    ASSERT_FALSE(teapot.positions.empty()) << "teapot_552.obj: build course_assets";
    for (const TestMesh& mesh : {teapot, flatGrid(12), randomSoup(300, 31)}) {
        SCOPED_TRACE(mesh.name);
        Bvh bvh = buildTree(mesh);
        TestMesh leafOrder = reordered(mesh, bvh);
        for (const Ray& ray : testRays(mesh, 1000, 77)) {
            RayHit expected = bruteForce(mesh, ray, 1e-5f, 1e30f, false);
            for (auto port : {&ports::leftFirst, &ports::nearFirst, &ports::whileWhile
#ifdef BVH_TEST_TRAVERSAL_THREADED
                              , &ports::threaded
#endif
                 }) {
                RayHit got = port(bvh, leafOrder, ray, 1e-5f, 1e30f, false, nullptr);
                ASSERT_EQ(got.found, expected.found);
                if (expected.found) {
                    ASSERT_EQ(got.t, expected.t);
                }
                ASSERT_EQ(port(bvh, leafOrder, ray, 1e-5f, 1e30f, true, nullptr).found,
                          expected.found);
            }
        }
    }
}

// The big teapots, when they are there: build time, tree, and a few rays. Brute force
// through a million triangles is the slow part: one tree only (bvh_tests.cmake).
#ifdef BVH_TEST_BIG_TEAPOTS
TEST(Bvh, BigTeapotsBuildValidTrees) {
    bool any = false;
    for (const char* name : {"teapot_102080", "teapot_1015056"}) {
        TestMesh teapot = loadTeapot(name);
        if (teapot.positions.empty()) continue;
        any = true;
        Bvh bvh = buildTree(teapot);
#ifdef BVH_TEST_OPTIONS
        std::cout << name << ": " << describeBvh(bvh.stats) << "\n";
        EXPECT_EQ(bvh.stats.depthLimitedSplits, 0u);
#endif
        TreeChecker(bvh, teapot, TreeOptions{}).check();
        CrossCheck check = crossCheck(teapot, bvh, 40, 77);  // brute force is slow here
        std::cout << name << ": loop iterations per ray mean " << check.meanIterations
                  << ", max " << check.worst.loopIterations << "\n";
    }
    // The build makes them for these tests (bvh_tests.cmake): missing is a failure.
    ASSERT_TRUE(any) << "no big teapots in " << meshDir();
}
#endif
