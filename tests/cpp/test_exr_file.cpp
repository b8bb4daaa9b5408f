// OpenEXR images: the linear output read back exactly, and the radiance maps we read,
// written here by OpenEXR itself in the forms other tools write (half floats, a grey Y
// channel, a data window that does not start at 0), and refused when damaged.
#include <gtest/gtest.h>

#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfOutputFile.h>
#include <half.h>

#include <filesystem>
#include <fstream>
#include <vector>

#include "course/error.h"
#include "course/exr_file.h"
#include "course/image_file.h"
#include "course/image_read.h"
#include "scratch_folder.h"

namespace fs = std::filesystem;

namespace {

fs::path scratch() { return scratchFolder("course_exr_test_"); }

// A 3 x 2 image whose every value differs: value = 100 row + 10 column + channel, plus a
// fraction that needs all of a float's bits.
course::Image distinctValues() {
    course::Image image;
    image.width = 3;
    image.height = 2;
    for (int row = 0; row < 2; ++row)
        for (int column = 0; column < 3; ++column) {
            for (int c = 0; c < 3; ++c)
                image.rgba.push_back(100.0f * row + 10.0f * column + c + 1.0f / 3.0f);
            image.rgba.push_back(1.0f);
        }
    return image;
}

// One channel named `name` of half floats over the data window (left, top) .. (left +
// width - 1, top + height - 1), holding 0.25 * (its index in the window).
void writeHalfChannel(const fs::path& path, const char* name, int left, int top, int width,
                      int height) {
    Imf::Header header(width, height);
    header.dataWindow() = Imath::Box2i(Imath::V2i(left, top),
                                       Imath::V2i(left + width - 1, top + height - 1));
    header.displayWindow() = header.dataWindow();
    header.channels().insert(name, Imf::Channel(Imf::HALF));
    std::vector<half> values(size_t(width) * height);
    for (size_t i = 0; i < values.size(); ++i) values[i] = half(0.25f * float(i));
    char* origin = reinterpret_cast<char*>(values.data()) -
                   (std::ptrdiff_t(left) + std::ptrdiff_t(top) * width) * sizeof(half);
    Imf::FrameBuffer frame;
    frame.insert(name, Imf::Slice(Imf::HALF, origin, sizeof(half), sizeof(half) * width));
    Imf::OutputFile file(path.c_str(), header);
    file.setFrameBuffer(frame);
    file.writePixels(height);
}

}  // namespace

TEST(ExrFile, TheLinearOutputReadsBackExactlyTopRowFirst) {
    const fs::path folder = scratch();
    const course::Image image = distinctValues();
    course::writeImage((folder / "a.exr").string(), image);
    EXPECT_EQ(course::exrProblem((folder / "a.exr").string()), "");
    const course::ImageF read = course::readRadianceMap((folder / "a.exr").string());
    ASSERT_EQ(read.width, 3);
    ASSERT_EQ(read.height, 2);
    for (size_t pixel = 0; pixel < 6; ++pixel)
        for (int c = 0; c < 3; ++c)
            EXPECT_EQ(read.rgb[pixel * 3 + c], image.rgba[pixel * 4 + c]) << pixel << " " << c;
    EXPECT_EQ(std::distance(fs::directory_iterator(folder), fs::directory_iterator()), 1);
    fs::remove_all(folder);
}

TEST(ExrFile, GreyHalfFloatsAndAnOffsetDataWindow) {
    const fs::path folder = scratch();
    writeHalfChannel(folder / "y.exr", "Y", -5, 7, 4, 3);
    const course::ImageF read = course::readExr((folder / "y.exr").string());
    ASSERT_EQ(read.width, 4);
    ASSERT_EQ(read.height, 3);
    for (size_t i = 0; i < 12; ++i)
        for (int c = 0; c < 3; ++c) EXPECT_EQ(read.rgb[i * 3 + c], 0.25f * float(i)) << i;
    fs::remove_all(folder);
}

TEST(ExrFile, WhatIsNotARadianceMapIsRefusedWithAReason) {
    const fs::path folder = scratch();
    writeHalfChannel(folder / "depth.exr", "Z", 0, 0, 2, 2);
    EXPECT_EQ(course::radianceMapProblem((folder / "depth.exr").string()),
              "an OpenEXR image without R, G and B (or Y) channels (it has: Z)");
    writeHalfChannel(folder / "wide.exr", "Y", 0, 0, course::kMostImageSide + 1, 1);
    EXPECT_EQ(course::radianceMapProblem((folder / "wide.exr").string()),
              "8193 x 1 texels: at most 8192 a side");
    std::ofstream(folder / "text.exr") << "PF\n";
    EXPECT_EQ(course::exrProblem((folder / "text.exr").string()),
              "not an OpenEXR image (it does not start with the EXR magic number)");
    // The first 300 bytes of a good file: the header reads, the pixels do not.
    course::writeImage((folder / "good.exr").string(), distinctValues());
    std::ifstream good(folder / "good.exr", std::ios::binary);
    std::string start(300, '\0');
    good.read(start.data(), 300);
    std::ofstream(folder / "cut.exr", std::ios::binary) << start;
    EXPECT_EQ(course::radianceMapProblem((folder / "cut.exr").string())
                  .rfind("not a readable OpenEXR image (", 0), 0u);
    try {
        course::readRadianceMap((folder / "cut.exr").string());
        ADD_FAILURE() << "read a truncated EXR";
    } catch (const course::Failure& error) {
        EXPECT_EQ(error.code(), course::ExitCode::BadInput);
    }
    fs::remove_all(folder);
}
