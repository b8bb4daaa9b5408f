#include "course/text_file.h"

#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <limits>
#include <system_error>

#include "course/error.h"

namespace course {

bool isBlank(char c) { return c == ' ' || c == '\t' || c == '\r'; }

bool isControlByte(char c) {
    const unsigned char byte = static_cast<unsigned char>(c);
    return (byte < 0x20 && c != '\t' && c != '\r') || byte == 0x7f;
}

bool isLetter(char c) { return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z'); }
bool isDigit(char c) { return c >= '0' && c <= '9'; }

std::string_view nextWord(std::string_view& rest) {
    size_t start = 0;
    while (start < rest.size() && isBlank(rest[start]))
        ++start;
    size_t end = start;
    while (end < rest.size() && !isBlank(rest[end]))
        ++end;
    const std::string_view word = rest.substr(start, end - start);
    rest.remove_prefix(end);
    return word;
}

std::string inQuotes(std::string_view word) {
    constexpr size_t kShown = 40;
    if (word.size() <= kShown)
        return "'" + std::string(word) + "'";
    return "'" + std::string(word.substr(0, kShown)) + "...'";
}

void failAtLine(const std::string& path, size_t line, const std::string& what) {
    fail(ExitCode::BadInput, path + ":" + std::to_string(line) + ": " + what);
}

void forEachLine(std::string_view text, const std::string& path,
                 const std::function<void(std::string_view line, size_t lineNumber)>& readLine) {
    if (text.empty())
        failAtLine(path, 0, "empty file");
    if (text.substr(0, 3) == "\xEF\xBB\xBF")
        text.remove_prefix(3);  // a UTF-8 byte order mark, written by some Windows tools
    size_t lineNumber = 0;
    while (!text.empty()) {
        const size_t newline = text.find('\n');
        const std::string_view line = text.substr(0, newline);
        text.remove_prefix(newline == std::string_view::npos ? text.size() : newline + 1);
        ++lineNumber;
        // Before anything else: a NUL or other control byte means this is no text file.
        for (char c : line)
            if (isControlByte(c))
                failAtLine(path, lineNumber,
                           "binary data (a control byte) in what should be a text file");
        readLine(line.substr(0, line.find('#')), lineNumber);  // a comment runs to the end
    }
}

// --8<-- [start:number]
float readNumber(std::string_view word, const std::string& path, size_t lineNumber) {
    auto refuse = [&](const char* why) {  // throws: the mistake is named, nothing returned
        failAtLine(path, lineNumber, inQuotes(word) + why);
    };
    // from_chars reads the whole word or tells us where it stopped; it refuses a leading
    // '+', which some exporters write.
    std::string_view digits = word;
    if (digits.size() > 1 && digits[0] == '+')
        digits.remove_prefix(1);
    double value = 0.0;
    const char* end = digits.data() + digits.size();
    const auto [stop, error] = std::from_chars(digits.data(), end, value);
    if (error == std::errc::result_out_of_range)
        refuse(" is out of range for a number");
    if (error != std::errc() || stop != end)
        refuse(" is not a number");
    // from_chars accepts "nan" and "inf": valid numbers, but no place in a mesh or scene.
    if (!std::isfinite(value))
        refuse(" is not a finite number");
    if (std::fabs(value) > std::numeric_limits<float>::max())
        refuse(" is too large for a float");
    return float(value);
}
// --8<-- [end:number]

std::string absolutePath(const std::string& path) {
    std::error_code error;
    const std::filesystem::path absolute = std::filesystem::absolute(path, error);
    return error ? path : absolute.lexically_normal().string();
}

namespace {

// 16777216 bytes as "16 MiB", 4294967296 as "4 GiB".
std::string inBinaryUnits(std::uintmax_t bytes) {
    if (bytes >= (std::uintmax_t(1) << 30) && bytes % (std::uintmax_t(1) << 30) == 0)
        return std::to_string(bytes >> 30) + " GiB";
    if (bytes >= (std::uintmax_t(1) << 20) && bytes % (std::uintmax_t(1) << 20) == 0)
        return std::to_string(bytes >> 20) + " MiB";
    return std::to_string(bytes) + " bytes";
}

}  // namespace

std::string readWholeFile(const std::string& path, std::uintmax_t mostBytes,
                          const std::string& kind) {
    namespace fs = std::filesystem;
    const std::string shownPath = absolutePath(path);
    std::error_code error;
    const fs::file_status status = fs::status(path, error);
    if (fs::is_directory(status))
        fail(ExitCode::BadInput, shownPath + ": cannot open: it is a directory");
    if (fs::exists(status) && !fs::is_regular_file(status))
        fail(ExitCode::BadInput, shownPath + ": cannot open: not a regular file");
    const std::string tooLarge = shownPath + ": too large for " + kind;
    const std::uintmax_t size = fs::file_size(path, error);
    if (!error && size > mostBytes)
        fail(ExitCode::BadInput, tooLarge + ": " + std::to_string(size) + " bytes, over " +
                                     inBinaryUnits(mostBytes));
    std::FILE* file = std::fopen(path.c_str(), "rb");
    if (!file)
        fail(ExitCode::BadInput, shownPath + ": cannot open (" + std::strerror(errno) + ")");

    std::string text;
    if (!error)
        text.reserve(size);  // one allocation; the loop below still reads to the end
    char chunk[1 << 16];
    size_t count = 0;
    while ((count = std::fread(chunk, 1, sizeof chunk, file)) > 0 && text.size() <= mostBytes)
        text.append(chunk, count);
    const bool failed = std::ferror(file) != 0;
    std::fclose(file);
    if (failed)
        fail(ExitCode::BadInput, shownPath + ": cannot read the file");
    if (text.size() > mostBytes)  // the file grew while it was read
        fail(ExitCode::BadInput, tooLarge);
    return text;
}

}  // namespace course
