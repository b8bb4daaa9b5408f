// Shader programs on a real (headless) GL context: errors point at file:line through
// #include, and hot reload keeps the last good program.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "course/error.h"
#include "course/gl_context.h"
#include "course/shader_program.h"

namespace fs = std::filesystem;

namespace {

class ShaderProgramTest : public ::testing::Test {
protected:
    void SetUp() override {
        course::Options options;
        options.backend = course::Backend::Egl;
        context = course::createGlContext(options, {4, 3}, "test");
        root = fs::temp_directory_path() /
               ("course_program_test_" +
                std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
        fs::remove_all(root);
        folder = root / "shaders" / "99_test";
        fs::create_directories(folder);
    }
    void TearDown() override { fs::remove_all(root); }
    void write(const std::string& name, const std::string& text) {
        std::ofstream(folder / name) << text;
    }
    std::unique_ptr<course::GlContext> context;
    fs::path root, folder;
};

using Reload = course::ShaderProgram::Reload;

const char* kGoodMain = "#version 430\n#include \"helper.glsl\"\n"
                        "layout(local_size_x = 8) in;\nvoid main() { helper(); }\n";

}  // namespace

TEST_F(ShaderProgramTest, ErrorInIncludedFileNamesThatFileAndLine) {
    write("main.comp", kGoodMain);
    write("helper.glsl", "// a helper\n\nvoid helper() {\n    float x = nonsense;\n}\n");
    try {
        course::ShaderProgram::compute(folder.string(), "main.comp");
        FAIL() << "compiled";
    } catch (const course::Failure& failure) {
        EXPECT_EQ(failure.code(), course::ExitCode::GlProblem);
        EXPECT_NE(std::string(failure.what()).find("shaders/99_test/helper.glsl:4:"),
                  std::string::npos)
            << failure.what();
    }
}

TEST_F(ShaderProgramTest, ErrorAfterAnIncludeHasTheRightLine) {
    write("helper.glsl", "void helper() {}\n");
    write("main.comp", "#version 430\n#include \"helper.glsl\"\nlayout(local_size_x = 8) in;\n"
                       "void main() {\n    helper();\n    int broken = ;\n}\n");
    try {
        course::ShaderProgram::compute(folder.string(), "main.comp");
        FAIL() << "compiled";
    } catch (const course::Failure& failure) {
        EXPECT_NE(std::string(failure.what()).find("shaders/99_test/main.comp:6:"),
                  std::string::npos)
            << failure.what();
    }
}

TEST_F(ShaderProgramTest, HotReloadKeepsTheLastGoodProgram) {
    write("main.comp", kGoodMain);
    write("helper.glsl", "void helper() {}\n");
    course::ShaderProgram program = course::ShaderProgram::compute(folder.string(), "main.comp");
    GLuint first = program.id();
    EXPECT_EQ(program.reloadIfChanged(), Reload::Unchanged);
    EXPECT_EQ(program.watchedFiles(), (std::vector<std::string>{
                                          "shaders/99_test/main.comp",
                                          "shaders/99_test/helper.glsl"}));

    write("helper.glsl", "void helper() { broken }\n");  // a bad edit in an included file
    EXPECT_EQ(program.reloadIfChanged(), Reload::KeptLastGood);
    EXPECT_EQ(program.id(), first);
    EXPECT_TRUE(glIsProgram(program.id()));
    EXPECT_EQ(program.reloadIfChanged(), Reload::Unchanged);  // each version tried once

    write("helper.glsl", "void helper() { float x = 1.0; }\n");  // fixed
    EXPECT_EQ(program.reloadIfChanged(), Reload::Reloaded);
    EXPECT_NE(program.id(), 0u);
    EXPECT_EQ(program.workGroupSize().x, 8);
}

TEST_F(ShaderProgramTest, AnEditKeepingSizeAndModificationTimeIsSeen) {
    // Two saves within the file system's timestamp granularity (a few milliseconds on
    // Linux, two seconds on FAT) and of the same length look alike to stat().
    write("main.comp", kGoodMain);
    write("helper.glsl", "void helper() { float x = 1.0; }\n");
    course::ShaderProgram program = course::ShaderProgram::compute(folder.string(), "main.comp");
    auto time = fs::last_write_time(folder / "helper.glsl");
    write("helper.glsl", "void helper() { float x = 2.0; }\n");
    fs::last_write_time(folder / "helper.glsl", time);
    EXPECT_EQ(program.reloadIfChanged(), Reload::Reloaded);
}

TEST_F(ShaderProgramTest, ANewIncludeIsWatchedEvenWhenItFailed) {
    write("main.comp", kGoodMain);
    write("helper.glsl", "void helper() {}\n");
    course::ShaderProgram program = course::ShaderProgram::compute(folder.string(), "main.comp");
    // A new #include of a file not written yet: the editor saved the includer first.
    write("helper.glsl", "#include \"more.glsl\"\nvoid helper() { more(); }\n");
    EXPECT_EQ(program.reloadIfChanged(), Reload::KeptLastGood);
    EXPECT_EQ(program.reloadIfChanged(), Reload::Unchanged);
    write("more.glsl", "void more() {}\n");
    EXPECT_EQ(program.reloadIfChanged(), Reload::Reloaded);
    EXPECT_EQ(program.watchedFiles().back(), "shaders/99_test/more.glsl");
}
