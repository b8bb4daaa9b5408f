// A chapter's BSDF code on the GPU, for the Python checks (tests/python/test_15_metals.py):
//
//   bsdf_probe SHADER_DIR PROBE_SHADER QUERIES ANSWERS
//
// compiles PROBE_SHADER (tests/data/bsdf/bsdf_probe.comp) with its #includes found in
// SHADER_DIR (a chapter's shaders, or a copy with a planted bug), runs it headless on
// the queries (raw float32, 20 a query) and writes the answers (raw float32, 24 each).
// Exit codes as the chapters': 2 bad usage, 3 an unreadable file, 4 a GL problem.
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <iterator>
#include <vector>

#include "course/error.h"
#include "course/gl_context.h"
#include "course/gpu_buffer.h"
#include "course/shader_program.h"

namespace {

constexpr size_t kQueryFloats = 20, kAnswerFloats = 24;  // bsdf_probe.comp's structs

std::vector<float> readFloats(const std::string& path) {
    std::ifstream file(path, std::ios::binary);
    std::vector<char> bytes((std::istreambuf_iterator<char>(file)), {});
    if (!file.good() && !file.eof())
        throw course::Failure(course::ExitCode::BadInput, path + ": cannot read");
    if (bytes.empty() || bytes.size() % (kQueryFloats * sizeof(float)) != 0)
        throw course::Failure(course::ExitCode::BadInput,
                              path + ": not a whole number of queries of 20 floats");
    std::vector<float> floats(bytes.size() / sizeof(float));
    std::memcpy(floats.data(), bytes.data(), bytes.size());
    return floats;
}

int probe(const std::string& shaderDir, const std::string& probeShader,
          const std::string& queriesPath, const std::string& answersPath) {
    course::Options options;
    options.backend = course::Backend::Egl;
    auto context = course::createGlContext(options, {4, 3}, "bsdf probe");
    std::string relative =
        std::filesystem::relative(std::filesystem::absolute(probeShader),
                                  std::filesystem::absolute(shaderDir)).string();
    course::ShaderProgram program = course::ShaderProgram::compute(shaderDir, relative);

    std::vector<float> queries = readFloats(queriesPath);
    const size_t count = queries.size() / kQueryFloats;
    auto queryBuffer = course::GpuBuffer::fromVector(queries);
    course::GpuBuffer answerBuffer(count * kAnswerFloats * sizeof(float));
    queryBuffer.bindStorage(0);
    answerBuffer.bindStorage(1);
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

int main(int argc, char** argv) {
    if (argc != 5) {
        std::cerr << "usage: bsdf_probe SHADER_DIR PROBE_SHADER QUERIES ANSWERS\n";
        return int(course::ExitCode::BadUsage);
    }
    try {
        return probe(argv[1], argv[2], argv[3], argv[4]);
    } catch (const course::Failure& failure) {
        std::cerr << "bsdf_probe: " << failure.what() << "\n";
        return int(failure.code());
    }
}
