#include "course/exr_file.h"

#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfInputFile.h>
#include <ImfOutputFile.h>

#include <cstdint>
#include <cstdio>
#include <exception>
#include <vector>

#include "course/error.h"

namespace course {
namespace {

struct Layout {
    int width = 0, height = 0, left = 0, top = 0;
    bool grey = false;  // one Y channel instead of R, G and B
};

// What the header says, or a problem. The OpenEXR calls throw on a damaged file.
std::string readLayout(Imf::InputFile& file, Layout& layout) {
    const Imath::Box2i window = file.header().dataWindow();
    layout.left = window.min.x;
    layout.top = window.min.y;
    layout.width = window.max.x - window.min.x + 1;
    layout.height = window.max.y - window.min.y + 1;
    if (layout.width < 1 || layout.height < 1 || layout.width > kMostImageSide ||
        layout.height > kMostImageSide)
        return std::to_string(layout.width) + " x " + std::to_string(layout.height) +
               " texels: at most " + std::to_string(kMostImageSide) + " a side";
    const Imf::ChannelList& channels = file.header().channels();
    const bool rgb = channels.findChannel("R") && channels.findChannel("G") &&
                     channels.findChannel("B");
    layout.grey = !rgb && channels.findChannel("Y");
    if (!rgb && !layout.grey) {
        std::string names;
        for (auto channel = channels.begin(); channel != channels.end(); ++channel)
            names += std::string(names.empty() ? "" : ", ") + channel.name();
        return "an OpenEXR image without R, G and B (or Y) channels (it has: " +
               (names.empty() ? std::string("none") : names) + ")";
    }
    return "";
}

// The whole image into `image`; returns what is wrong, or an empty string. A damaged
// file may show only when its pixels are read, so even a check reads them all.
std::string readPixels(const std::string& path, ImageF& image) {
    if (!startsLikeExr(path))
        return "not an OpenEXR image (it does not start with the EXR magic number)";
    try {
        Imf::InputFile file(path.c_str());
        Layout layout;
        const std::string problem = readLayout(file, layout);
        if (!problem.empty())
            return problem;
        image.width = layout.width;
        image.height = layout.height;
        image.rgb.assign(size_t(layout.width) * layout.height * 3, 0.0f);
        // The frame buffer is addressed in the file's own pixel coordinates, which start
        // at the data window's corner, not at 0.
        const size_t xStride = 3 * sizeof(float), yStride = xStride * layout.width;
        char* origin = reinterpret_cast<char*>(image.rgb.data()) -
                       (std::ptrdiff_t(layout.left) * xStride +
                        std::ptrdiff_t(layout.top) * yStride);
        Imf::FrameBuffer frame;
        const char* names[3] = {"R", "G", "B"};
        for (int c = 0; c < (layout.grey ? 1 : 3); ++c)
            frame.insert(layout.grey ? "Y" : names[c],
                         Imf::Slice(Imf::FLOAT, origin + c * sizeof(float), xStride, yStride));
        file.setFrameBuffer(frame);
        file.readPixels(layout.top, layout.top + layout.height - 1);
        if (layout.grey)
            for (size_t i = 0; i < image.rgb.size(); i += 3)
                image.rgb[i + 1] = image.rgb[i + 2] = image.rgb[i];
        return "";
    } catch (const std::exception& error) {
        return std::string("not a readable OpenEXR image (") + error.what() + ")";
    }
}

}  // namespace

std::string whyNoExr() { return ""; }

std::string exrProblem(const std::string& path) {
    ImageF ignored;
    return readPixels(path, ignored);
}

ImageF readExr(const std::string& path) {
    ImageF image;
    const std::string problem = readPixels(path, image);
    if (!problem.empty())
        fail(ExitCode::BadInput, path + ": " + problem);
    return image;
}

std::string writeExr(const std::string& path, const Image& image) {
    try {
        Imf::Header header(image.width, image.height);
        header.compression() = Imf::ZIP_COMPRESSION;
        const char* names[3] = {"R", "G", "B"};
        Imf::FrameBuffer frame;
        char* pixels = reinterpret_cast<char*>(const_cast<float*>(image.rgba.data()));
        const size_t xStride = 4 * sizeof(float), yStride = xStride * image.width;
        for (int c = 0; c < 3; ++c) {
            header.channels().insert(names[c], Imf::Channel(Imf::FLOAT));
            frame.insert(names[c],
                         Imf::Slice(Imf::FLOAT, pixels + c * sizeof(float), xStride, yStride));
        }
        Imf::OutputFile file(path.c_str(), header);
        file.setFrameBuffer(frame);
        file.writePixels(image.height);
        return "";
    } catch (const std::exception& error) {
        return error.what();
    }
}

}  // namespace course
