#include "course/volume_grid.h"

#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>

#include "course/error.h"
#include "course/image_file.h"

namespace course {
namespace {

constexpr size_t kHeaderBytes = 48;
// 512^3 densities (512 MiB): beyond that, a grid is not a course's scene.
constexpr long long kMostValues = 512LL * 512 * 512;

struct Header {
    glm::ivec3 resolution{0};
    int channels = 0;
    glm::vec3 boxMin{0.0f}, boxMax{0.0f};
};

template <typename T>
T readAt(const char* bytes, size_t offset) {
    T value;
    std::memcpy(&value, bytes + offset, sizeof value);  // the file is little-endian, as x86
    return value;
}

// The header's problem, or "": `fileBytes` is the file's size.
std::string headerProblem(const char* bytes, size_t fileBytes, Header& header) {
    if (fileBytes < kHeaderBytes) return "shorter than a .vol header (48 bytes)";
    if (std::memcmp(bytes, "VOL", 3) != 0) return "not a .vol grid (no 'VOL' at its start)";
    if (bytes[3] != 3) return "a .vol grid of version " + std::to_string(int(bytes[3])) +
                              ", not 3";
    const int32_t encoding = readAt<int32_t>(bytes, 4);
    if (encoding != 1)
        return "encoded as " + std::to_string(encoding) + ", not 1 (float32)";
    for (int axis = 0; axis < 3; ++axis)
        header.resolution[axis] = readAt<int32_t>(bytes, 8 + 4 * size_t(axis));
    header.channels = readAt<int32_t>(bytes, 20);
    for (int axis = 0; axis < 3; ++axis) {
        header.boxMin[axis] = readAt<float>(bytes, 24 + 4 * size_t(axis));
        header.boxMax[axis] = readAt<float>(bytes, 36 + 4 * size_t(axis));
    }
    if (header.channels != 1)
        return std::to_string(header.channels) + " channels, not 1 (a density)";
    long long values = 1;
    for (int axis = 0; axis < 3; ++axis) {
        if (header.resolution[axis] < 1)
            return "a resolution of " + std::to_string(header.resolution[axis]) + " along " +
                   "xyz"[axis];
        values *= header.resolution[axis];
        if (values > kMostValues) return "more than 512^3 values";
        if (!std::isfinite(header.boxMin[axis]) || !std::isfinite(header.boxMax[axis]) ||
            !(header.boxMax[axis] > header.boxMin[axis]))
            return std::string("a bounding box without size along ") + "xyz"[axis];
    }
    const size_t expected = kHeaderBytes + size_t(values) * 4;
    if (fileBytes != expected)
        return std::to_string(fileBytes) + " bytes, where its header promises " +
               std::to_string(expected);
    return "";
}

std::string readWhole(const std::string& path, std::string& problem) {
    std::ifstream file(path, std::ios::binary | std::ios::ate);
    if (!file) {
        problem = "not readable";
        return {};
    }
    const std::streamoff size = file.tellg();
    if (size > std::streamoff(kHeaderBytes + kMostValues * 4)) {
        problem = "more than 512^3 values";
        return {};
    }
    std::string bytes(size_t(size), '\0');
    file.seekg(0);
    file.read(bytes.data(), size);
    return bytes;
}

}  // namespace

std::string volumeGridProblem(const std::string& path) {
    std::string problem;
    const std::string bytes = readWhole(path, problem);
    if (!problem.empty()) return problem;
    Header header;
    return headerProblem(bytes.data(), bytes.size(), header);
}

VolumeGrid readVolumeGrid(const std::string& path) {
    std::string problem;
    const std::string bytes = readWhole(path, problem);
    Header header;
    if (problem.empty()) problem = headerProblem(bytes.data(), bytes.size(), header);
    if (!problem.empty()) fail(ExitCode::BadInput, path + ": " + problem);
    VolumeGrid grid;
    grid.resolution = header.resolution;
    grid.boxMin = header.boxMin;
    grid.boxMax = header.boxMax;
    grid.density.resize(size_t(header.resolution.x) * header.resolution.y * header.resolution.z);
    std::memcpy(grid.density.data(), bytes.data() + kHeaderBytes, grid.density.size() * 4);
    for (size_t i = 0; i < grid.density.size(); ++i)
        if (!std::isfinite(grid.density[i]) || grid.density[i] < 0.0f)
            fail(ExitCode::BadInput, path + ": density " + std::to_string(i) +
                                         " is negative or not a number");
    return grid;
}

void writeVolumeGrid(const std::string& path, const VolumeGrid& grid) {
    std::string bytes(kHeaderBytes, '\0');
    std::memcpy(bytes.data(), "VOL\3", 4);
    const int32_t ints[5] = {1, grid.resolution.x, grid.resolution.y, grid.resolution.z, 1};
    std::memcpy(bytes.data() + 4, ints, sizeof ints);
    const float box[6] = {grid.boxMin.x, grid.boxMin.y, grid.boxMin.z,
                          grid.boxMax.x, grid.boxMax.y, grid.boxMax.z};
    std::memcpy(bytes.data() + 24, box, sizeof box);
    bytes.append(reinterpret_cast<const char*>(grid.density.data()), grid.density.size() * 4);
    writeFileAtomically(path, bytes);
}

}  // namespace course
