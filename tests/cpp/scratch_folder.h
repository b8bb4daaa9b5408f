// An empty folder of the running test's own under the system's temporary folder, named
// by `prefix` and the test's name (so tests run in parallel do not share one).
#pragma once
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

inline std::filesystem::path scratchFolder(const std::string& prefix) {
    std::filesystem::path folder =
        std::filesystem::temp_directory_path() /
        (prefix + ::testing::UnitTest::GetInstance()->current_test_info()->name());
    std::filesystem::remove_all(folder);
    std::filesystem::create_directories(folder);
    return folder;
}
