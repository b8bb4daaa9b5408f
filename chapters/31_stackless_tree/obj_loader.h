// A small, strict reader for Wavefront OBJ meshes: positions, normals, texture
// coordinates and triangles.
// No GL here: the chapter uploads what this returns into storage buffers.
#pragma once
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include <glm/glm.hpp>

// --8<-- [start:mesh]
// A triangle mesh as the GPU wants it: flat arrays, 3 indices per triangle.
struct Mesh {
    std::vector<glm::vec3> positions;  // from `v` lines
    std::vector<glm::vec3> normals;    // from `vn` lines (may be empty)
    std::vector<glm::vec2> texcoords;  // from `vt` lines: (u, v), v = 0 the image's bottom
    // One entry per triangle corner, 3 per triangle, 0-based:
    std::vector<uint32_t> positionIndices;
    std::vector<uint32_t> normalIndices;    // empty when any face lacks normals
    std::vector<uint32_t> texcoordIndices;  // empty when any face lacks texture coordinates

    size_t triangleCount() const { return positionIndices.size() / 3; }
};
// --8<-- [end:mesh]

// Reads an OBJ file. Polygons are fan-triangulated: corners (0, i, i + 1).
// Any problem throws course::Failure(ExitCode::BadInput, "file:line: what is wrong"),
// with the file's absolute path; line 0 means the file as a whole (empty, no faces).
Mesh loadObj(const std::string& path);
