// Chapter 21's tree "priced as it runs" (book/docs/chapters/21_tree_price.md): a leaf costs
// all BVH_MAX_LEAF_SIZE triangle tests the traversal writes out, L = 4 triangleCost,
// whatever it holds, and a range of up to four triangles is split only if
//     nodeCost * A + L * (A_left + A_right) < L * A,
// its two children each a leaf. Above four triangles the split planes are chapter 14's
// (BvhOptions::leavesByCount = true builds that tree). Built for every tree whose bvh.h
// has leavesByCount (bvh_tests.cmake); its SAH tests are in test_bvh_sah.cpp.
#include <gtest/gtest.h>

#include <algorithm>
#include <functional>
#include <iostream>

#include "bvh_tree_checks.h"

using namespace bvh_test;

namespace {

TreeOptions writtenOut() {
    TreeOptions options;
    options.leavesByCount = false;
    return options;
}
TreeOptions byCount() {
    TreeOptions options;
    options.leavesByCount = true;
    return options;
}

// The slot that holds the whole mesh: node 0, or the lone leaf it wraps.
Slot wholeMesh(const Bvh& bvh) {
    const gpu::BvhNode& root = bvh.nodes.at(0);
    if (rightSlot(root).box.empty()) return leftSlot(root);
    Box3 box = leftSlot(root).box;
    box.grow(rightSlot(root).box);
    return {box, 0, 0};
}

std::vector<uint32_t> sorted(std::vector<uint32_t> triangles) {
    std::sort(triangles.begin(), triangles.end());
    return triangles;
}

// Walks the tree priced as written out (`priced`) and chapter 14's (`counted`) side by
// side, from the same mesh with the same options but the leaf price.
class SideBySide {
public:
    SideBySide(const Bvh& priced, const Bvh& counted, const TreeOptions& options)
        : priced_(priced), counted_(counted), options_(options) {}

    void walk() { visit(wholeMesh(priced_), wholeMesh(counted_)); }

    size_t keptWhole = 0;  // ranges chapter 14 splits and the priced tree keeps a leaf
    size_t smallSplits = 0;  // ranges of up to four the priced tree splits too

private:
    // Where the priced rule says a range of up to four triangles, box `box`, should be
    // split into children with boxes `left` and `right`.
    bool pricedSplit(const Box3& box, const Box3& left, const Box3& right) const {
        const double leafPrice = options_.triangleCost * double(BVH_MAX_LEAF_SIZE);
        return options_.nodeCost * box.halfArea() +
                   leafPrice * (left.halfArea() + right.halfArea()) <
               leafPrice * box.halfArea();
    }

    void visit(const Slot& priced, const Slot& counted) {
        // The same range of triangles, in the same box: the same split planes above.
        const std::vector<uint32_t> triangles = sorted(trianglesUnder(priced_, priced));
        ASSERT_EQ(triangles, sorted(trianglesUnder(counted_, counted)));
        ASSERT_TRUE(priced.box == counted.box);
        const size_t count = triangles.size();
        if (priced.isLeaf()) {
            ASSERT_LE(count, size_t(options_.maxLeafSize));
            if (counted.isLeaf()) return;
            // Chapter 14 splits it: the priced rule must say a leaf is no dearer.
            const gpu::BvhNode& node = counted_.nodes.at(counted.index);
            EXPECT_FALSE(pricedSplit(priced.box, leftSlot(node).box, rightSlot(node).box))
                << "a range of " << count << " kept whole though two leaves cost less";
            ++keptWhole;
            return;
        }
        // An inner node of the priced tree: chapter 14 splits there too, the same way.
        ASSERT_FALSE(counted.isLeaf()) << "the priced tree splits a range of " << count
                                       << " that chapter 14 keeps a leaf";
        const gpu::BvhNode& node = priced_.nodes.at(priced.index);
        const gpu::BvhNode& countedNode = counted_.nodes.at(counted.index);
        if (count <= size_t(options_.maxLeafSize)) {
            // It could have been a leaf: the priced rule must say two leaves cost less.
            EXPECT_TRUE(pricedSplit(priced.box, leftSlot(node).box, rightSlot(node).box))
                << "a range of " << count << " split though one leaf costs no more";
            ++smallSplits;
        }
        visit(leftSlot(node), leftSlot(countedNode));
        visit(rightSlot(node), rightSlot(countedNode));
    }

    const Bvh &priced_, &counted_;
    const TreeOptions options_;
};

// The SAH cost of a tree, every leaf priced as written out: BVH_MAX_LEAF_SIZE tests.
double costAsItRuns(const Bvh& bvh, const TreeOptions& options) {
    double sum = 0.0;
    std::function<void(uint32_t, const Box3&)> node = [&](uint32_t index, const Box3& box) {
        sum += options.nodeCost * box.halfArea();
        for (const Slot& slot : {leftSlot(bvh.nodes[index]), rightSlot(bvh.nodes[index])}) {
            if (slot.box.empty()) continue;
            if (slot.isLeaf())
                sum += options.triangleCost * BVH_MAX_LEAF_SIZE * slot.box.halfArea();
            else
                node(slot.index, slot.box);
        }
    };
    const Box3 root = wholeMesh(bvh).box;
    node(0, root);
    return sum / root.halfArea();
}

}  // namespace

// ---------------------------------------------------------------------------------------
// The pricing decision, on cases worked out by hand
// ---------------------------------------------------------------------------------------

// Two triangles: boxes of half area 1 each, 2 + gap around both (test_bvh_sah.cpp has
// the same pair priced by count). Priced as written out, split when
// nodeCost * A + 4 triangleCost * 2 < 4 triangleCost * A.
TEST(PricedLeaves, APairIsSplitExactlyWhenTwoLeavesCostLessThanOne) {
    struct Case {
        float gap, nodeCost, triangleCost;
        bool leavesByCount, split;
        double sahCost;  // of the tree, per unit of the root's area
    } cases[] = {
        // A = 4: 4 nodeCost + 8 < 16, nodeCost < 2.
        {2.0f, 1.0f, 1.0f, false, true, (4.0 + 4.0 + 4.0) / 4.0},
        {2.0f, 1.9921875f, 1.0f, false, true, (4.0 * 1.9921875 + 4.0 + 4.0) / 4.0},
        {2.0f, 2.0f, 1.0f, false, false, (4.0 * 2.0 + 4.0 * 4.0) / 4.0},  // a tie: a leaf
        {2.0f, 1.0f, 0.5f, false, false, (4.0 + 0.5 * 4.0 * 4.0) / 4.0},  // the same ratio
        // A = 2.5: 2.5 + 8 < 10 is false, so one leaf; priced by count, chapter 14's
        // 2.5 + 2 < 5 splits it.
        {0.5f, 1.0f, 1.0f, false, false, (2.5 + 4.0 * 2.5) / 2.5},
        {0.5f, 1.0f, 1.0f, true, true, (2.5 + 1.0 + 1.0) / 2.5},
        // A = 3: 3 + 8 < 12 splits, just.
        {1.0f, 1.0f, 1.0f, false, true, (3.0 + 4.0 + 4.0) / 3.0},
    };
    for (const Case& c : cases) {
        TreeOptions options;
        options.nodeCost = c.nodeCost;
        options.triangleCost = c.triangleCost;
        options.leavesByCount = c.leavesByCount;
        TestMesh pair = twoTrianglesApart(c.gap);
        SCOPED_TRACE(pair.name + ", node cost " + std::to_string(c.nodeCost) +
                     ", triangle cost " + std::to_string(c.triangleCost) +
                     (c.leavesByCount ? ", by count" : ", as written out"));
        Bvh bvh = buildTree(pair, options);
        ASSERT_EQ(bvh.nodes.size(), 1u);
        EXPECT_EQ(bvh.nodes[0].leftCount, c.split ? 1u : 2u);
        EXPECT_EQ(bvh.nodes[0].rightCount, c.split ? 1u : 0u);
        EXPECT_DOUBLE_EQ(bvh.stats.sahCost, c.sahCost);
        TreeChecker(bvh, pair, options).check();
    }
}

// One triangle: a node and a leaf over the same box, 1 + 4 = 5 as written out, 1 + 1
// by count. Two copies of one triangle (nothing separates them): 1 + 4 and 1 + 2.
TEST(PricedLeaves, ALeafCostsFourTestsWhateverItHolds) {
    TestMesh one{"one"}, two{"two"};
    one.add({0, 0, 0}, {1, 0, 0}, {0, 1, 0});
    two = one;
    two.add({0, 0, 0}, {1, 0, 0}, {0, 1, 0});
    EXPECT_DOUBLE_EQ(buildTree(one, writtenOut()).stats.sahCost, 5.0);
    EXPECT_DOUBLE_EQ(buildTree(one, byCount()).stats.sahCost, 2.0);
    EXPECT_DOUBLE_EQ(buildTree(two, writtenOut()).stats.sahCost, 5.0);
    EXPECT_DOUBLE_EQ(buildTree(two, byCount()).stats.sahCost, 3.0);
}

// Two unit squares side by side, two triangles each: box 2, each square's box 1, each
// triangle's box its square. By count, chapter 14 splits the four into the squares
// (2 + 2 * 1 + 2 * 1 < 4 * 2) and keeps each square a leaf (1 + 1 + 1 < 2 * 1 fails).
// Priced as written out, the four stay one leaf (2 + 4 * (1 + 1) < 4 * 2 fails):
// neighbouring triangles' boxes cover about as much as the box around them.
TEST(PricedLeaves, NeighbouringTrianglesStayOneLeaf) {
    TestMesh squares{"two_squares"};
    for (float x : {0.0f, 1.0f}) {
        glm::vec3 a(x, 0, 0), b(x + 1, 0, 0), c(x + 1, 1, 0), d(x, 1, 0);
        squares.add(a, b, c);
        squares.add(a, c, d);
    }
    Bvh priced = buildTree(squares, writtenOut());
    ASSERT_EQ(priced.nodes.size(), 1u);
    EXPECT_EQ(priced.nodes[0].leftCount, 4u);
    EXPECT_EQ(priced.nodes[0].rightCount, 0u);
    EXPECT_DOUBLE_EQ(priced.stats.sahCost, (2.0 + 4.0 * 2.0) / 2.0);
    Bvh counted = buildTree(squares, byCount());
    ASSERT_EQ(counted.nodes.size(), 1u);
    EXPECT_EQ(counted.nodes[0].leftCount, 2u);
    EXPECT_EQ(counted.nodes[0].rightCount, 2u);
    EXPECT_DOUBLE_EQ(counted.stats.sahCost, (2.0 + 2.0 * 1.0 + 2.0 * 1.0) / 2.0);
    // Priced as it runs, chapter 14's tree would cost (2 + 4 + 4) / 2 = 5 as well: the
    // node buys nothing, and the priced tree does without it.
    EXPECT_DOUBLE_EQ(costAsItRuns(counted, writtenOut()), 5.0);
}

// ---------------------------------------------------------------------------------------
// The whole tree: chapter 14's, with the small ranges the price says to keep whole
// ---------------------------------------------------------------------------------------

// Above four triangles nothing changes: the priced tree has chapter 14's nodes there,
// split the same way. At four or fewer it is a leaf exactly where the priced rule says
// one costs no more than two, and never splits where chapter 14 keeps a leaf (with the
// default prices, a split the priced rule takes is cheaper by count too: nodeCost <= 4/3).
TEST(PricedLeaves, ThePricedTreeIsChapter14sWithSmallRangesKeptWhole) {
    TestMesh teapot552 = loadTeapot("teapot_552"), teapot = loadTeapot("teapot_6320");
    ASSERT_FALSE(teapot552.positions.empty() || teapot.positions.empty())
        << "the teapots: build course_assets";
    for (const TestMesh& mesh :
         {teapot552, teapot, randomSoup(1000, 7), randomSoup(17, 17), randomSoup(3, 3),
          flatGrid(30), zeroAreaTriangles(999, 4), identicalTriangles(100)}) {
        SCOPED_TRACE(mesh.name);
        Bvh priced = buildTree(mesh, writtenOut()), counted = buildTree(mesh, byCount());
        ASSERT_EQ(priced.stats.depthLimitedSplits + counted.stats.depthLimitedSplits, 0u);
        SideBySide sides(priced, counted, writtenOut());
        sides.walk();
        EXPECT_LE(priced.nodes.size(), counted.nodes.size());
        EXPECT_LE(priced.stats.maxDepth, counted.stats.maxDepth);
        std::cout << mesh.name << ": " << counted.nodes.size() << " nodes by count, "
                  << priced.nodes.size() << " priced as written out; " << sides.keptWhole
                  << " small ranges kept whole, " << sides.smallSplits << " split\n";
        if (mesh.name == teapot.name) {
            EXPECT_GT(sides.keptWhole, 500u);
            EXPECT_GT(sides.smallSplits, 0u) << "the rule's other side, exercised";
        }
    }
}

// What the page promises for the teapot: fewer than 0.7 times the nodes of chapter 14's
// tree, more than three triangles in a leaf on average, and cheaper as the traversal
// runs it (chapter 14's tree priced so too).
TEST(PricedLeaves, TheTeapotsTreeHasFewerNodesFullerLeavesAndCostsLessAsItRuns) {
    TestMesh teapot = loadTeapot("teapot_6320");
    ASSERT_FALSE(teapot.positions.empty()) << "teapot_6320.obj: build course_assets";
    Bvh priced = buildTree(teapot, writtenOut()), counted = buildTree(teapot, byCount());
    std::cout << "priced as written out: " << describeBvh(priced.stats) << "\nby count: "
              << describeBvh(counted.stats) << "\n";
    EXPECT_LT(priced.stats.nodeCount, 0.7 * counted.stats.nodeCount);
    EXPECT_GT(6320.0 / priced.stats.leafCount, 3.0);
    EXPECT_NEAR(costAsItRuns(priced, writtenOut()), priced.stats.sahCost,
                1e-9 * priced.stats.sahCost);
    EXPECT_LT(priced.stats.sahCost, costAsItRuns(counted, writtenOut()));
}
