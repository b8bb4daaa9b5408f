// Fuzzes the .vol grid reader (common/volume_grid.cpp) through a scratch file: a
// problem is a Failure, never a crash; the header check and the reader agree; and a
// grid that reads survives a round trip through writeVolumeGrid value for value.
#include <cstdint>
#include <string>

#include "course/error.h"
#include "course/volume_grid.h"
#include "fuzz_file.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const std::string path = writeScratchFile("input.vol", data, size);
    const bool headerReads = course::volumeGridProblem(path).empty();
    course::VolumeGrid grid;
    try {
        grid = course::readVolumeGrid(path);
    } catch (const course::Failure&) {
        return 0;  // refused: fine, if the header check did not pass it
    }
    if (!headerReads) __builtin_trap();  // read a file the header check refuses
    const std::string copy = scratchFolder() + "/copy.vol";
    course::writeVolumeGrid(copy, grid);
    const course::VolumeGrid again = course::readVolumeGrid(copy);
    if (again.resolution != grid.resolution || again.boxMin != grid.boxMin ||
        again.boxMax != grid.boxMax || again.density != grid.density)
        __builtin_trap();  // what the writer writes, the reader must read back
    return 0;
}
