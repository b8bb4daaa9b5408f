#pragma once
// The few file and process calls that differ between POSIX and Windows, answered once
// here so that the rest of common/ and the chapters call neither API directly.

#include <cstdio>
#include <filesystem>
#include <string>

namespace course {

// This process's id: part of temporary file names, so that two runs never share one.
long processId();

// Opens `path` as std::fopen does; on Windows through the path's wide-character name,
// so that a folder named in any language works.
std::FILE* openFile(const std::filesystem::path& path, const char* mode);

// Puts `from` in the place of `to` in one step, replacing `to` if it exists: a reader
// sees the old file or the new one, never half of either (rename on POSIX; MoveFileExW
// with MOVEFILE_REPLACE_EXISTING on Windows, whose rename refuses an existing target).
// Returns "" or why it failed.
std::string replaceFile(const std::filesystem::path& from, const std::filesystem::path& to);

// Whether the user may create files in `folder` (access(W_OK) / _waccess).
bool folderIsWritable(const std::filesystem::path& folder);

// Where per-user caches go: $XDG_CACHE_HOME (when absolute) or ~/.cache on POSIX,
// %LOCALAPPDATA% on Windows; empty when neither is known.
std::filesystem::path userCacheFolder();

}  // namespace course
