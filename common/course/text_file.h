// Text files as the course's two parsers read them, the chapters' OBJ loader and
// the scene files (course/scene_file.h): the whole file at once, then lines, words and
// numbers as string_views. No stream per token, and no line, however long or strange,
// can crash or hang a parser. Every mistake is exit code 3 with "<path>:<line>: what".
#pragma once
#include <cstddef>
#include <cstdint>
#include <functional>
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

// A mistake in a text file: throws course::Failure(BadInput, "<path>:<line>: what").
// Line 0 means the file as a whole (empty, or missing something it needs).
[[noreturn]] void failAtLine(const std::string& path, size_t line, const std::string& what);

// Calls readLine(line, lineNumber) for each line of `text`, numbered from 1, without its
// line end and its comment ('#' to the end of the line); a UTF-8 byte order mark at the
// start is skipped. An empty text, or a control byte in a line (binary data: no text
// file), fails naming `path` and the line.
void forEachLine(std::string_view text, const std::string& path,
                 const std::function<void(std::string_view line, size_t lineNumber)>& readLine);

// `word` as a float, or a failure at path:lineNumber that says why not: not a number
// ("1.0abc"), not finite ("nan", "inf"), out of range ("1e999") or too large for a float
// ("1e39"). A leading '+' is allowed. Never depends on the locale.
float readNumber(std::string_view word, const std::string& path, size_t lineNumber);

// Messages name absolute paths, so "cannot open" says exactly where we looked.
std::string absolutePath(const std::string& path);

// The file's bytes. Throws course::Failure(BadInput, "<absolute path>: why") when it is
// missing, unreadable, a directory, not a regular file (a pipe or /dev/zero could block
// or never end), or longer than `mostBytes`: "too large for <kind>".
std::string readWholeFile(const std::string& path, std::uintmax_t mostBytes,
                          const std::string& kind);

}  // namespace course
