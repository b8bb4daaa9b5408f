#include "course/image_file.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>

#include <stb/stb_image_write.h>

#include "course/error.h"
#include "course/exr_file.h"
#include "course/portable_files.h"

namespace fs = std::filesystem;

namespace course {
namespace {

std::string extensionOf(const std::string& path) {
    std::string ext = fs::path(path).extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), ::tolower);
    return ext;
}

std::string encodePng(const Image& image) {
    std::vector<unsigned char> srgb(size_t(image.width) * image.height * 3);
    for (size_t i = 0; i < srgb.size() / 3; ++i)
        for (int c = 0; c < 3; ++c) {
            float encoded = linearToSrgb(image.rgba[i * 4 + c]);
            srgb[i * 3 + c] = static_cast<unsigned char>(std::lround(encoded * 255.0f));
        }
    std::string bytes;
    auto append = [](void* context, void* data, int size) {
        static_cast<std::string*>(context)->append(static_cast<char*>(data), size);
    };
    if (!stbi_write_png_to_func(append, &bytes, image.width, image.height, 3,
                                srgb.data(), image.width * 3))
        fail(ExitCode::BadInput, "could not encode the PNG image");
    return bytes;
}

// PFM: a text header, then little-endian floats with the BOTTOM row first.
std::string encodePfm(const Image& image) {
    std::string bytes = "PF\n" + std::to_string(image.width) + " " +
                        std::to_string(image.height) + "\n-1.0\n";
    std::vector<float> rgb(size_t(image.width) * image.height * 3);
    for (int y = 0; y < image.height; ++y) {
        int sourceRow = image.height - 1 - y;
        for (int x = 0; x < image.width; ++x)
            for (int c = 0; c < 3; ++c)
                rgb[(size_t(y) * image.width + x) * 3 + c] =
                    image.rgba[(size_t(sourceRow) * image.width + x) * 4 + c];
    }
    bytes.append(reinterpret_cast<const char*>(rgb.data()), rgb.size() * sizeof(float));
    return bytes;
}

}  // namespace

float linearToSrgb(float linear) {
    float x = std::clamp(std::isnan(linear) ? 0.0f : linear, 0.0f, 1.0f);
    return x <= 0.0031308f ? 12.92f * x : 1.055f * std::pow(x, 1.0f / 2.4f) - 0.055f;
}

void checkOutputPath(const std::string& path) {
    std::string ext = extensionOf(path);
    if (ext != ".png" && ext != ".pfm" && ext != ".exr")
        fail(ExitCode::BadUsage,
             "--out " + path + ": the file name must end in .png, .pfm or .exr");
    if (ext == ".exr" && !whyNoExr().empty())
        fail(ExitCode::BadUsage, "--out " + path + ": " + whyNoExr());
    fs::path folder = fs::absolute(path).parent_path();
    std::error_code error;
    if (!fs::is_directory(folder, error))
        fail(ExitCode::BadUsage, "--out " + path + ": folder " + folder.string() +
                                     " does not exist");
    if (fs::is_directory(fs::path(path), error))
        fail(ExitCode::BadUsage, "--out " + path + ": is a folder, not a file");
    if (!folderIsWritable(folder))
        fail(ExitCode::BadUsage, "--out " + path + ": folder " + folder.string() +
                                     " is not writable");
    // access() says yes to root even on a read-only file system: try for real, with the
    // temporary name the image will be written under, before any rendering.
    fs::path probe = fs::absolute(path);
    probe += ".tmp" + std::to_string(processId());
    std::FILE* file = openFile(probe, "wb");
    if (!file)
        fail(ExitCode::BadUsage, "--out " + path + ": cannot write in " + folder.string() +
                                     " (" + std::strerror(errno) + ")");
    std::fclose(file);
    fs::remove(probe, error);
}

void writeFileAtomically(const std::string& path,
                         const std::function<std::string(const std::string&)>& write) {
    fs::path target = fs::absolute(path);
    fs::path temporary = target;
    temporary += ".tmp" + std::to_string(processId());
    // An output we cannot write is a usage problem (exit 2): a read-only or full disk,
    // a path the user chose. The message says which folder and why.
    auto cannotWrite = [&](const char* step, const std::string& reason) {
        std::error_code ignored;
        fs::remove(temporary, ignored);
        fail(ExitCode::BadUsage, "cannot write the image " + target.string() + " (" + step +
                                     " failed: " + reason + ")");
    };
    const std::string problem = write(temporary.string());
    if (!problem.empty()) cannotWrite("writing", problem);
    const std::string replaced = replaceFile(temporary, target);
    if (!replaced.empty()) cannotWrite("renaming", replaced);
}

void writeFileAtomically(const std::string& path, const std::string& bytes) {
    writeFileAtomically(path, [&](const std::string& temporary) -> std::string {
        std::FILE* file = openFile(temporary, "wb");
        if (!file) return std::string("creating a temporary file: ") + std::strerror(errno);
        bool written = std::fwrite(bytes.data(), 1, bytes.size(), file) == bytes.size();
        written = (std::fflush(file) == 0) && written;
        const int closed = std::fclose(file);
        return closed == 0 && written ? "" : std::strerror(errno);
    });
}

void writeImage(const std::string& path, const Image& image) {
    checkOutputPath(path);
    const std::string ext = extensionOf(path);
    if (ext == ".exr")
        writeFileAtomically(path, [&](const std::string& temporary) {
            return writeExr(temporary, image);
        });
    else
        writeFileAtomically(path, ext == ".png" ? encodePng(image) : encodePfm(image));
}

}  // namespace course
