// Objects that change shape (chapter 27): a twist for the animation, and the object's
// tree kept up with it. Rebuilding a tree costs a build a frame; refitting keeps its
// shape and grows each box again around what it holds, from the leaves up, in one pass.
// But the tree was split for the old shape: as the shape drifts from it, boxes overlap
// more and its SAH cost grows, which a rebuild would bring back down.
#pragma once
#include <cstddef>
#include <vector>

#include <glm/glm.hpp>

#include "gpu_scene.h"

// The objects' corners and normals as they were packed: each frame twists them afresh.
struct RestPose {
    std::vector<glm::vec4> positions, normals;
};

// Twists each object about the upright line through the middle of its box: by
// `degrees` at the top of the box, by none at its bottom, evenly in between. A corner's
// normal turns with it (the twist's slight shear of the normals is left out).
void twistObjects(GpuScene& gpu, const RestPose& rest, float degrees);

// Grows every box of the object's tree again around what it holds now.
void refitTree(GpuScene& gpu, const PackedObject& object);

// The tree's SAH cost, as BvhStats::sahCost counts it for a tree just built: nodes and
// leaves priced by their boxes' areas relative to the root's.
double treeSahCost(const std::vector<gpu::BvhNode>& nodes, size_t firstNode, size_t nodeCount);
