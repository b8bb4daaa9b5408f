// What the SAH builders promise besides every tree's invariants (test_bvh.cpp): their
// options (leaf size, bins, axes, prices, depth limit) all give valid trees, a split
// happens exactly when the surface area heuristic says it is cheaper, the depth limit
// holds where the SAH would go deeper, the stats, and bad options refused. Built for
// every tree whose bvh.h has BvhOptions (bvh_tests.cmake): chapter 14's, and chapter
// 21's with each of its two leaf prices where a test does not depend on the price.
#include <gtest/gtest.h>

#include <cmath>
#include <iostream>

#include "bvh_tree_checks.h"
#include "course/error.h"
#include "course/stats.h"

using namespace bvh_test;

namespace {

// Chapter 14's price of a leaf, the triangles it holds, whichever tree this is.
TreeOptions pricedByCount() { return everyLeafPrice({}).front(); }

}  // namespace

// ---------------------------------------------------------------------------------------
// Invariants
// ---------------------------------------------------------------------------------------

TEST(Bvh, InvariantsHoldForEveryOption) {
    TestMesh soup = randomSoup(3000, 11);
    TestMesh teapot = loadTeapot("teapot_552");
    ASSERT_FALSE(teapot.positions.empty()) << "teapot_552.obj: build course_assets";
    for (int leaf = 1; leaf <= BVH_MAX_LEAF_SIZE; ++leaf)
        for (int bins : {2, 5, 16, 64}) {
            TreeOptions options;
            options.maxLeafSize = leaf;
            options.binCount = bins;
            options.allAxes = (bins % 2 == 0);
            for (const TreeOptions& priced : everyLeafPrice(options)) {
                SCOPED_TRACE("leaf " + std::to_string(leaf) + ", bins " +
                             std::to_string(bins));
                expectValidTree(soup, priced);
                expectValidTree(teapot, priced);
            }
        }
    TreeOptions cheapNodes;  // nodes cost little: deeper trees, smaller leaves
    cheapNodes.nodeCost = 0.1f;
    TreeOptions dearNodes;  // nodes cost a lot: leaves as full as allowed
    dearNodes.nodeCost = 100.0f;
    for (const TreeOptions& options : {cheapNodes, dearNodes})
        for (const TreeOptions& priced : everyLeafPrice(options))
            expectValidTree(soup, priced);
    for (const TreeOptions& priced : everyLeafPrice(dearNodes))
        EXPECT_EQ(buildTree(soup, priced).stats.maxLeafSize, BVH_MAX_LEAF_SIZE);
}

// ---------------------------------------------------------------------------------------
// The split rule, on cases worked out by hand
// ---------------------------------------------------------------------------------------

// Two triangles, boxes of half area 1 each, a box of 2 + gap around both (SAH units).
// Priced by count, the split costs nodeCost * A + triangleCost * (1 * 1 + 1 * 1) and the
// leaf triangleCost * 2 * A; a split is made only when strictly cheaper.
TEST(Bvh, APairIsSplitExactlyWhenTheSahSaysSo) {
    struct Case {
        float gap, nodeCost, triangleCost;
        bool split;
        double sahCost;  // of the tree, per unit of the root's area
    } cases[] = {
        // A = 4: split when 4 nodeCost + 2 < 8, nodeCost < 1.5.
        {2.0f, 1.0f, 1.0f, true, (4.0 + 1.0 + 1.0) / 4.0},
        {2.0f, 1.4921875f, 1.0f, true, (4.0 * 1.4921875 + 1.0 + 1.0) / 4.0},
        {2.0f, 1.5f, 1.0f, false, (4.0 * 1.5 + 2.0 * 4.0) / 4.0},  // a tie: one leaf
        {2.0f, 3.0f, 2.0f, false, (4.0 * 3.0 + 2.0 * 2.0 * 4.0) / 4.0},  // the same ratio
        // A = 2.5: 2.5 + 2 < 5 splits; A = 1.5: 1.5 + 2 < 3 does not.
        {0.5f, 1.0f, 1.0f, true, (2.5 + 1.0 + 1.0) / 2.5},
        {-0.5f, 1.0f, 1.0f, false, (1.5 + 2.0 * 1.5) / 1.5},
    };
    for (const Case& c : cases) {
        TreeOptions options = pricedByCount();
        options.nodeCost = c.nodeCost;
        options.triangleCost = c.triangleCost;
        TestMesh pair = twoTrianglesApart(c.gap);
        SCOPED_TRACE(pair.name + ", node cost " + std::to_string(c.nodeCost) +
                     ", triangle cost " + std::to_string(c.triangleCost));
        Bvh bvh = buildTree(pair, options);
        ASSERT_EQ(bvh.nodes.size(), 1u);
        const gpu::BvhNode& root = bvh.nodes[0];
        if (c.split) {  // a root over two leaves of one
            EXPECT_EQ(root.leftCount, 1u);
            EXPECT_EQ(root.rightCount, 1u);
        } else {  // a root wrapping one leaf of two
            EXPECT_EQ(root.leftCount, 2u);
            EXPECT_EQ(root.rightCount, 0u);
        }
        EXPECT_DOUBLE_EQ(bvh.stats.sahCost, c.sahCost);
        TreeChecker(bvh, pair, options).check();
    }
}

// ---------------------------------------------------------------------------------------
// Depth
// ---------------------------------------------------------------------------------------

TEST(Bvh, DepthLimitHoldsWhereTheSahWouldGoDeeper) {
    // Without a limit the SAH would peel one triangle at a time: depth 79.
    TestMesh chain = peelingChain(80);
    TreeOptions twoBins;
    twoBins.binCount = 2;
    for (const TreeOptions& priced : everyLeafPrice(twoBins)) {
        Bvh bvh = buildTree(chain, priced);
        EXPECT_EQ(bvh.stats.maxDepth, BVH_MAX_DEPTH);
        EXPECT_GT(bvh.stats.depthLimitedSplits, 0u);
        expectValidTree(chain, priced);
        crossCheck(chain, bvh, 2000, 3);
    }
    // A tight limit: exactly what halving needs, so every split must halve.
    TestMesh soup = randomSoup(1000, 3);
    TreeOptions tight;
    tight.maxDepth = 8;  // 1000 -> 500 -> ... -> 4 in 8 halvings
    Bvh shallow = buildTree(soup, tight);
    EXPECT_LE(shallow.stats.maxDepth, 8);
    EXPECT_GT(shallow.stats.depthLimitedSplits, 0u);
    expectValidTree(soup, tight);
    tight.maxDepth = 7;  // cannot be done
    EXPECT_THROW(buildTree(soup, tight), course::Failure);
}

TEST(Bvh, TeapotTreesAreShallowAndCheap) {
    TestMesh teapot = loadTeapot("teapot_6320");
    ASSERT_FALSE(teapot.positions.empty()) << "teapot_6320.obj not built";
    for (const TreeOptions& priced : everyLeafPrice({})) {
        Bvh bvh = buildTree(teapot, priced);
        std::cout << describeBvh(bvh.stats) << "\n";
        EXPECT_EQ(bvh.stats.depthLimitedSplits, 0u);
        EXPECT_LE(bvh.stats.maxDepth, 32);
        // A ray crossing the teapot's box costs well under 1% of testing all 6320.
        EXPECT_LT(bvh.stats.sahCost, 0.01 * 6320);
        // Three axes are never worse than the longest one alone, here.
        TreeOptions longest = priced;
        longest.allAxes = false;
        EXPECT_LE(bvh.stats.sahCost, buildTree(teapot, longest).stats.sahCost);
    }
}

// ---------------------------------------------------------------------------------------
// Bad options
// ---------------------------------------------------------------------------------------

TEST(Bvh, BadOptionsAreRefusedWithAMessage) {
    auto failure = [](const TreeOptions& options) {
        try {
            buildTree({"three", {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, {0, 1, 2}}, options);
        } catch (const course::Failure& failure) {
            return std::to_string(int(failure.code())) + " " + failure.what();
        }
        return std::string("built");
    };
    TreeOptions options;
    options.maxLeafSize = BVH_MAX_LEAF_SIZE + 1;
    EXPECT_NE(failure(options).find("2 buildBvh: maxLeafSize"), std::string::npos);
    options = {};
    options.binCount = 1;
    EXPECT_NE(failure(options).find("2 buildBvh: binCount"), std::string::npos);
    options = {};
    options.nodeCost = 0.0f;
    EXPECT_NE(failure(options).find("2 buildBvh: nodeCost"), std::string::npos);
    options = {};
    options.maxDepth = BVH_MAX_DEPTH + 1;
    EXPECT_NE(failure(options).find("2 buildBvh: maxDepth"), std::string::npos);
}

// ---------------------------------------------------------------------------------------
// Rays
// ---------------------------------------------------------------------------------------

TEST(Bvh, TraversalWorksForEveryLeafSize) {
    TestMesh teapot = loadTeapot("teapot_552");
    ASSERT_FALSE(teapot.positions.empty()) << "teapot_552.obj: build course_assets";
    for (int leaf = 1; leaf <= BVH_MAX_LEAF_SIZE; ++leaf) {
        TreeOptions options;
        options.maxLeafSize = leaf;
        crossCheck(teapot, buildTree(teapot, options), 2000, leaf);
    }
}

// ---------------------------------------------------------------------------------------
// Helpers for the chapter
// ---------------------------------------------------------------------------------------

TEST(Bvh, StatsGoToVerboseAndJson) {
    TestMesh soup = randomSoup(500, 8);
    Bvh bvh = buildTree(soup);
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
