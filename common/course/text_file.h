// Text files as the course's two parsers read them, the OBJ loader (chapter 07) and
// the scene files (course/scene_file.h): the whole file at once, then lines and words
// as string_views. No stream per token, and no line, however long or strange, can
// crash or hang a parser.
#pragma once
#include <cstdint>
#include <string>
#include <string_view>

namespace course {

bool isBlank(char c);        // space, tab, or the \r of a CR LF line end
bool isControlByte(char c);  // a byte no text file has (tab, CR and LF aside)
bool isLetter(char c);       // a-z, A-Z
bool isDigit(char c);        // 0-9

// Cuts the next blank-separated word off the front of `rest`; "" at the end of the line.
std::string_view nextWord(std::string_view& rest);

// 'word' for a message, cut short so that one huge garbage word gives a short message.
std::string inQuotes(std::string_view word);

// Messages name absolute paths, so "cannot open" says exactly where we looked.
std::string absolutePath(const std::string& path);

// The file's bytes. Throws course::Failure(BadInput, "<absolute path>: why") when it is
// missing, unreadable, a directory, not a regular file (a pipe or /dev/zero could block
// or never end), or longer than `mostBytes`: "too large for <kind>".
std::string readWholeFile(const std::string& path, std::uintmax_t mostBytes,
                          const std::string& kind);

}  // namespace course
