// The parsers read files, so each fuzz input is written to a scratch file first.
// Slower than parsing from memory, but it fuzzes exactly the code learners run.
#pragma once
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <string>

inline std::string scratchFolder() {
    static const std::string folder = [] {
        char pattern[] = "/tmp/course-fuzz-XXXXXX";
        const char* made = mkdtemp(pattern);
        return std::string(made ? made : "/tmp");
    }();
    return folder;
}

inline std::string writeScratchFile(const std::string& name, const uint8_t* data, size_t size) {
    std::string path = scratchFolder() + "/" + name;
    if (std::FILE* file = std::fopen(path.c_str(), "wb")) {
        std::fwrite(data, 1, size, file);
        std::fclose(file);
    }
    return path;
}
