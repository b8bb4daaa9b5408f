// The text reading that the OBJ loader and the scene files share (common/course/text_file.h):
// words, numbers, lines, and the file:line of every mistake. Each parser's own tests
// (test_obj_loader, test_scene_file) check the same messages through a whole file.
#include <gtest/gtest.h>

#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "course/error.h"
#include "course/text_file.h"

using course::ExitCode;
using course::Failure;

namespace {

// The words of a line, as nextWord cuts them off one by one.
std::vector<std::string> words(std::string_view line) {
    std::vector<std::string> found;
    for (std::string_view word = course::nextWord(line); !word.empty();
         word = course::nextWord(line))
        found.emplace_back(word);
    return found;
}

// The message readNumber throws for `word` at f.obj:7; "" when it reads a number.
std::string numberFailure(std::string_view word) {
    try {
        course::readNumber(word, "f.obj", 7);
    } catch (const Failure& failure) {
        EXPECT_EQ(failure.code(), ExitCode::BadInput);
        return failure.what();
    }
    return "";
}

// The lines forEachLine hands over, with their numbers, or the message it throws.
std::pair<std::vector<std::pair<size_t, std::string>>, std::string> lines(
    std::string_view text) {
    std::vector<std::pair<size_t, std::string>> seen;
    try {
        course::forEachLine(text, "f.txt", [&](std::string_view line, size_t number) {
            seen.emplace_back(number, std::string(line));
        });
    } catch (const Failure& failure) {
        EXPECT_EQ(failure.code(), ExitCode::BadInput);
        return {seen, failure.what()};
    }
    return {seen, ""};
}

}  // namespace

TEST(TextFile, WordsAreSeparatedByBlanks) {
    EXPECT_EQ(words("  v 1\t2  3\r"), (std::vector<std::string>{"v", "1", "2", "3"}));
    EXPECT_EQ(words(""), std::vector<std::string>{});
    EXPECT_EQ(words(" \t\r "), std::vector<std::string>{});
    EXPECT_EQ(words("f 1/2/3 4//6"), (std::vector<std::string>{"f", "1/2/3", "4//6"}));
}

TEST(TextFile, ReadsNumbersAsFloats) {
    EXPECT_EQ(course::readNumber("1.5", "f.obj", 1), 1.5f);
    EXPECT_EQ(course::readNumber("-2", "f.obj", 1), -2.0f);
    EXPECT_EQ(course::readNumber("+0.25", "f.obj", 1), 0.25f);  // some exporters write '+'
    EXPECT_EQ(course::readNumber("1e-3", "f.obj", 1), 1e-3f);
    EXPECT_EQ(course::readNumber("3.4e38", "f.obj", 1), 3.4e38f);
    EXPECT_EQ(course::readNumber(".5", "f.obj", 1), 0.5f);
}

TEST(TextFile, EveryBadNumberIsNamedWithFileAndLine) {
    EXPECT_EQ(numberFailure("1.0abc"), "f.obj:7: '1.0abc' is not a number");
    EXPECT_EQ(numberFailure("1,5"), "f.obj:7: '1,5' is not a number");  // never the locale's
    EXPECT_EQ(numberFailure("+"), "f.obj:7: '+' is not a number");
    EXPECT_EQ(numberFailure("++1"), "f.obj:7: '++1' is not a number");
    EXPECT_EQ(numberFailure("0x10"), "f.obj:7: '0x10' is not a number");
    EXPECT_EQ(numberFailure("nan"), "f.obj:7: 'nan' is not a finite number");
    EXPECT_EQ(numberFailure("-INF"), "f.obj:7: '-INF' is not a finite number");
    EXPECT_EQ(numberFailure("1e39"), "f.obj:7: '1e39' is too large for a float");
    EXPECT_EQ(numberFailure("1e999"), "f.obj:7: '1e999' is out of range for a number");
    // A huge garbage word gives a short message.
    EXPECT_EQ(numberFailure(std::string(1000, 'x')),
              "f.obj:7: '" + std::string(40, 'x') + "...' is not a number");
}

TEST(TextFile, LinesAreNumberedWithoutLineEndsOrComments) {
    const auto [seen, failure] = lines("\xEF\xBB\xBFv 1 # a comment\r\n\n# only one\nf 1");
    EXPECT_EQ(failure, "");
    const std::vector<std::pair<size_t, std::string>> expected = {
        {1, "v 1 "}, {2, ""}, {3, ""}, {4, "f 1"}};
    EXPECT_EQ(seen, expected);
}

TEST(TextFile, AnEmptyFileOrBinaryDataIsRefused) {
    EXPECT_EQ(lines("").second, "f.txt:0: empty file");
    const auto [seen, failure] = lines(std::string("v 1\nv 2\x01\nv 3", 12));
    EXPECT_EQ(seen.size(), 1u);  // line 2 is refused before it is read
    EXPECT_EQ(failure, "f.txt:2: binary data (a control byte) in what should be a text file");
    // In a comment too: a control byte means the file is not text at all.
    EXPECT_EQ(lines(std::string("# \0\n", 4)).second,
              "f.txt:1: binary data (a control byte) in what should be a text file");
}
