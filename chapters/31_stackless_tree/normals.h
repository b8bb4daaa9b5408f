// Normals at the vertices, for meshes whose file has none: each vertex gets the average
// of the normals of the triangles around it, weighted by their areas.
#pragma once
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

// One unit normal per position. `corners` holds 3 position indices per triangle; a
// triangle's normal points to the side from which its corners run counter-clockwise.
// A vertex in no triangle, or whose triangles' normals cancel, gets (0, 0, 0).
std::vector<glm::vec3> areaWeightedNormals(const std::vector<glm::vec3>& positions,
                                           const std::vector<uint32_t>& corners);
