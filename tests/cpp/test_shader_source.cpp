// The shader preprocessor: #include, #line mapping and compiler-log translation.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "course/error.h"
#include "course/shader_source.h"

namespace fs = std::filesystem;
using course::ExitCode;
using course::Failure;

namespace {

// A scratch shader folder laid out like the course's: <tmp>/shaders/NN_test/.
struct ShaderFolder {
    fs::path root = fs::temp_directory_path() /
                    ("course_shader_test_" + std::to_string(::testing::UnitTest::GetInstance()
                                                                 ->random_seed()) +
                     "_" + ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::path folder = root / "shaders" / "99_test";
    ShaderFolder() { fs::create_directories(folder); }
    ~ShaderFolder() { fs::remove_all(root); }
    void write(const std::string& name, const std::string& text) {
        std::ofstream(folder / name) << text;
    }
};

std::string failureOf(const std::function<void()>& action, ExitCode expected) {
    try {
        action();
    } catch (const Failure& failure) {
        EXPECT_EQ(failure.code(), expected);
        return failure.what();
    }
    ADD_FAILURE() << "no Failure thrown";
    return "";
}

}  // namespace

TEST(ShaderSource, IncludesAreInlinedWithLineDirectives) {
    ShaderFolder shaders;
    shaders.write("main.comp", "#version 430\n#include \"a.glsl\"\nvoid main() {}\n");
    shaders.write("a.glsl", "float a() { return 1.0; }\n");
    course::ShaderSource source = course::loadShaderSource(shaders.folder.string(), "main.comp");
    EXPECT_EQ(source.text,
              "#version 430\n#line 10001 1\nfloat a() { return 1.0; }\n#line 3 0\n"
              "void main() {}\n");
    ASSERT_EQ(source.shownPaths.size(), 2u);
    EXPECT_EQ(source.shownPaths[0], "shaders/99_test/main.comp");
    EXPECT_EQ(source.shownPaths[1], "shaders/99_test/a.glsl");
}

TEST(ShaderSource, NestedIncludesAndCrlf) {
    ShaderFolder shaders;
    shaders.write("main.comp", "#version 430\r\n#include \"a.glsl\"\r\nvoid main() {}\r\n");
    shaders.write("a.glsl", "#include \"b.glsl\"\nfloat a;\n");
    shaders.write("b.glsl", "float b;\n");
    course::ShaderSource source = course::loadShaderSource(shaders.folder.string(), "main.comp");
    EXPECT_EQ(source.text, "#version 430\n#line 10001 1\n#line 20001 2\nfloat b;\n"
                           "#line 10002 1\nfloat a;\n#line 3 0\nvoid main() {}\n");
}

TEST(ShaderSource, GeneratedFilesComeFirstAreNamedSoAndAreNotWatched) {
    ShaderFolder shaders;
    shaders.write("main.comp", "#version 430\n#include \"scene_code.glsl\"\nvoid main() {}\n");
    shaders.write("scene_code.glsl", "float onDisk;\n");  // the generated text wins
    std::vector<course::ShaderFile> read;
    course::ShaderSource source = course::loadShaderSource(
        shaders.folder.string(), "main.comp", &read, {{"scene_code.glsl", "float made;\n"}});
    EXPECT_EQ(source.text, "#version 430\n#line 10001 1\nfloat made;\n#line 3 0\n"
                           "void main() {}\n");
    ASSERT_EQ(source.shownPaths.size(), 2u);
    EXPECT_EQ(source.shownPaths[1], "shaders/99_test/scene_code.glsl (generated)");
    ASSERT_EQ(read.size(), 1u);  // main.comp only: hot reload has nothing to re-read
    EXPECT_EQ(read[0].shownPath, "shaders/99_test/main.comp");
}

TEST(ShaderSource, AnEmptyGeneratedFileIsAnError) {
    ShaderFolder shaders;
    shaders.write("main.comp", "#version 430\n#include \"made.glsl\"\n");
    std::string message = failureOf(
        [&] {
            course::loadShaderSource(shaders.folder.string(), "main.comp", nullptr,
                                     {{"made.glsl", "\n"}});
        },
        ExitCode::GlProblem);
    EXPECT_NE(message.find("made.glsl (generated): shader file is empty"), std::string::npos)
        << message;
}

TEST(ShaderSource, MissingIncludeNamesTheIncludingLine) {
    ShaderFolder shaders;
    shaders.write("main.comp", "#version 430\n\n#include \"missing.glsl\"\n");
    std::string message = failureOf(
        [&] { course::loadShaderSource(shaders.folder.string(), "main.comp"); },
        ExitCode::GlProblem);
    EXPECT_NE(message.find("shaders/99_test/main.comp:3"), std::string::npos) << message;
    EXPECT_NE(message.find((shaders.folder / "missing.glsl").string()), std::string::npos)
        << message;
}

TEST(ShaderSource, MissingFileGivesTheAbsolutePathTried) {
    ShaderFolder shaders;
    std::string message = failureOf(
        [&] { course::loadShaderSource(shaders.folder.string(), "nope.comp"); },
        ExitCode::GlProblem);
    EXPECT_NE(message.find((shaders.folder / "nope.comp").string()), std::string::npos);
}

TEST(ShaderSource, EmptyShaderIsNeverCompiled) {
    ShaderFolder shaders;
    shaders.write("main.comp", "  \n\n");
    std::string message = failureOf(
        [&] { course::loadShaderSource(shaders.folder.string(), "main.comp"); },
        ExitCode::GlProblem);
    EXPECT_NE(message.find("empty"), std::string::npos);
}

TEST(ShaderSource, IncludeCycleIsReported) {
    ShaderFolder shaders;
    shaders.write("main.comp", "#version 430\n#include \"a.glsl\"\n");
    shaders.write("a.glsl", "#include \"b.glsl\"\n");
    shaders.write("b.glsl", "#include \"a.glsl\"\n");
    std::string message = failureOf(
        [&] { course::loadShaderSource(shaders.folder.string(), "main.comp"); },
        ExitCode::GlProblem);
    EXPECT_NE(message.find("cycle"), std::string::npos);
    EXPECT_NE(message.find("shaders/99_test/b.glsl:1"), std::string::npos) << message;
}

TEST(ShaderSource, MissingVersionAndBadIncludeSyntax) {
    ShaderFolder shaders;
    shaders.write("noversion.comp", "void main() {}\n");
    EXPECT_NE(failureOf([&] { course::loadShaderSource(shaders.folder.string(), "noversion.comp"); },
                        ExitCode::GlProblem)
                  .find("#version"),
              std::string::npos);
    shaders.write("bad.comp", "#version 430\n#include <a.glsl>\n");
    EXPECT_NE(failureOf([&] { course::loadShaderSource(shaders.folder.string(), "bad.comp"); },
                        ExitCode::GlProblem)
                  .find("shaders/99_test/bad.comp:2"),
              std::string::npos);
}

// A header shared with C++ keeps its C++ includes inside #ifdef __cplusplus: those lines
// reach GLSL blank (so every line keeps its number), their #includes are not looked for,
// and the #if lines themselves pass, so GLSL sees the same structure.
TEST(ShaderSource, CplusplusOnlyLinesArePassedOverBlank) {
    ShaderFolder shaders;
    shaders.write("main.comp", "#version 430\n#include \"shared.h\"\nvoid main() {}\n");
    shaders.write("shared.h",
                  "#ifndef SHARED_H\n"                   // 1
                  "#define SHARED_H\n"                   // 2
                  "#ifdef __cplusplus\n"                 // 3
                  "#include <glm/glm.hpp>\n"             // 4
                  "#include \"only_cpp.h\"\n"            // 5: never looked for
                  "namespace gpu {\n"                    // 6
                  "#endif\n"                             // 7
                  "#define BINDING 1\n"                  // 8
                  "#ifdef __cplusplus\n"                 // 9
                  "struct Block {\n"                     // 10
                  "#else\n"                              // 11
                  "layout(std140) uniform Block {\n"     // 12
                  "#endif\n"                             // 13
                  "    float x;\n"                       // 14
                  "};\n"                                 // 15
                  "#ifdef __cplusplus\n"                 // 16
                  "}  // namespace gpu\n"                // 17
                  "#endif\n"                             // 18
                  "#endif\n");                           // 19
    const course::ShaderSource source =
        course::loadShaderSource(shaders.folder.string(), "main.comp");
    EXPECT_EQ(source.text,
              "#version 430\n#line 10001 1\n"
              "#ifndef SHARED_H\n#define SHARED_H\n#ifdef __cplusplus\n\n\n\n#endif\n"
              "#define BINDING 1\n#ifdef __cplusplus\n\n#else\n"
              "layout(std140) uniform Block {\n#endif\n    float x;\n};\n"
              "#ifdef __cplusplus\n\n#endif\n#endif\n"
              "#line 3 0\nvoid main() {}\n");
    EXPECT_EQ(source.shownPaths.size(), 2u);  // only_cpp.h was not read
}

TEST(ShaderSource, EveryWayOfAskingForCplusplus) {
    ShaderFolder shaders;
    shaders.write("main.comp",
                  "#version 430\n"
                  "#if defined(__cplusplus)  // C++\n#include <a>\n#endif\n"
                  "#if defined __cplusplus\n#include <b>\n#elif FOO\nglsl_b;\n#endif\n"
                  "#ifndef __cplusplus\nglsl_c;\n#else\n#include <c>\n#endif\n"
                  "#if !defined(__cplusplus)\nglsl_d;\n#else\n"
                  "#if NESTED\n#include <d>\n#endif\n#endif\n"
                  "#if defined(__cplusplus) && OTHER\nunchanged;\n#endif\n");
    EXPECT_EQ(course::loadShaderSource(shaders.folder.string(), "main.comp").text,
              "#version 430\n"
              "#if defined(__cplusplus)  // C++\n\n#endif\n"
              "#if defined __cplusplus\n\n#elif FOO\nglsl_b;\n#endif\n"
              "#ifndef __cplusplus\nglsl_c;\n#else\n\n#endif\n"
              "#if !defined(__cplusplus)\nglsl_d;\n#else\n\n\n\n#endif\n"
              "#if defined(__cplusplus) && OTHER\nunchanged;\n#endif\n");
}

TEST(ShaderSource, CplusplusBlockWithoutEndifIsReported) {
    ShaderFolder shaders;
    shaders.write("main.comp", "#version 430\n#include \"shared.h\"\nvoid main() {}\n");
    shaders.write("shared.h", "#define A 1\n#ifdef __cplusplus\n#include <glm/glm.hpp>\n");
    const std::string message = failureOf(
        [&] { course::loadShaderSource(shaders.folder.string(), "main.comp"); },
        ExitCode::GlProblem);
    EXPECT_NE(message.find("shaders/99_test/shared.h:2: this #if on __cplusplus has no "
                           "#endif"),
              std::string::npos)
        << message;
}

TEST(ShaderSource, AngleIncludeOutsideCplusplusSaysWhereItBelongs) {
    ShaderFolder shaders;
    shaders.write("main.comp", "#version 430\n#include <glm/glm.hpp>\nvoid main() {}\n");
    const std::string message = failureOf(
        [&] { course::loadShaderSource(shaders.folder.string(), "main.comp"); },
        ExitCode::GlProblem);
    EXPECT_NE(message.find("shaders/99_test/main.comp:2: #include needs a quoted file name"),
              std::string::npos)
        << message;
    EXPECT_NE(message.find("inside #ifdef __cplusplus"), std::string::npos) << message;
}

TEST(ShaderLog, MesaNvidiaAndAmdFormsAreTranslated) {
    std::vector<std::string> paths = {"shaders/01/main.comp", "shaders/01/a.glsl"};
    EXPECT_EQ(course::translateShaderLog("1:7(12): error: syntax error", paths),
              "shaders/01/a.glsl:7: error: syntax error\n");
    EXPECT_EQ(course::translateShaderLog("0(12) : error C1008: undefined variable", paths),
              "shaders/01/main.comp:12: error C1008: undefined variable\n");
    EXPECT_EQ(course::translateShaderLog("ERROR: 1:3: 'x' : undeclared", paths),
              "shaders/01/a.glsl:3: ERROR: 'x' : undeclared\n");
    EXPECT_EQ(course::translateShaderLog("something else", paths), "something else\n");
    // Mesa reports string 0 whatever #line said; the line number carries the file.
    EXPECT_EQ(course::translateShaderLog("0:10004(12): error: `x' undeclared", paths),
              "shaders/01/a.glsl:4: error: `x' undeclared\n");
}
