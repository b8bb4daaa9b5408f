// A build without OpenEXR (configured with -DCOURSE_WITH_OPENEXR=OFF, or where the
// library was not found): .exr files are refused with a message that says how to get it.
#include "course/exr_file.h"

#include "course/error.h"

namespace course {
namespace {
const char* kWhy = "this build has no OpenEXR (install it: Debian and Ubuntu "
                   "libopenexr-dev, Fedora openexr-devel, Homebrew openexr; then rebuild)";
}

std::string whyNoExr() { return kWhy; }

std::string exrProblem(const std::string& path) {
    return startsLikeExr(path) ? kWhy
                               : "not an OpenEXR image (it does not start with the EXR "
                                 "magic number)";
}

ImageF readExr(const std::string& path) { fail(ExitCode::BadInput, path + ": " + kWhy); }

std::string writeExr(const std::string&, const Image&) { return kWhy; }

}  // namespace course
