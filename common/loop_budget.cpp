#include "course/loop_budget.h"

#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <system_error>
#include <vector>

#include "course/error.h"
#include "course/gpu_buffer.h"
#include "course/log.h"
#include "course/portable_files.h"
#include "course/shader_program.h"

namespace fs = std::filesystem;

namespace course {
namespace {

// --- The probe -------------------------------------------------------------------------

// --8<-- [start:probe]
// The loop the probe runs: `iterations` steps of a xorshift generator from `seed`. No
// compiler can shorten it (there is no formula for the hundredth step but the hundred
// steps), and its result says how far it got: the CPU repeats the steps until it meets
// the same number.
const char* const kProbeLoop = R"(
uniform uint seed;
uniform uint iterations;
uint probeLoop() {
    uint x = seed;
    for (uint i = 0u; i < iterations; ++i) {
        x ^= x << 13u;
        x ^= x >> 17u;
        x ^= x << 5u;
    }
    return x;
}
)";

uint32_t xorshift(uint32_t x) {
    x ^= x << 13;
    x ^= x >> 17;
    x ^= x << 5;
    return x;
}

// How many steps from `seed` give `result`, if at most `probed` do (xorshift32 repeats
// only after 2^32 - 1 steps, so the answer is unique).
std::optional<long long> stepsTo(uint32_t result, uint32_t seed, long long probed) {
    uint32_t x = seed;
    for (long long steps = 0; steps <= probed; ++steps, x = xorshift(x))
        if (x == result) return steps;
    return std::nullopt;  // not a state of the loop: the shader wrote nothing
}
// --8<-- [end:probe]

constexpr uint32_t kProbeSeed = 2463534242u;  // any but 0, where xorshift stays

// One compute invocation; the result goes to a storage buffer at binding 0, whose
// previous binding is put back afterwards (as is the current program).
uint32_t runComputeProbe(long long iterations) {
    if (!GLAD_GL_VERSION_4_3)  // measureLoopLimit() asks for the fragment probe instead
        throw std::logic_error("the compute-shader loop probe needs OpenGL 4.3");
    GLint oldProgram = 0, oldBuffer = 0, oldGeneric = 0;
    GLint64 oldStart = 0, oldSize = 0;
    glGetIntegerv(GL_CURRENT_PROGRAM, &oldProgram);
    glGetIntegerv(GL_SHADER_STORAGE_BUFFER_BINDING, &oldGeneric);
    glGetIntegeri_v(GL_SHADER_STORAGE_BUFFER_BINDING, 0, &oldBuffer);
    glGetInteger64i_v(GL_SHADER_STORAGE_BUFFER_START, 0, &oldStart);
    glGetInteger64i_v(GL_SHADER_STORAGE_BUFFER_SIZE, 0, &oldSize);

    const std::string source = std::string("#version 430\nlayout(local_size_x = 1) in;\n"
                                           "layout(std430, binding = 0) writeonly buffer "
                                           "Result { uint result; };\n") +
                               kProbeLoop + "void main() { result = probeLoop(); }\n";
    GLuint program = buildProgramFromText({{GL_COMPUTE_SHADER, source}}, "loop probe");
    const uint32_t nothing = 0;  // no state of the loop: xorshift never reaches 0
    GpuBuffer result(sizeof(uint32_t), &nothing);
    result.bindStorage(0);
    glUseProgram(program);
    glUniform1ui(glGetUniformLocation(program, "seed"), kProbeSeed);
    glUniform1ui(glGetUniformLocation(program, "iterations"), GLuint(iterations));
    glDispatchCompute(1, 1, 1);
    uint32_t value = result.readAll<uint32_t>().at(0);

    glUseProgram(GLuint(oldProgram));
    glDeleteProgram(program);
    if (oldSize > 0)
        glBindBufferRange(GL_SHADER_STORAGE_BUFFER, 0, GLuint(oldBuffer), oldStart, oldSize);
    else
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, GLuint(oldBuffer));
    glBindBuffer(GL_SHADER_STORAGE_BUFFER, GLuint(oldGeneric));
    return value;
}

// GL 3.3 has no compute shaders: one fragment, drawn into a 1x1 integer texture. The
// framebuffer, viewport, program and bindings it changes are put back afterwards.
uint32_t runFragmentProbe(long long iterations) {
    GLint oldProgram = 0, oldDraw = 0, oldRead = 0, oldVao = 0, oldTexture = 0, oldPack = 0;
    GLint oldViewport[4] = {0, 0, 0, 0};
    glGetIntegerv(GL_CURRENT_PROGRAM, &oldProgram);
    glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &oldDraw);
    glGetIntegerv(GL_READ_FRAMEBUFFER_BINDING, &oldRead);
    glGetIntegerv(GL_VERTEX_ARRAY_BINDING, &oldVao);
    glGetIntegerv(GL_TEXTURE_BINDING_2D, &oldTexture);
    glGetIntegerv(GL_PIXEL_PACK_BUFFER_BINDING, &oldPack);
    glGetIntegerv(GL_VIEWPORT, oldViewport);

    // A triangle that covers the viewport, from the vertex index alone.
    const std::string vertex =
        "#version 330 core\nvoid main() {\n"
        "    vec2 corner = vec2((gl_VertexID & 1) * 4 - 1, (gl_VertexID & 2) * 2 - 1);\n"
        "    gl_Position = vec4(corner, 0.0, 1.0);\n}\n";
    const std::string fragment = std::string("#version 330 core\nout uvec4 result;\n") +
                                 kProbeLoop +
                                 "void main() { result = uvec4(probeLoop(), 0u, 0u, 0u); }\n";
    GLuint program = buildProgramFromText(
        {{GL_VERTEX_SHADER, vertex}, {GL_FRAGMENT_SHADER, fragment}}, "loop probe");
    GLuint texture = 0, framebuffer = 0, vertexArray = 0;
    glGenTextures(1, &texture);
    glBindTexture(GL_TEXTURE_2D, texture);
    glTexImage2D(GL_TEXTURE_2D, 0, GL_R32UI, 1, 1, 0, GL_RED_INTEGER, GL_UNSIGNED_INT,
                 nullptr);
    glGenFramebuffers(1, &framebuffer);
    glBindFramebuffer(GL_FRAMEBUFFER, framebuffer);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, texture, 0);
    const GLuint nothing[4] = {0, 0, 0, 0};  // xorshift never reaches 0
    glClearBufferuiv(GL_COLOR, 0, nothing);
    glGenVertexArrays(1, &vertexArray);
    glBindVertexArray(vertexArray);
    glViewport(0, 0, 1, 1);
    glUseProgram(program);
    glUniform1ui(glGetUniformLocation(program, "seed"), kProbeSeed);
    glUniform1ui(glGetUniformLocation(program, "iterations"), GLuint(iterations));
    glDrawArrays(GL_TRIANGLES, 0, 3);
    glBindBuffer(GL_PIXEL_PACK_BUFFER, 0);
    GLuint value = 0;
    glReadPixels(0, 0, 1, 1, GL_RED_INTEGER, GL_UNSIGNED_INT, &value);

    glUseProgram(GLuint(oldProgram));
    glBindVertexArray(GLuint(oldVao));
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, GLuint(oldDraw));
    glBindFramebuffer(GL_READ_FRAMEBUFFER, GLuint(oldRead));
    glBindTexture(GL_TEXTURE_2D, GLuint(oldTexture));
    glBindBuffer(GL_PIXEL_PACK_BUFFER, GLuint(oldPack));
    glViewport(oldViewport[0], oldViewport[1], oldViewport[2], oldViewport[3]);
    glDeleteVertexArrays(1, &vertexArray);
    glDeleteFramebuffers(1, &framebuffer);
    glDeleteTextures(1, &texture);
    glDeleteProgram(program);
    return value;
}

// --- Which GL, and the cache file ----------------------------------------------------

std::string glString(GLenum name) {
    const char* text = reinterpret_cast<const char*>(glGetString(name));
    std::string value = text ? text : "";
    for (char& c : value)
        if (c == '\t' || c == '\n' || c == '\r') c = ' ';  // one line, tab-separated
    return value;
}

const char* stageName(GLenum stage) {
    return stage == GL_FRAGMENT_SHADER ? "fragment" : "compute";
}

// vendor, renderer, version, stage: what the limit depends on.
std::string driverKey(GLenum stage) {
    return glString(GL_VENDOR) + "\t" + glString(GL_RENDERER) + "\t" +
           glString(GL_VERSION) + "\t" + stageName(stage);
}

fs::path cacheFile() {
    const fs::path folder = userCacheFolder();
    if (folder.empty()) return {};
    return folder / "gpu-ray-tracing-course" / "loop-limits.tsv";
}

// A line: vendor, renderer, version, stage, then the limit ("none" when every probed
// iteration ran) and the probed count. Anything else is no line of ours: ignored.
std::optional<std::pair<std::string, LoopLimit>> parseLine(const std::string& line) {
    std::vector<std::string> fields;
    std::stringstream in(line);
    for (std::string field; std::getline(in, field, '\t');) fields.push_back(field);
    if (fields.size() != 6 || (fields[3] != "compute" && fields[3] != "fragment"))
        return std::nullopt;
    auto number = [](const std::string& text) -> long long {
        if (text.empty() || text.size() > 12 ||
            text.find_first_not_of("0123456789") != std::string::npos)
            return -1;
        return std::stoll(text);
    };
    LoopLimit limit;
    limit.probed = number(fields[5]);
    limit.limited = fields[4] != "none";
    limit.iterations = limit.limited ? number(fields[4]) : limit.probed;
    if (limit.probed <= 0 || limit.iterations <= 0 || limit.iterations > limit.probed ||
        (limit.limited && limit.iterations == limit.probed))
        return std::nullopt;
    return std::make_pair(fields[0] + "\t" + fields[1] + "\t" + fields[2] + "\t" + fields[3],
                          limit);
}

std::vector<std::pair<std::string, LoopLimit>> readCache(const fs::path& file) {
    std::vector<std::pair<std::string, LoopLimit>> entries;
    std::ifstream in(file);
    for (std::string line; in && std::getline(in, line);)
        if (auto entry = parseLine(line)) entries.push_back(*entry);
    return entries;
}

// Rewrites the file with `key`'s new line: written under a temporary name and renamed,
// so that a reader never sees half of it. Returns false when that did not work.
bool writeCache(const fs::path& file, const std::string& key, const LoopLimit& limit) {
    std::error_code error;
    fs::create_directories(file.parent_path(), error);
    if (error) return false;
    const fs::path partial = file.string() + "." + std::to_string(processId()) + ".tmp";
    {
        std::ofstream out(partial);
        out << "# Shader loop limits measured by the GPU ray tracing course (loop_budget.h)"
               ": vendor, renderer, version, stage, limit (none: every probed iteration "
               "ran), probed iterations. Delete this file to measure again.\n";
        for (const auto& [otherKey, other] : readCache(file))
            if (otherKey != key)
                out << otherKey << "\t" << (other.limited ? std::to_string(other.iterations)
                                                          : "none")
                    << "\t" << other.probed << "\n";
        out << key << "\t" << (limit.limited ? std::to_string(limit.iterations) : "none")
            << "\t" << limit.probed << "\n";
        if (!out.flush()) {
            fs::remove(partial, error);
            return false;
        }
    }
    if (replaceFile(partial, file).empty()) return true;
    fs::remove(partial, error);
    return false;
}

}  // namespace

std::string LoopLimit::text() const {
    return limited ? std::to_string(iterations) + " loop iterations"
                   : "no limit up to " + std::to_string(probed) + " loop iterations";
}

LoopLimit measureLoopLimit(GLenum stage) {
    if (stage == GL_COMPUTE_SHADER && !GLAD_GL_VERSION_4_3) stage = GL_FRAGMENT_SHADER;
    const std::string key = driverKey(stage);
    const std::string driver = glString(GL_RENDERER) + ", OpenGL " + glString(GL_VERSION);
    static std::map<std::string, LoopLimit> known;  // this run's answers
    if (auto found = known.find(key); found != known.end()) return found->second;

    const fs::path file = cacheFile();
    if (!file.empty())
        for (auto& [cachedKey, cached] : readCache(file))
            if (cachedKey == key) {
                cached.driver = driver;
                logInfo(std::string("loop limit of ") + stageName(stage) + " shaders: " +
                        cached.text() + " (" + file.string() + ")");
                return known[key] = cached;
            }

    LoopLimit limit;
    limit.driver = driver;
    limit.probed = kLoopProbeIterations;
    const uint32_t result = stage == GL_FRAGMENT_SHADER ? runFragmentProbe(limit.probed)
                                                        : runComputeProbe(limit.probed);
    std::optional<long long> ran = stepsTo(result, kProbeSeed, limit.probed);
    if (!ran || *ran == 0) {
        // The shader wrote nothing: assume the worst known limit, and do not remember it.
        logWarning(std::string("the loop probe (") + stageName(stage) + " shader) gave no "
                   "answer on " + driver + "; assuming " +
                   std::to_string(kSmallestKnownLoopLimit) + " loop iterations");
        limit.limited = true;
        limit.iterations = kSmallestKnownLoopLimit;
        return known[key] = limit;
    }
    limit.limited = *ran < limit.probed;
    limit.iterations = *ran;
    logInfo(std::string("loop limit of ") + stageName(stage) + " shaders: " + limit.text() +
            " (measured on " + driver + ")");
    if (!file.empty() && !writeCache(file, key, limit))
        logInfo("could not write " + file.string() + ": the next run measures again");
    return known[key] = limit;
}

// --8<-- [start:check]
void checkLoopBudget(const LoopWork& work) {
    const long long iterations = static_cast<long long>(work.count * work.iterationsEach);
    if (iterations <= kSmallestKnownLoopLimit) return;  // fits every known GL: no probe
    const LoopLimit limit = measureLoopLimit(work.stage);
    if (!limit.limited || iterations <= limit.iterations) return;
    fail(ExitCode::GlProblem,
         work.file + ": " + std::to_string(work.count) + " " + work.things + " need up to " +
             std::to_string(iterations) + " loop iterations per pixel, but " + limit.driver +
             " ends a shader invocation after " + std::to_string(limit.iterations) +
             " (measured), silently, and the picture would be wrong; at most " +
             std::to_string(limit.iterations / static_cast<long long>(work.iterationsEach)) +
             " fit. " + work.wayOut);
}
// --8<-- [end:check]

}  // namespace course
