// Shader programs on a real (headless) GL context: errors point at file:line through
// #include, and hot reload keeps the last good program.
#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <thread>

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
        // Make sure the modification time moves even on coarse file systems.
        auto time = fs::last_write_time(folder / name);
        fs::last_write_time(folder / name, time + std::chrono::seconds(++edits));
    }
    std::unique_ptr<course::GlContext> context;
    fs::path root, folder;
    int edits = 0;
};

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
    EXPECT_FALSE(program.reloadIfChanged());  // nothing changed

    write("helper.glsl", "void helper() { broken }\n");  // a bad edit in an included file
    EXPECT_FALSE(program.reloadIfChanged());
    EXPECT_EQ(program.id(), first);
    EXPECT_TRUE(glIsProgram(program.id()));

    write("helper.glsl", "void helper() { float x = 1.0; }\n");  // fixed
    EXPECT_TRUE(program.reloadIfChanged());
    EXPECT_NE(program.id(), 0u);
    EXPECT_EQ(program.workGroupSize().x, 8);
}
