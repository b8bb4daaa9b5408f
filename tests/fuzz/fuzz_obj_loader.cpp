// Fuzzes the chapters' OBJ loader (chapter 08's, which reads normals as well as chapter
// 07's positions and faces): any bytes must give a mesh or a clean Failure.
#include "course/error.h"
#include "fuzz_file.h"
#include "obj_loader.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    std::string path = writeScratchFile("input.obj", data, size);
    try {
        Mesh mesh = loadObj(path);
        // A mesh that loads must be consistent: every index inside its array.
        for (uint32_t index : mesh.positionIndices)
            if (index >= mesh.positions.size()) __builtin_trap();
        for (uint32_t index : mesh.normalIndices)
            if (index >= mesh.normals.size()) __builtin_trap();
    } catch (const course::Failure&) {
    }
    return 0;
}
