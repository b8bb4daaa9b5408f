// Density grids in Mitsuba's `.vol` format, so that one file renders in the course and
// in Mitsuba 3 (its `gridvolume`). Little-endian, a 48-byte header, then the values:
//
//   bytes  0-2   'V' 'O' 'L'          bytes 3       version, 3
//   int32        encoding, 1: float32  int32 x3      resolution X, Y, Z (each >= 1)
//   int32        channels (1 here: a density)
//   float32 x6   the bounding box: min X Y Z, max X Y Z (world units; max > min)
//   float32 ...  X * Y * Z * channels values, x fastest: ((z * Y + y) * X + x) * C + c
//
// The values sit at the centres of the X * Y * Z cells that divide the box (Mitsuba
// 3's convention): value (x, y, z) at min + (x + 0.5, y + 0.5, z + 0.5) * size / res.
#pragma once
#include <string>
#include <vector>

#include <glm/glm.hpp>

namespace course {

struct VolumeGrid {
    glm::ivec3 resolution{0};
    glm::vec3 boxMin{0.0f}, boxMax{0.0f};
    std::vector<float> density;  // resolution.x * y * z values, x fastest; each >= 0

    float at(int x, int y, int z) const {
        return density[(size_t(z) * resolution.y + y) * resolution.x + x];
    }
};

// Reads and checks a grid: one channel of finite float32 densities >= 0. A problem
// throws Failure(BadInput) naming the file.
VolumeGrid readVolumeGrid(const std::string& path);

// What is wrong with the file's header and size, or "" when it reads (for the scene
// reader, which checks a grid file at its line before any program loads it).
std::string volumeGridProblem(const std::string& path);

// The grid as a .vol file (the build's procedural smoke, tests).
void writeVolumeGrid(const std::string& path, const VolumeGrid& grid);

}  // namespace course
