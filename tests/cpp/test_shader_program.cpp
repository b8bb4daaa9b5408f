// Shader programs on a real (headless) GL context: errors point at file:line through
// #include, hot reload keeps the last good program, every checkpoint's shared.h compiles
// as GLSL, and a uniform the program does not have is an error (this test builds
// common/shader_program.cpp as a debug build does, whatever the build type).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <functional>
#include <vector>

#include "course/error.h"
#include "course/gl_context.h"
#include "course/gpu_buffer.h"
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

// What shared.h keeps for C++ inside #ifdef __cplusplus (its own #include <glm/glm.hpp>
// among it) is passed over blank: the lines after it keep their numbers.
TEST_F(ShaderProgramTest, ErrorAfterACplusplusBlockHasTheRightLine) {
    write("shared.h", "#ifdef __cplusplus\n#include <cstddef>\n#include <glm/glm.hpp>\n"
                      "namespace gpu {\n#endif\nfloat broken = ;\n");
    write("main.comp", "#version 430\n#include \"shared.h\"\nlayout(local_size_x = 8) in;\n"
                       "void main() {}\n");
    try {
        course::ShaderProgram::compute(folder.string(), "main.comp");
        FAIL() << "compiled";
    } catch (const course::Failure& failure) {
        EXPECT_NE(std::string(failure.what()).find("shaders/99_test/shared.h:6:"),
                  std::string::npos)
            << failure.what();
    }
}

TEST_F(ShaderProgramTest, EveryCheckpointsSharedHeaderCompilesAsGlsl) {
    size_t headers = 0;
    for (const auto& entry : fs::directory_iterator(COURSE_SOURCE_DIR "/shaders")) {
        if (!fs::exists(entry.path() / "shared.h")) continue;
        SCOPED_TRACE(entry.path().string());
        ++headers;
        EXPECT_NO_THROW(course::ShaderProgram::compute(entry.path().string(),
                                                       "../../tests/data/shared_header.comp"));
    }
    EXPECT_GE(headers, 12u);
}

namespace {

const char* kUniformMain =
    "#version 430\nlayout(local_size_x = 8) in;\n"
    "uniform uint count;\n"
    "uniform uint unused;  // never read: the compiler removes it\n"
    "layout(std140, binding = 0) uniform Parameters { uint scale; };\n"
    "layout(std430, binding = 0) buffer Values { uint values[]; };\n"
    "void main() { values[gl_GlobalInvocationID.x] = count * scale; }\n";

std::string failureOf(const std::function<void()>& action) {
    try {
        action();
    } catch (const course::Failure& failure) {
        EXPECT_EQ(failure.code(), course::ExitCode::GlProblem);
        return failure.what();
    }
    ADD_FAILURE() << "no Failure thrown";
    return "";
}

}  // namespace

// A misspelt uniform name would leave the uniform at zero without a word: in a debug
// build, set() refuses a name the program's source does not declare, naming it and the
// program. A declared uniform the shader does not read (a starter's stub) is no error.
TEST_F(ShaderProgramTest, AnUndeclaredUniformIsAnErrorInDebugBuilds) {
    write("main.comp", kUniformMain);
    course::ShaderProgram program =
        course::ShaderProgram::compute(folder.string(), "main.comp");
    EXPECT_NO_THROW(program.set("count", 3u));
    EXPECT_TRUE(program.hasUniform("count"));
    EXPECT_FALSE(program.hasUniform("cuont"));
    EXPECT_FALSE(program.hasUniform("unused"));  // declared, but removed by the compiler
    EXPECT_NO_THROW(program.set("unused", 1u));
    EXPECT_EQ(failureOf([&] { program.set("cuont", 3u); }),
              "shaders/99_test/main.comp: no uniform 'cuont' to set: the shader does not "
              "declare it (misspelt?)");
    EXPECT_NE(failureOf([&] { program.set("scale", 3u); }).find("'scale'"),  // a block's
              std::string::npos);
}

TEST_F(ShaderProgramTest, UniformBlocksAreConnectedByNameAndCheckedInDebugBuilds) {
    write("main.comp", kUniformMain);
    course::ShaderProgram program =
        course::ShaderProgram::compute(folder.string(), "main.comp");
    EXPECT_NO_THROW(program.bindUniformBlock("Parameters", 3));
    GLint binding = -1;
    glGetActiveUniformBlockiv(program.id(), glGetUniformBlockIndex(program.id(), "Parameters"),
                              GL_UNIFORM_BLOCK_BINDING, &binding);
    EXPECT_EQ(binding, 3);
    EXPECT_NE(failureOf([&] { program.bindUniformBlock("Parameter", 0); })
                  .find("shaders/99_test/main.comp: no uniform block 'Parameter'"),
              std::string::npos);
}

// The values a uniform block gives a dispatch: a GpuBuffer bound with bindUniform.
TEST_F(ShaderProgramTest, AUniformBufferFeedsTheBlock) {
    write("main.comp", kUniformMain);
    course::ShaderProgram program =
        course::ShaderProgram::compute(folder.string(), "main.comp");
    program.set("count", 3u);
    const uint32_t scale[4] = {5u, 0u, 0u, 0u};
    course::GpuBuffer parameters(sizeof scale, scale);
    parameters.bindUniform(0);
    course::GpuBuffer values(8 * sizeof(uint32_t));
    values.bindStorage(0);
    program.dispatchCovering(8);
    EXPECT_EQ(values.readAll<uint32_t>(), std::vector<uint32_t>(8, 15u));
}
