// What a GPU's driver may do differently from llvmpipe, on a headless context here:
// limits asked at run time (lowered with COURSE_GL_LIMIT_*, as a smaller GL would give
// them), the search for a context that does not stop at a device with an older GL,
// and buffer textures that hand back NaN and denormal bit patterns unchanged.
#include <gtest/gtest.h>

#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <vector>

#include "course/context_search.h"
#include "course/error.h"
#include "course/gl_context.h"
#include "course/gpu_buffer.h"
#include "course/gpu_limits.h"
#include "course/shader_program.h"
#include "scratch_folder.h"

namespace fs = std::filesystem;

namespace {

// --- what a source declares (the explanation of a failed link) ---

TEST(DeclaredBlocks, CountsStorageBlocksAndResolvesDefinedBindings) {
    const std::string source = R"(#define SPHERES_BINDING 3
#define NODES_BINDING 19
layout(std430, binding = 0) buffer Image { vec4 pixels[]; };
layout(std430, binding = SPHERES_BINDING) readonly buffer Spheres { vec4 spheres[]; };
layout(std430, binding = NODES_BINDING) readonly restrict buffer Nodes { vec4 nodes[]; };
// layout(std430, binding = 40) buffer Commented { vec4 never[]; };
/* layout(std430, binding = 41) buffer AlsoCommented { vec4 never[]; }; */
layout(std140, binding = 2) uniform Camera { vec4 eye; };
)";
    const course::DeclaredBlocks declared = course::declaredBlocks(source);
    EXPECT_EQ(declared.storageBlocks, 3);
    EXPECT_EQ(declared.highestStorageBinding, 19);
}

// --- the search for a context ---

class FakeContext : public course::GlContext {
public:
    explicit FakeContext(std::string name) : name_(std::move(name)) {}
    std::string backendName() const override { return name_; }

private:
    std::string name_;
};

course::ContextCandidate tooOld(const std::string& name) {
    return {name, [](std::string&) -> std::unique_ptr<course::GlContext> {
                throw course::GlTooOld("offers OpenGL 3.1 only");
            }};
}
course::ContextCandidate failing(const std::string& name) {
    return {name, [name](std::string& reason) -> std::unique_ptr<course::GlContext> {
                reason = name + ": eglInitialize failed";
                return nullptr;
            }};
}
course::ContextCandidate working(const std::string& name) {
    return {name, [name](std::string&) -> std::unique_ptr<course::GlContext> {
                return std::make_unique<FakeContext>(name);
            }};
}

TEST(ContextSearch, ADeviceWithAnOlderGlDoesNotEndTheSearch) {
    std::string reasons;
    auto context = course::firstWorkingContext(
        {tooOld("egl device 0 (old)"), failing("egl device 1"), working("egl device 2")},
        reasons);
    ASSERT_TRUE(context);
    EXPECT_EQ(context->backendName(), "egl device 2");
    EXPECT_NE(reasons.find("egl device 0 (old): offers OpenGL 3.1 only"), std::string::npos);
}

TEST(ContextSearch, WhenNothingWorksTooOldIsTheAnswerIfAnyoneSaidIt) {
    std::string reasons;
    EXPECT_THROW(course::firstWorkingContext({failing("a"), tooOld("b"), failing("c")}, reasons),
                 course::GlTooOld);
    EXPECT_EQ(course::firstWorkingContext({failing("a"), failing("c")}, reasons), nullptr);
    EXPECT_NE(reasons.find("c: eglInitialize failed"), std::string::npos);
}

// --- on a real context ---

class GpuLimitsTest : public ::testing::Test {
protected:
    void SetUp() override {
        course::Options options;
        options.backend = course::Backend::Egl;
        context = course::createGlContext(options, {4, 3}, "test");
        folder = scratchFolder("course_limits_test_");
    }
    void TearDown() override {
        unsetenv("COURSE_GL_LIMIT_MAX_COMPUTE_SHADER_STORAGE_BLOCKS");
        fs::remove_all(folder);
    }
    course::ShaderProgram compute(const std::string& text) {
        std::ofstream(folder / "main.comp") << text;
        return course::ShaderProgram::compute(folder.string(), "main.comp");
    }
    std::unique_ptr<course::GlContext> context;
    fs::path folder;
};

const char* kThreeBlocks = R"(#version 430
layout(local_size_x = 64) in;
layout(std430, binding = 0) readonly buffer A { uint a[]; };
layout(std430, binding = 1) readonly buffer B { uint b[]; };
layout(std430, binding = 2) writeonly buffer C { uint c[]; };
void main() { uint i = gl_GlobalInvocationID.x; c[i] = a[i] + b[i]; }
)";

TEST_F(GpuLimitsTest, AProgramNeedingMoreStorageBlocksThanTheGlGivesIsExit4) {
    EXPECT_NO_THROW(compute(kThreeBlocks));
    setenv("COURSE_GL_LIMIT_MAX_COMPUTE_SHADER_STORAGE_BLOCKS", "2", 1);
    try {
        compute(kThreeBlocks);
        FAIL() << "linked with 3 storage blocks where 2 are allowed";
    } catch (const course::Failure& failure) {
        EXPECT_EQ(failure.code(), course::ExitCode::GlProblem);
        EXPECT_NE(std::string(failure.what())
                      .find("its compute shader uses 3 storage blocks, but this GL allows 2 "
                            "(GL_MAX_COMPUTE_SHADER_STORAGE_BLOCKS"),
                  std::string::npos)
            << failure.what();
    }
    setenv("COURSE_GL_LIMIT_MAX_COMPUTE_SHADER_STORAGE_BLOCKS", "3", 1);
    EXPECT_NO_THROW(compute(kThreeBlocks));
}

TEST_F(GpuLimitsTest, TheLinkFailureExplanationNamesTheLimit) {
    setenv("COURSE_GL_LIMIT_MAX_COMPUTE_SHADER_STORAGE_BLOCKS", "2", 1);
    const std::string why = course::explainLinkFailure({{GL_COMPUTE_SHADER, kThreeBlocks}});
    EXPECT_NE(why.find("declares 3 storage blocks, and this GL allows 2"), std::string::npos)
        << why;
    unsetenv("COURSE_GL_LIMIT_MAX_COMPUTE_SHADER_STORAGE_BLOCKS");
    EXPECT_EQ(course::explainLinkFailure({{GL_COMPUTE_SHADER, kThreeBlocks}}), "");
}

// Bit patterns a float texel could lose: NaNs (0xFFFFFFFF is the course's "none"), the
// smallest and largest denormals (small indices), negative zero, infinity.
TEST_F(GpuLimitsTest, ABufferTextureHandsBackNanAndDenormalPatternsBitForBit) {
    const std::vector<uint32_t> patterns = {
        0xFFFFFFFFu, 0x7FC00001u, 0xFF800001u, 0x7F800001u,  // NaNs, quiet and signalling
        0x00000001u, 0x00000002u, 0x00000003u, 0x007FFFFFu,  // denormals: indices 1, 2, 3
        0x80000001u, 0x80000000u, 0x7F800000u, 0x00000000u,  // -denormal, -0, infinity, 0
        0x3F800000u, 0x12345678u, 0xDEADBEEFu, 0x00800000u};
    course::GpuBuffer input(patterns.size() * 4, patterns.data());
    course::GpuBuffer output(patterns.size() * 4);
    course::BufferTexture texels(input, "the patterns");
    course::ShaderProgram copy = compute(R"(#version 430
layout(local_size_x = 1) in;
layout(binding = 0) uniform usamplerBuffer texels;
layout(std430, binding = 1) writeonly buffer Copy { uvec4 copied[]; };
void main() {
    uint i = gl_GlobalInvocationID.x;
    copied[i] = texelFetch(texels, int(i));
}
)");
    texels.bind(0);
    output.bindStorage(1);
    copy.dispatchCovering(int(patterns.size() / 4));
    std::vector<uint32_t> copied(patterns.size());
    output.read(copied.data(), copied.size() * 4);
    for (size_t i = 0; i < patterns.size(); ++i)
        EXPECT_EQ(copied[i], patterns[i]) << "texel word " << i;
}

}  // namespace
