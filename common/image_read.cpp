#include "course/image_read.h"

#include <cmath>
#include <cstring>
#include <fstream>
#include <memory>
#include <sstream>

#include <stb/stb_image.h>

#include "course/error.h"
#include "course/exr_file.h"

namespace course {

std::string imageProblem(const std::string& path) {
    int width = 0, height = 0, channels = 0;
    if (!stbi_info(path.c_str(), &width, &height, &channels))
        return std::string("not a PNG or JPEG image (") + stbi_failure_reason() + ")";
    if (width > kMostImageSide || height > kMostImageSide)
        return std::to_string(width) + " x " + std::to_string(height) +
               " texels: at most " + std::to_string(kMostImageSide) + " a side";
    return "";
}

Image8 readImage8(const std::string& path) {
    const std::string problem = imageProblem(path);
    if (!problem.empty())
        fail(ExitCode::BadInput, path + ": " + problem);
    Image8 image;
    int channels = 0;
    std::unique_ptr<stbi_uc, void (*)(void*)> pixels(
        stbi_load(path.c_str(), &image.width, &image.height, &channels, 3), stbi_image_free);
    if (!pixels)
        fail(ExitCode::BadInput,
             path + ": the image cannot be decoded (" + stbi_failure_reason() + ")");
    image.rgb.assign(pixels.get(), pixels.get() + size_t(image.width) * image.height * 3);
    return image;
}

namespace {

struct PfmHeader {
    int width = 0, height = 0, channels = 0;
    bool littleEndian = true;
    std::streamoff dataStart = 0;
    std::string problem;  // empty when the header is good
};

// "PF" or "Pf", the width and height, and a scale whose sign is the byte order, each
// followed by one whitespace character (the format's own definition).
PfmHeader readPfmHeader(std::ifstream& file) {
    PfmHeader header;
    std::string magic;
    double scale = 0.0;
    if (!(file >> magic) || (magic != "PF" && magic != "Pf")) {
        header.problem = "not a PFM image (it does not start with PF or Pf)";
        return header;
    }
    header.channels = magic == "PF" ? 3 : 1;
    if (!(file >> header.width >> header.height >> scale) || header.width <= 0 ||
        header.height <= 0 || scale == 0.0 || !std::isfinite(scale)) {
        header.problem = "not a PFM image (a bad width, height or scale line)";
        return header;
    }
    if (header.width > kMostImageSide || header.height > kMostImageSide) {
        header.problem = std::to_string(header.width) + " x " +
                         std::to_string(header.height) + " texels: at most " +
                         std::to_string(kMostImageSide) + " a side";
        return header;
    }
    file.get();  // the one whitespace character before the data
    header.littleEndian = scale < 0.0;
    header.dataStart = file.tellg();
    const std::streamoff bytes = std::streamoff(header.width) * header.height *
                                 header.channels * 4;
    file.seekg(0, std::ios::end);
    if (file.tellg() - header.dataStart < bytes)
        header.problem = "not a whole PFM image (the file ends before its last row)";
    file.seekg(header.dataStart);
    return header;
}

bool machineIsLittleEndian() {
    const uint16_t one = 1;
    uint8_t first = 0;
    std::memcpy(&first, &one, 1);
    return first == 1;
}

}  // namespace

std::string pfmProblem(const std::string& path) {
    std::ifstream file(path, std::ios::binary);
    if (!file)
        return "not readable";
    return readPfmHeader(file).problem;
}

ImageF readPfm(const std::string& path) {
    std::ifstream file(path, std::ios::binary);
    if (!file)
        fail(ExitCode::BadInput, path + ": cannot open");
    const PfmHeader header = readPfmHeader(file);
    if (!header.problem.empty())
        fail(ExitCode::BadInput, path + ": " + header.problem);
    const size_t row = size_t(header.width) * header.channels;
    std::vector<float> data(row * header.height);
    file.read(reinterpret_cast<char*>(data.data()), std::streamsize(data.size() * 4));
    if (!file)
        fail(ExitCode::BadInput, path + ": the file ends before its last row");
    if (header.littleEndian != machineIsLittleEndian())
        for (float& value : data) {
            uint8_t bytes[4];
            std::memcpy(bytes, &value, 4);
            std::swap(bytes[0], bytes[3]);
            std::swap(bytes[1], bytes[2]);
            std::memcpy(&value, bytes, 4);
        }
    ImageF image;
    image.width = header.width;
    image.height = header.height;
    image.rgb.resize(size_t(header.width) * header.height * 3);
    for (int y = 0; y < header.height; ++y) {  // the file's last row is the top
        const float* source = &data[row * size_t(header.height - 1 - y)];
        for (int x = 0; x < header.width; ++x)
            for (int c = 0; c < 3; ++c)
                image.rgb[(size_t(y) * header.width + x) * 3 + c] =
                    source[size_t(x) * header.channels + (header.channels == 3 ? c : 0)];
    }
    return image;
}

bool startsLikeExr(const std::string& path) {
    std::ifstream file(path, std::ios::binary);
    unsigned char magic[4] = {};
    file.read(reinterpret_cast<char*>(magic), 4);
    return file && magic[0] == 0x76 && magic[1] == 0x2f && magic[2] == 0x31 && magic[3] == 0x01;
}

std::string radianceMapProblem(const std::string& path) {
    if (startsLikeExr(path))
        return exrProblem(path);
    std::string problem = pfmProblem(path);
    if (problem.rfind("not a PFM image (it does not start", 0) == 0)
        problem = "not a PFM or OpenEXR image (it starts with neither PF, Pf nor the EXR "
                  "magic number)";
    return problem;
}

ImageF readRadianceMap(const std::string& path) {
    return startsLikeExr(path) ? readExr(path) : readPfm(path);
}

}  // namespace course
