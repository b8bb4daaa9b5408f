// Objects placed many times (chapter 26). Each object's shapes are packed once, in its
// own space, after the world's, under a tree of their own; each instance is a few words
// (gpu::Instance: the map from the world to its object, and where the object is); and
// a tree over the instances' world boxes, the top level, joins the world's and the
// objects' trees in the one node array the walk reads (bvh_traversal.glsl).
#pragma once
#include <cstddef>
#include <string>
#include <utility>

#include <glm/glm.hpp>

#include "course/scene_file.h"
#include "course/stats.h"
#include "shared.h"

struct GpuScene;

// What was built, for --verbose, --json and the book.
struct InstanceStats {
    size_t objects = 0, instances = 0, objectNodes = 0, instanceNodes = 0;
    size_t objectTriangles = 0, placedTriangles = 0;  // kept once; shown by the instances
    double instanceTreeMilliseconds = 0.0;  // the top level: rebuilt when instances move
    size_t memoryBytes = 0;  // the objects' triangles and trees, the instances and theirs
};

// Where an object was packed: its tree's root and its spheres (the map is each
// instance's), its triangles' run and tree's nodes, and its box in its own space.
struct PackedObject {
    gpu::Instance where{};
    size_t firstTriangle = 0, triangleCount = 0, firstNode = 0, nodeCount = 0;
    size_t firstPosition = 0, positionCount = 0, firstNormal = 0, normalCount = 0;
    glm::vec3 low{0.0f}, high{0.0f};
};

// Adds the scene's objects and instances to `gpu`, whose world triangles are packed and
// under their tree already; grows the box [low, high] by the instances' world boxes.
void addInstances(GpuScene& gpu, const course::SceneFile& scene, glm::vec3& low,
                  glm::vec3& high);

// A blurred picture sees each instance over the whole shutter interval; a still, at
// one instant of it (0: the shutter opens, 1: it closes).
constexpr float kWholeShutter = -1.0f;

// The instances' table and the top level over their boxes, built again for `instant`
// (or kWholeShutter: each box swept over the interval, and each instance's motion in
// the table for the walk). Returns the instances' box in the world.
std::pair<glm::vec3, glm::vec3> placeInstances(GpuScene& gpu, const course::SceneFile& scene,
                                               float instant);

// One line for --verbose, and the stats as --json fields (objects, instances,
// object_triangles, placed_triangles, instance_tree_ms, instance_bytes).
std::string describeInstances(const InstanceStats& stats);
void recordInstanceStats(const InstanceStats& stats, course::Stats& json);

// What the walk reads of the instances (PathParameters). --brute-force tests the world's
// own triangles one by one: with instances, it is exit code 2.
void setInstanceParameters(const GpuScene& gpu, bool bruteForce, gpu::PathParameters& p);
