// OpenEXR images, through the OpenEXR library: the linear format renderers and
// compositors exchange. The course writes its linear output as .exr on request and reads
// environment maps from it. A build without OpenEXR (common/exr_unavailable.cpp) refuses
// .exr files with a message that says how to get it.
#pragma once
#include <string>

#include "course/image_file.h"
#include "course/image_read.h"

namespace course {

// Empty, or in a build without OpenEXR why .exr files cannot be read or written.
std::string whyNoExr();

// True when the file starts with OpenEXR's magic number (any build).
bool startsLikeExr(const std::string& path);

// Empty when `path` is an OpenEXR image with R, G and B (or Y) channels and at most
// kMostImageSide pixels a side, else what is wrong with it. Reads the pixels too: a
// damaged file may show only then.
std::string exrProblem(const std::string& path);

// The whole image as 32-bit floats (half floats converted), Y repeated into R, G and B.
// Throws Failure(BadInput) naming the file when it cannot be read.
ImageF readExr(const std::string& path);

// Writes R, G and B as 32-bit floats, ZIP-compressed (lossless). Returns an empty string,
// or why the file could not be written.
std::string writeExr(const std::string& path, const Image& image);

}  // namespace course
