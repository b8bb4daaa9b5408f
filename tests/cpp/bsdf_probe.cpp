// A chapter's BSDF code on the GPU, for the Python checks (tests/python/chapters/test_15_metals.py):
//
//   bsdf_probe SHADER_DIR PROBE_SHADER QUERIES ANSWERS [--buffer BINDING FILE]...
//
// compiles PROBE_SHADER (tests/data/bsdf/bsdf_probe.comp) with its #includes found in
// SHADER_DIR (a chapter's shaders, or a copy with a planted bug), runs it headless on
// the queries (raw float32, 20 a query) and writes the answers (raw float32, 24 each).
// Each --buffer binds FILE's bytes (raw, any whole number of 4-byte words: a table, a
// map's texels) as the storage buffer at BINDING, for probes of code that reads more
// than its queries (tests/data/environment/environment_probe.comp). The queries and
// the answers keep bindings 0 and 1.
// Exit codes as the chapters': 2 bad usage, 3 an unreadable file, 4 a GL problem.
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <iterator>
#include <string>
#include <vector>

#include "course/error.h"
#include "course/gl_context.h"
#include "course/gpu_buffer.h"
#include "course/shader_program.h"

namespace {

constexpr size_t kQueryFloats = 20, kAnswerFloats = 24;  // bsdf_probe.comp's structs

// A file's bytes as float32s: `group` of them at a time (a whole number of groups,
// at least one), `what` naming the group in the message if not.
std::vector<float> readFloats(const std::string& path, size_t group, const std::string& what) {
    std::ifstream file(path, std::ios::binary);
    if (!file) throw course::Failure(course::ExitCode::BadInput, path + ": cannot read");
    std::vector<char> bytes((std::istreambuf_iterator<char>(file)), {});
    if (!file.good() && !file.eof())
        throw course::Failure(course::ExitCode::BadInput, path + ": cannot read");
    if (bytes.empty() || bytes.size() % (group * sizeof(float)) != 0)
        throw course::Failure(course::ExitCode::BadInput,
                              path + ": not a whole number of " + what);
    std::vector<float> floats(bytes.size() / sizeof(float));
    std::memcpy(floats.data(), bytes.data(), bytes.size());
    return floats;
}

struct ExtraBuffer {  // --buffer BINDING FILE
    GLuint binding;
    std::string path;
};

int probe(const std::string& shaderDir, const std::string& probeShader,
          const std::string& queriesPath, const std::string& answersPath,
          const std::vector<ExtraBuffer>& extras) {
    course::Options options;
    options.backend = course::Backend::Egl;
    auto context = course::createGlContext(options, {4, 3}, "bsdf probe");
    std::string relative =
        std::filesystem::relative(std::filesystem::absolute(probeShader),
                                  std::filesystem::absolute(shaderDir)).string();
    course::ShaderProgram program = course::ShaderProgram::compute(shaderDir, relative);

    std::vector<float> queries = readFloats(queriesPath, kQueryFloats, "queries of 20 floats");
    const size_t count = queries.size() / kQueryFloats;
    auto queryBuffer = course::GpuBuffer::fromVector(queries);
    course::GpuBuffer answerBuffer(count * kAnswerFloats * sizeof(float));
    queryBuffer.bindStorage(0);
    answerBuffer.bindStorage(1);
    std::vector<course::GpuBuffer> extraBuffers;
    for (const ExtraBuffer& extra : extras) {
        extraBuffers.push_back(
            course::GpuBuffer::fromVector(readFloats(extra.path, 1, "4-byte words")));
        extraBuffers.back().bindStorage(extra.binding);
    }
    program.use();
    program.dispatchCovering(int(count));
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    std::vector<float> answers = answerBuffer.readAll<float>();

    std::ofstream out(answersPath, std::ios::binary);
    out.write(reinterpret_cast<const char*>(answers.data()),
              std::streamsize(answers.size() * sizeof(float)));
    if (!out) throw course::Failure(course::ExitCode::BadInput, answersPath + ": cannot write");
    return 0;
}

}  // namespace

constexpr const char* kUsage =
    "usage: bsdf_probe SHADER_DIR PROBE_SHADER QUERIES ANSWERS [--buffer BINDING FILE]...\n";

int main(int argc, char** argv) {
    std::vector<ExtraBuffer> extras;
    for (int i = 5; i < argc; i += 3) {
        char* end = nullptr;
        const long binding = i + 2 < argc ? std::strtol(argv[i + 1], &end, 10) : -1;
        // 0 and 1 are the queries' and the answers'.
        if (std::string(argv[i]) != "--buffer" || i + 2 >= argc || *end != '\0' ||
            binding < 2 || binding > 1000) {
            std::cerr << kUsage << "bsdf_probe: expected --buffer BINDING FILE (a binding "
                      << "of 2 or more), got '" << argv[i] << "'\n";
            return int(course::ExitCode::BadUsage);
        }
        extras.push_back({GLuint(binding), argv[i + 2]});
    }
    if (argc < 5) {
        std::cerr << kUsage;
        return int(course::ExitCode::BadUsage);
    }
    try {
        return probe(argv[1], argv[2], argv[3], argv[4], extras);
    } catch (const course::Failure& failure) {
        std::cerr << "bsdf_probe: " << failure.what() << "\n";
        return int(failure.code());
    }
}
