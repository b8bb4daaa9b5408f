// Image files: PFM bytes and orientation, PNG sRGB encoding, atomic writes.
#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "course/error.h"
#include "course/exr_file.h"
#include "course/image_file.h"
#include "course/image_read.h"
#include "scratch_folder.h"

namespace fs = std::filesystem;

namespace {

fs::path scratch() { return scratchFolder("course_image_test_"); }

std::string readAll(const fs::path& path) {
    std::ifstream file(path, std::ios::binary);
    std::stringstream bytes;
    bytes << file.rdbuf();
    return bytes.str();
}

course::Image twoRows() {  // 2x2: top row red and green, bottom row blue and white
    course::Image image;
    image.width = 2;
    image.height = 2;
    image.rgba = {1, 0, 0, 1, 0, 1, 0, 1, 0, 0, 1, 1, 1, 1, 1, 1};
    return image;
}

}  // namespace

TEST(ImageFile, SrgbTransferFunction) {
    EXPECT_FLOAT_EQ(course::linearToSrgb(0.0f), 0.0f);
    EXPECT_FLOAT_EQ(course::linearToSrgb(1.0f), 1.0f);
    EXPECT_NEAR(course::linearToSrgb(0.5f), 0.735357f, 1e-5);
    EXPECT_NEAR(course::linearToSrgb(0.002f), 0.02584f, 1e-5);  // the linear toe
    EXPECT_FLOAT_EQ(course::linearToSrgb(-3.0f), 0.0f);
    EXPECT_FLOAT_EQ(course::linearToSrgb(7.0f), 1.0f);
}

TEST(ImageFile, PfmHeaderAndBottomRowFirst) {
    fs::path folder = scratch();
    course::writeImage((folder / "a.pfm").string(), twoRows());
    std::string bytes = readAll(folder / "a.pfm");
    const std::string header = "PF\n2 2\n-1.0\n";
    ASSERT_EQ(bytes.substr(0, header.size()), header);
    ASSERT_EQ(bytes.size(), header.size() + 2 * 2 * 3 * sizeof(float));
    float first[3];
    std::memcpy(first, bytes.data() + header.size(), sizeof first);
    EXPECT_EQ(first[2], 1.0f);  // the first pixel in the file is the bottom-left: blue
    EXPECT_EQ(first[0], 0.0f);
    fs::remove_all(folder);
}

TEST(ImageFile, PfmReadsBackTopRowFirstInEitherByteOrder) {
    fs::path folder = scratch();
    course::writeImage((folder / "a.pfm").string(), twoRows());
    EXPECT_EQ(course::pfmProblem((folder / "a.pfm").string()), "");
    course::ImageF image = course::readPfm((folder / "a.pfm").string());
    ASSERT_EQ(image.width, 2);
    ASSERT_EQ(image.height, 2);
    const std::vector<float> expected = {1, 0, 0, 0, 1, 0, 0, 0, 1, 1, 1, 1};
    EXPECT_EQ(image.rgb, expected);  // red and green on top, as written
    // Big-endian, grey: 1 x 1 holding 2.0 (0x40000000).
    std::ofstream(folder / "b.pfm", std::ios::binary)
        << std::string("Pf\n1 1\n1.0\n") << std::string("\x40\0\0\0", 4);
    image = course::readPfm((folder / "b.pfm").string());
    EXPECT_EQ(image.rgb, std::vector<float>({2, 2, 2}));
    std::ofstream(folder / "c.pfm", std::ios::binary) << "PF\n3 3\n-1.0\n";
    EXPECT_EQ(course::pfmProblem((folder / "c.pfm").string()),
              "not a whole PFM image (the file ends before its last row)");
    try {
        course::readPfm((folder / "c.pfm").string());
        ADD_FAILURE() << "read a truncated PFM";
    } catch (const course::Failure& error) {
        EXPECT_EQ(error.code(), course::ExitCode::BadInput);
    }
    fs::remove_all(folder);
}

TEST(ImageFile, PngIsWrittenAndNoTemporaryIsLeft) {
    fs::path folder = scratch();
    course::writeImage((folder / "a.png").string(), twoRows());
    std::string bytes = readAll(folder / "a.png");
    EXPECT_EQ(bytes.substr(1, 3), "PNG");
    size_t files = std::distance(fs::directory_iterator(folder), fs::directory_iterator());
    EXPECT_EQ(files, 1u);
    fs::remove_all(folder);
}

TEST(ImageFile, BadPathsAreRefusedBeforeWriting) {
    fs::path folder = scratch();
    auto codeOf = [](const std::string& path) {
        try {
            course::checkOutputPath(path);
        } catch (const course::Failure& failure) {
            return failure.code();
        }
        return course::ExitCode::Ok;
    };
    EXPECT_EQ(codeOf((folder / "a.jpg").string()), course::ExitCode::BadUsage);
    EXPECT_EQ(codeOf((folder / "missing" / "a.png").string()), course::ExitCode::BadUsage);
    EXPECT_EQ(codeOf(folder.string() + "/"), course::ExitCode::BadUsage);
    EXPECT_EQ(codeOf((folder / "a.PNG").string()), course::ExitCode::Ok);
    // .exr is written in a build with OpenEXR, and refused before rendering without it.
    EXPECT_EQ(codeOf((folder / "a.exr").string()),
              course::whyNoExr().empty() ? course::ExitCode::Ok : course::ExitCode::BadUsage);
    fs::remove_all(folder);
}
