// Objects placed many times (chapter 26). Each object's shapes are packed once, in its
// own space, after the world's, under a tree of their own; each instance is a few words
// (gpu::Instance: the map from the world to its object, and where the object is); and
// a tree over the instances' world boxes, the top level, joins the world's and the
// objects' trees in the one node array the walk reads (bvh_traversal.glsl).
#pragma once
#include <cstddef>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "course/scene_file.h"
#include "course/stats.h"

struct GpuScene;

// What was built, for --verbose, --json and the book.
struct InstanceStats {
    size_t objects = 0, instances = 0, objectNodes = 0, instanceNodes = 0;
    size_t objectTriangles = 0;  // each object's once, however often it is placed
    size_t placedTriangles = 0;  // what the instances show: as many written out
    double instanceTreeMilliseconds = 0.0;  // the top level: rebuilt when instances move
    size_t memoryBytes = 0;  // the objects' triangles and trees, the instances and theirs
};

// Adds the scene's objects and instances to `gpu`, whose world triangles are packed and
// under their tree already; grows the box [low, high] by the instances' world boxes.
void addInstances(GpuScene& gpu, const course::SceneFile& scene, glm::vec3& low,
                  glm::vec3& high);

// One line for --verbose: "instances: 100 of 1 object (6320 triangles once, 632000
// placed), trees 3147 + 199 nodes, 0.4 MiB, top level built in 0.1 ms".
std::string describeInstances(const InstanceStats& stats);
// The stats as --json fields: objects, instances, object_triangles, placed_triangles,
// instance_tree_ms, instance_bytes.
void recordInstanceStats(const InstanceStats& stats, course::Stats& json);
