// Reading images: PNG and JPEG for textures, with stb_image (compiled once in
// common/stb_image.cpp), and PFM or OpenEXR radiance maps for the environment light
// (EXR through the OpenEXR library: common/exr_file.cpp). Decoding
// image files is not a lesson of the course; what a texture does with the values (sRGB
// decoding, filtering) is, and what a light does with a map.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

namespace course {

// The largest image side read: 8192 texels (a 256 MiB float texture at most).
constexpr int kMostImageSide = 8192;

struct Image8 {
    int width = 0, height = 0;
    std::vector<uint8_t> rgb;  // row 0 is the TOP row of the file, 3 bytes per texel
};

// Empty when `path` is a PNG or JPEG image of a size we read, else what is wrong with
// it ("not a PNG or JPEG image: ...", "16385 x 2 texels: ..."). Reads only the header.
std::string imageProblem(const std::string& path);

// The whole image as 8-bit RGB (grey is repeated into R, G and B; alpha is dropped).
// Throws Failure(BadInput) naming the file when it cannot be read.
Image8 readImage8(const std::string& path);

// A float image: what a PFM or EXR file holds.
struct ImageF {
    int width = 0, height = 0;
    std::vector<float> rgb;  // row 0 is the TOP row (PFM files store the bottom first)
};

// Empty when `path` is a PFM image ("PF" colour or "Pf" grey) of a size we read, else
// what is wrong with it. Reads only the header.
std::string pfmProblem(const std::string& path);

// The whole PFM image, grey repeated into R, G and B, either byte order. Throws
// Failure(BadInput) naming the file when it cannot be read; the values are as the
// file has them (the caller decides what a NaN or a negative value means).
ImageF readPfm(const std::string& path);

// A radiance map: OpenEXR when the file starts with EXR's magic number, else PFM.
// Empty when it can be read, else what is wrong with it (a PFM's header and length;
// an EXR is read whole).
std::string radianceMapProblem(const std::string& path);
// The whole map; throws Failure(BadInput) naming the file when it cannot be read.
ImageF readRadianceMap(const std::string& path);

}  // namespace course
