#include "course/portable_files.h"

#include <cerrno>
#include <cstdlib>
#include <cstring>

#ifdef _WIN32
#ifndef NOMINMAX
#define NOMINMAX
#endif
#include <windows.h>
#include <io.h>
#include <process.h>
#else
#include <unistd.h>
#endif

namespace fs = std::filesystem;

namespace course {

#ifdef _WIN32

long processId() { return static_cast<long>(GetCurrentProcessId()); }

std::FILE* openFile(const fs::path& path, const char* mode) {
    const std::wstring wideMode(mode, mode + std::strlen(mode));
    return _wfopen(path.c_str(), wideMode.c_str());
}

std::string replaceFile(const fs::path& from, const fs::path& to) {
    // MOVEFILE_WRITE_THROUGH: the call returns once the move is on disk.
    if (MoveFileExW(from.c_str(), to.c_str(),
                    MOVEFILE_REPLACE_EXISTING | MOVEFILE_WRITE_THROUGH))
        return "";
    return "MoveFileExW failed with Windows error " + std::to_string(GetLastError());
}

bool folderIsWritable(const fs::path& folder) { return _waccess(folder.c_str(), 2) == 0; }

fs::path userCacheFolder() {
    const wchar_t* local = _wgetenv(L"LOCALAPPDATA");
    if (local && *local && fs::path(local).is_absolute()) return fs::path(local);
    return {};
}

#else

long processId() { return static_cast<long>(getpid()); }

std::FILE* openFile(const fs::path& path, const char* mode) {
    return std::fopen(path.c_str(), mode);
}

std::string replaceFile(const fs::path& from, const fs::path& to) {
    if (std::rename(from.c_str(), to.c_str()) == 0) return "";
    return std::strerror(errno);
}

bool folderIsWritable(const fs::path& folder) { return access(folder.c_str(), W_OK) == 0; }

fs::path userCacheFolder() {
    const char* xdg = std::getenv("XDG_CACHE_HOME");
    const char* home = std::getenv("HOME");
    if (xdg && fs::path(xdg).is_absolute())  // the XDG rule: a relative one is ignored
        return fs::path(xdg);
    if (home && *home) return fs::path(home) / ".cache";
    return {};
}

#endif

}  // namespace course
