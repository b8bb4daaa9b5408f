#include "bvh.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>

#include "course/error.h"
#include "course/stats.h"

namespace {

using glm::vec3;

// --8<-- [start:box]
// An axis-aligned box. A new box is empty, min > max, so that growing it by anything
// gives exactly that thing; an empty box is also what the GPU misses (bvh_layout.h).
struct Box {
    vec3 min{std::numeric_limits<float>::max()};
    vec3 max{-std::numeric_limits<float>::max()};

    void grow(const vec3& point) {
        min = glm::min(min, point);
        max = glm::max(max, point);
    }
    void grow(const Box& box) {
        min = glm::min(min, box.min);
        max = glm::max(max, box.max);
    }
    // Half the surface area. The SAH only compares areas, so the factor 2 is left out.
    // In double: a box that spans the float range would overflow float's squares.
    double halfArea() const {
        if (min.x > max.x) return 0.0;
        glm::dvec3 size = glm::dvec3(max) - glm::dvec3(min);
        return size.x * size.y + size.y * size.z + size.z * size.x;
    }
};
// --8<-- [end:box]

// One triangle while the tree is built: its box and its index in the input. The
// builder sorts these records, not the triangles: 28 bytes each, read in order.
struct TriangleRecord {
    Box box;
    uint32_t triangle;
    // The centre of the box stands for the triangle when splitting. (Each half first:
    // min + max could overflow where min / 2 + max / 2 cannot.)
    vec3 centroid() const { return box.min * 0.5f + box.max * 0.5f; }
};

// What a child slot of a node holds: the child's box and where it is (bvh_layout.h).
struct Child {
    Box box;
    uint32_t index = 0;  // a node, or the first triangle of a leaf
    uint32_t count = 0;  // 0: a node; otherwise a leaf of `count` triangles
};

// How many node levels a range of n triangles needs below its slot when every split
// halves it: 0 if it fits in a leaf. A subtree built that way is as shallow as can be.
int halvingDepth(size_t n, size_t maxLeafSize) {
    int depth = 0;
    for (; n > maxLeafSize; n = (n + 1) / 2) ++depth;
    return depth;
}

// --8<-- [start:median]
// The triangles whose centroids are the lower half along the centroids' longest axis
// go left: both children get half (ties broken by input index, so it is deterministic).
// nth_element puts the middle record where a sort would, the smaller ones before it and
// the larger after, in time proportional to the range: no full sort is needed. Chapter
// 13's only split; here the depth guard's (Builder::build, step 3).
uint32_t medianSplit(std::vector<TriangleRecord>& records, uint32_t begin, uint32_t end,
                     const Box& centroids) {
    const vec3 extent = centroids.max - centroids.min;
    int axis = 0;
    for (int a = 1; a < 3; ++a)
        if (extent[a] > extent[axis]) axis = a;
    const uint32_t middle = begin + (end - begin) / 2;
    std::nth_element(records.begin() + begin, records.begin() + middle,
                     records.begin() + end,
                     [axis](const TriangleRecord& a, const TriangleRecord& b) {
                         float ca = a.centroid()[axis], cb = b.centroid()[axis];
                         return ca < cb || (ca == cb && a.triangle < b.triangle);
                     });
    return middle;
}
// --8<-- [end:median]

// --8<-- [start:binning]
// Which of `count` equal bins along [min, min + extent] a centroid coordinate falls in.
// The same function sorts triangles into bins and then into the two children, so the
// two always agree, whatever the rounding.
struct Bins {
    float min = 0.0f, scale = 0.0f;
    int count = 0;
    int of(float coordinate) const {
        int bin = int((coordinate - min) * scale);
        return std::clamp(bin, 0, count - 1);
    }
};
// --8<-- [end:binning]

// The best split the SAH found for a range: triangles whose centroid falls in bins
// 0 ... lastLeftBin along `axis` go left.
struct Split {
    bool found = false;
    int axis = 0;
    Bins bins;
    int lastLeftBin = 0;
    double cost = 0.0;  // nodeCost * area + triangleCost * (leftArea * nLeft + ...)
    double childAreas = 0.0;  // leftArea + rightArea
};

class Builder {
public:
    Builder(const BvhOptions& options, std::vector<TriangleRecord>& records, Bvh& bvh)
        : options_(options), records_(records), bvh_(bvh) {
        binBoxes_.resize(3 * options.binCount);  // binCount per axis
        binCounts_.resize(3 * options.binCount);
        rightAreas_.resize(options.binCount);
    }

    // Builds the subtree of records [begin, end) and returns the child slot that points
    // at it. `depth`: the node fetches that reach this slot (0 for the whole mesh).
    Child build(uint32_t begin, uint32_t end, int depth);

    double sahSum = 0.0;  // sum of cost * area over nodes and leaves

private:
    Split findSahSplit(uint32_t begin, uint32_t end, const Box& box,
                       const Box& centroids);
    uint32_t partition(uint32_t begin, uint32_t end, const Split& split);
    Child leaf(uint32_t begin, uint32_t end, const Box& box, int depth);
    double leafTests(uint32_t count) const;
    bool cheaperToSplit(const Split& split, uint32_t count, const Box& box) const;

    const BvhOptions& options_;
    std::vector<TriangleRecord>& records_;
    Bvh& bvh_;
    // Scratch for the binning, allocated once.
    std::vector<Box> binBoxes_;
    std::vector<uint32_t> binCounts_;
    std::vector<double> rightAreas_;
};

// --8<-- [start:build]
Child Builder::build(uint32_t begin, uint32_t end, int depth) {
    const uint32_t count = end - begin;
    Box box, centroids;  // of the triangles, and of their centroids
    for (uint32_t i = begin; i < end; ++i) {
        box.grow(records_[i].box);
        centroids.grow(records_[i].centroid());
    }

    // 1. A leaf, if the range is small enough and the SAH says testing its triangles
    //    is cheaper than a node and two children (or the depth is used up).
    if (count == 1) return leaf(begin, end, box, depth);
    Split split = findSahSplit(begin, end, box, centroids);
    if (count <= uint32_t(options_.maxLeafSize) &&
        (!cheaperToSplit(split, count, box) || depth >= options_.maxDepth))
        return leaf(begin, end, box, depth);

    // 2. Otherwise split where the SAH says. When all centroids are one point no plane
    //    separates them: any two halves are as good, so halve the list.
    uint32_t middle = split.found ? partition(begin, end, split) : begin + count / 2;

    // 3. Keep the tree within maxDepth: if a child would need deeper leaves than are
    //    left, split at the median instead, which halves the range (never for teapots).
    const size_t bigger = std::max(middle - begin, end - middle);
    if (depth + 1 + halvingDepth(bigger, options_.maxLeafSize) > options_.maxDepth) {
        middle = medianSplit(records_, begin, end, centroids);
        ++bvh_.stats.depthLimitedSplits;
    }

    // 4. The node goes into the array before its children: depth first, root at 0.
    const uint32_t nodeIndex = uint32_t(bvh_.nodes.size());
    bvh_.nodes.emplace_back();
    Child left = build(begin, middle, depth + 1);
    Child right = build(middle, end, depth + 1);
    bvh_.nodes[nodeIndex] = {left.box.min,  left.index,  left.box.max,  left.count,
                             right.box.min, right.index, right.box.max, right.count};
    sahSum += options_.nodeCost * box.halfArea();
    return {box, nodeIndex, 0};
}
// --8<-- [end:build]

Child Builder::leaf(uint32_t begin, uint32_t end, const Box& box, int depth) {
    const uint32_t count = end - begin;
    BvhStats& stats = bvh_.stats;
    ++stats.leafCount;
    stats.maxDepth = std::max(stats.maxDepth, depth);
    stats.maxLeafSize = std::max(stats.maxLeafSize, int(count));
    sahSum += options_.triangleCost * leafTests(count) * box.halfArea();
    return {box, begin, count};  // the records' order is the leaf order
}

// --8<-- [start:leaf_price]
// The triangle tests a ray pays on entering a leaf of `count` triangles: those it holds
// (chapter 14), or all that the traversal writes out (BvhOptions::leavesByCount).
double Builder::leafTests(uint32_t count) const {
    return options_.leavesByCount ? double(count) : double(BVH_MAX_LEAF_SIZE);
}

// Is splitting a range that could be one leaf cheaper than that leaf? Its children would
// be leaves too; the SAH's split cost prices them by count, which is right only if
// leaves are priced so.
bool Builder::cheaperToSplit(const Split& split, uint32_t count, const Box& box) const {
    if (!split.found) return false;
    const double leafPrice = options_.triangleCost * leafTests(count);  // per unit of area
    if (options_.leavesByCount) return split.cost < leafPrice * box.halfArea();
    // Priced as written out, each child leaf costs per area what this one would.
    return options_.nodeCost * box.halfArea() + leafPrice * split.childAreas <
           leafPrice * box.halfArea();
}
// --8<-- [end:leaf_price]

// --8<-- [start:sah]
Split Builder::findSahSplit(uint32_t begin, uint32_t end, const Box& box,
                            const Box& centroids) {
    const int binCount = options_.binCount;
    const vec3 extent = centroids.max - centroids.min;
    int longest = 0;
    for (int axis = 1; axis < 3; ++axis)
        if (extent[axis] > extent[longest]) longest = axis;

    // The axes to try, and their bins. An axis across which all centroids lie in one
    // plane (or too close for float to tell apart) has nothing to split.
    Bins bins[3];
    int axes[3], axisCount = 0;
    for (int axis = 0; axis < 3; ++axis) {
        const float scale = binCount / extent[axis];
        if ((options_.allAxes || axis == longest) && extent[axis] > 0.0f &&
            std::isfinite(scale)) {
            bins[axis] = {centroids.min[axis], scale, binCount};
            axes[axisCount++] = axis;
        }
    }

    // a. Drop each triangle into its bin along each axis: a bin keeps a count and a box.
    //    (One pass for all axes: the triangles are read once.)
    std::fill(binBoxes_.begin(), binBoxes_.end(), Box{});
    std::fill(binCounts_.begin(), binCounts_.end(), 0u);
    for (uint32_t i = begin; i < end; ++i) {
        const vec3 centroid = records_[i].centroid();
        for (int a = 0; a < axisCount; ++a) {
            const int slot = axes[a] * binCount + bins[axes[a]].of(centroid[axes[a]]);
            binBoxes_[slot].grow(records_[i].box);
            ++binCounts_[slot];
        }
    }

    Split best;
    for (int a = 0; a < axisCount; ++a) {
        const int axis = axes[a];
        const Box* axisBoxes = &binBoxes_[axis * binCount];
        const uint32_t* axisCounts = &binCounts_[axis * binCount];
        // b. Sweep from the right: the area of bins b+1 ... binCount-1 together.
        Box right;
        for (int bin = binCount - 1; bin > 0; --bin) {
            right.grow(axisBoxes[bin]);
            rightAreas_[bin - 1] = right.halfArea();
        }
        // c. Sweep from the left: the plane after bin b has the left box on one side
        //    and the right box on the other. Its cost: a node, then each child's
        //    triangles, weighted by the chance a ray through the node hits the child.
        Box left;
        uint32_t leftCount = 0;
        for (int bin = 0; bin < binCount - 1; ++bin) {
            left.grow(axisBoxes[bin]);
            leftCount += axisCounts[bin];
            const uint32_t rightCount = (end - begin) - leftCount;
            if (leftCount == 0 || rightCount == 0) continue;  // not a split
            double cost = options_.nodeCost * box.halfArea() +
                          options_.triangleCost * (left.halfArea() * leftCount +
                                                   rightAreas_[bin] * rightCount);
            // Strictly cheaper only: on a tie the first candidate stays (deterministic).
            if (!best.found || cost < best.cost)
                best = {true, axis, bins[axis], bin, cost, left.halfArea() + rightAreas_[bin]};
        }
    }
    return best;
}
// --8<-- [end:sah]

uint32_t Builder::partition(uint32_t begin, uint32_t end, const Split& split) {
    auto goesLeft = [&](const TriangleRecord& record) {
        return split.bins.of(record.centroid()[split.axis]) <= split.lastLeftBin;
    };
    auto middle = std::partition(records_.begin() + begin, records_.begin() + end, goesLeft);
    uint32_t index = uint32_t(middle - records_.begin());
    // The bins said both sides have triangles; the same function decided here. Should it
    // ever disagree, halving is still a valid tree.
    if (index == begin || index == end) return begin + (end - begin) / 2;
    return index;
}

[[noreturn]] void badInput(const std::string& what) {
    course::fail(course::ExitCode::BadInput, "buildBvh: " + what);
}

void checkOptions(const BvhOptions& options) {
    auto bad = [](const std::string& what) {
        course::fail(course::ExitCode::BadUsage, "buildBvh: " + what);
    };
    if (options.maxLeafSize < 1 || options.maxLeafSize > BVH_MAX_LEAF_SIZE)
        bad("maxLeafSize " + std::to_string(options.maxLeafSize) + " is not in 1 ... " +
            std::to_string(BVH_MAX_LEAF_SIZE) + " (BVH_MAX_LEAF_SIZE)");
    if (options.binCount < 2 || options.binCount > 1024)
        bad("binCount " + std::to_string(options.binCount) + " is not in 2 ... 1024");
    if (!(options.nodeCost > 0.0f && options.triangleCost > 0.0f) ||
        !std::isfinite(options.nodeCost) || !std::isfinite(options.triangleCost))
        bad("nodeCost and triangleCost must be positive numbers");
    if (options.maxDepth < 1 || options.maxDepth > BVH_MAX_DEPTH)
        bad("maxDepth " + std::to_string(options.maxDepth) + " is not in 1 ... " +
            std::to_string(BVH_MAX_DEPTH) + " (BVH_MAX_DEPTH, the traversal's stack)");
}

}  // namespace

Bvh buildBvh(const std::vector<vec3>& positions, const std::vector<uint32_t>& triangleIndices,
             const BvhOptions& options) {
    const auto start = std::chrono::steady_clock::now();
    checkOptions(options);
    if (triangleIndices.size() % 3 != 0)
        badInput(std::to_string(triangleIndices.size()) +
                 " triangle indices: not 3 per triangle");
    const size_t triangleCount = triangleIndices.size() / 3;
    if (triangleCount >= (size_t(1) << (32 - BVH_COUNT_BITS)))
        badInput(std::to_string(triangleCount) + " triangles: more than the traversal's "
                 "stack entries hold (2^29, BVH_COUNT_BITS in bvh_layout.h)");
    if (halvingDepth(triangleCount, options.maxLeafSize) > options.maxDepth)
        badInput(std::to_string(triangleCount) + " triangles do not fit in a tree of depth " +
                 std::to_string(options.maxDepth) + " with leaves of " +
                 std::to_string(options.maxLeafSize));

    // 1. A record per triangle: its box, from its three corners.
    std::vector<TriangleRecord> records(triangleCount);
    for (size_t i = 0; i < triangleCount; ++i) {
        records[i].triangle = uint32_t(i);
        for (int corner = 0; corner < 3; ++corner) {
            const uint32_t index = triangleIndices[3 * i + corner];
            if (index >= positions.size())
                badInput("triangle " + std::to_string(i) + " corner " + std::to_string(corner) +
                         ": index " + std::to_string(index) + ", but there are only " +
                         std::to_string(positions.size()) + " positions");
            const vec3& p = positions[index];
            if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
                badInput("position " + std::to_string(index) + " (triangle " +
                         std::to_string(i) + ") is not a finite number");
            records[i].box.grow(p);
        }
    }

    // 2. The tree, depth first from the root.
    Bvh bvh;
    bvh.stats.triangleCount = triangleCount;
    bvh.nodes.reserve(triangleCount == 0 ? 1 : 2 * triangleCount / options.maxLeafSize + 1);
    Builder builder(options, records, bvh);
    Box rootBox;
    if (triangleCount == 0) {  // no triangles: a root whose two children do not exist
        bvh.nodes.push_back({Box{}.min, 0, Box{}.max, 0, Box{}.min, 0, Box{}.max, 0});
    } else {
        Child root = builder.build(0, uint32_t(triangleCount), 0);
        rootBox = root.box;
        if (root.count > 0) {
            // The whole mesh is one leaf: the root node holds it and an empty child,
            // because the traversal always starts with a node.
            bvh.nodes.push_back({root.box.min, root.index, root.box.max, root.count,
                                 Box{}.min, 0, Box{}.max, 0});
            builder.sahSum += options.nodeCost * root.box.halfArea();
            bvh.stats.maxDepth = 1;
        }
    }

    // 3. The leaf order, and the numbers.
    bvh.triangleOrder.resize(triangleCount);
    for (size_t i = 0; i < triangleCount; ++i) bvh.triangleOrder[i] = records[i].triangle;
    BvhStats& stats = bvh.stats;
    stats.nodeCount = bvh.nodes.size();
    // Every ray that crosses the root box pays the SAH cost on average. A mesh without
    // area (all on a line or a point) has no such rays; we report 0 then.
    const double rootArea = rootBox.halfArea();
    stats.sahCost = rootArea > 0.0 ? builder.sahSum / rootArea : 0.0;
    stats.memoryBytes = bvh.nodes.size() * sizeof(gpu::BvhNode) +
                        bvh.triangleOrder.size() * sizeof(uint32_t);
    stats.buildMilliseconds =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
            .count();
    return bvh;
}

std::string describeBvh(const BvhStats& stats) {
    char line[256];
    std::snprintf(line, sizeof line,
                  "BVH: %zu triangles -> %zu nodes, %zu leaves of at most %d triangles, "
                  "depth %d, SAH cost %.1f, %.1f MiB, built in %.1f ms",
                  stats.triangleCount, stats.nodeCount, stats.leafCount, stats.maxLeafSize,
                  stats.maxDepth, stats.sahCost,
                  stats.memoryBytes / (1024.0 * 1024.0), stats.buildMilliseconds);
    std::string text = line;
    if (stats.depthLimitedSplits > 0)
        text += ", " + std::to_string(stats.depthLimitedSplits) + " splits forced by depth";
    return text;
}

void recordBvhStats(const BvhStats& stats, course::Stats& json) {
    json.set("bvh_build_ms", stats.buildMilliseconds);
    json.set("bvh_nodes", double(stats.nodeCount));
    json.set("bvh_leaves", double(stats.leafCount));
    json.set("bvh_max_depth", double(stats.maxDepth));
    json.set("bvh_sah_cost", stats.sahCost);
    json.set("bvh_bytes", double(stats.memoryBytes));
}
