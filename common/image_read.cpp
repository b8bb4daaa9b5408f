#include "course/image_read.h"

#include <memory>

#include <stb/stb_image.h>

#include "course/error.h"

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

}  // namespace course
