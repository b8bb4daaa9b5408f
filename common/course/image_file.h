// Images leave the GPU as linear RGBA floats and are written as
//   .png  8-bit, sRGB-encoded (what a viewer expects), alpha dropped
//   .pfm  32-bit float RGB, linear (what a numerical check wants)
//   .exr  32-bit float RGB, linear, ZIP-compressed (what renderers and compositors
//         exchange; through OpenEXR, common/exr_file.cpp)
// Files are written to a temporary name in the same folder and renamed, so a crash
// or a full disk never leaves a half-written image under the real name.
#pragma once
#include <functional>
#include <string>
#include <vector>

namespace course {

struct Image {
    int width = 0, height = 0;
    std::vector<float> rgba;  // row 0 is the TOP row, 4 floats per pixel, linear
};

float linearToSrgb(float linear);  // the sRGB transfer function, input clamped to [0,1]

// Writes .png, .pfm or .exr by the file's extension; throws Failure(BadUsage) for other
// extensions and when the file cannot be written (read-only folder, full disk).
void writeImage(const std::string& path, const Image& image);

// Checks before any rendering that `path` has a known extension and a writable folder,
// so a typo fails in a millisecond instead of after a long render.
void checkOutputPath(const std::string& path);

// Writes `bytes` to `path` through a temporary file and a rename.
void writeFileAtomically(const std::string& path, const std::string& bytes);

// The same for a writer that needs a file name: `write` writes the temporary file it is
// given and returns an empty string, or why it could not.
void writeFileAtomically(const std::string& path,
                         const std::function<std::string(const std::string&)>& write);

}  // namespace course
