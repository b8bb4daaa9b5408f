#include "course/shader_program.h"

#include <cstdio>
#include <cstdlib>
#include <regex>
#include <utility>

#include <glm/gtc/type_ptr.hpp>

#include "course/error.h"
#include "course/gpu_limits.h"
#include "course/gpu_watchdog.h"
#include "course/shader_source.h"

namespace course {
namespace {

std::string infoLog(GLuint object, bool isProgram) {
    GLint length = 0;
    isProgram ? glGetProgramiv(object, GL_INFO_LOG_LENGTH, &length)
              : glGetShaderiv(object, GL_INFO_LOG_LENGTH, &length);
    std::string log(length > 0 ? size_t(length) : 0, '\0');
    if (length > 0)
        isProgram ? glGetProgramInfoLog(object, length, nullptr, log.data())
                  : glGetShaderInfoLog(object, length, nullptr, log.data());
    while (!log.empty() && (log.back() == '\0' || log.back() == '\n')) log.pop_back();
    return log;
}

GLuint compileStage(GLenum type, const std::string& text,
                    const std::vector<std::string>& shownPaths) {
    GLuint shader = glCreateShader(type);
    const char* source = text.c_str();
    glShaderSource(shader, 1, &source, nullptr);
    glCompileShader(shader);
    GLint ok = GL_FALSE;
    glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
    if (!ok) {
        std::string log = translateShaderLog(infoLog(shader, false), shownPaths);
        glDeleteShader(shader);
        fail(ExitCode::GlProblem, "shader compile failed:\n" + log);
    }
    return shader;
}

// Links the compiled `shaders` (of `stages`: type and source text), then checks what
// the program uses against this GL's limits (course/gpu_limits.h).
GLuint linkProgram(const std::vector<GLuint>& shaders,
                   const std::vector<std::pair<GLenum, std::string>>& stages,
                   const std::string& label) {
    GLuint program = glCreateProgram();
    for (GLuint shader : shaders) glAttachShader(program, shader);
    glLinkProgram(program);
    for (GLuint shader : shaders) glDeleteShader(shader);  // the program keeps them
    GLint ok = GL_FALSE;
    glGetProgramiv(program, GL_LINK_STATUS, &ok);
    if (!ok) {
        std::string log = infoLog(program, true);
        glDeleteProgram(program);
        // A driver's words for a limit it enforces vary; the course's come first.
        const std::string why = explainLinkFailure(stages);
        fail(ExitCode::GlProblem, label + ": shader link failed:\n" +
                                      (why.empty() ? log : why + "the driver says:\n" + log));
    }
    std::vector<GLenum> types;
    for (const auto& stage : stages) types.push_back(stage.first);
    try {
        checkProgramLimits(program, types, label);
    } catch (...) {
        glDeleteProgram(program);
        throw;
    }
    return program;
}

// COURSE_SHADER_DUMP=DIR: each stage's text as the GL gets it (every #include
// expanded, generated files in), as DIR/NN-name, for a reference compiler
// (glslangValidator, tests/python/chapters/test_glslang.py) or a driver's bug report.
void dumpForReview(const std::string& shownPath, const std::string& text) {
    const char* folder = std::getenv("COURSE_SHADER_DUMP");
    if (!folder || !*folder) return;
    static int dumped = 0;
    char number[16];
    std::snprintf(number, sizeof number, "%03d-", ++dumped);
    const std::string name = shownPath.substr(shownPath.find_last_of('/') + 1);
    const std::string path = std::string(folder) + "/" + number + name;
    std::FILE* file = std::fopen(path.c_str(), "wb");
    if (!file) fail(ExitCode::BadUsage, "COURSE_SHADER_DUMP: cannot write " + path);
    std::fwrite(text.data(), 1, text.size(), file);
    std::fclose(file);
}

}  // namespace

GLuint buildProgramFromText(const std::vector<std::pair<GLenum, std::string>>& stages,
                            const std::string& label) {
    std::vector<GLuint> shaders;
    for (const auto& [type, text] : stages) shaders.push_back(compileStage(type, text, {label}));
    return linkProgram(shaders, stages, label);
}

namespace {

// Each file once, as its first read found it: if it changed between two reads, the
// next check sees the difference and builds again.
std::vector<ShaderFile> withoutRepeats(const std::vector<ShaderFile>& files) {
    std::vector<ShaderFile> unique;
    for (const ShaderFile& file : files) {
        bool seen = false;
        for (const ShaderFile& kept : unique) seen = seen || kept.path == file.path;
        if (!seen) unique.push_back(file);
    }
    return unique;
}

}  // namespace

ShaderProgram::ShaderProgram(std::string shaderDir, std::vector<ShaderStage> stages,
                             GeneratedFiles generated)
    : shaderDir_(std::move(shaderDir)), stages_(std::move(stages)),
      generated_(std::move(generated)) {
    std::vector<ShaderFile> filesRead;
    id_ = build(filesRead, sources_);
    watched_ = withoutRepeats(filesRead);
}

ShaderProgram::~ShaderProgram() {
    if (id_) glDeleteProgram(id_);
}

ShaderProgram::ShaderProgram(ShaderProgram&& other) noexcept
    : id_(std::exchange(other.id_, 0)), shaderDir_(std::move(other.shaderDir_)),
      stages_(std::move(other.stages_)), generated_(std::move(other.generated_)),
      watched_(std::move(other.watched_)),
      sources_(std::move(other.sources_)) {}

ShaderProgram& ShaderProgram::operator=(ShaderProgram&& other) noexcept {
    if (this != &other) {
        if (id_) glDeleteProgram(id_);
        id_ = std::exchange(other.id_, 0);
        shaderDir_ = std::move(other.shaderDir_);
        stages_ = std::move(other.stages_);
        generated_ = std::move(other.generated_);
        watched_ = std::move(other.watched_);
        sources_ = std::move(other.sources_);
    }
    return *this;
}

GLuint ShaderProgram::build(std::vector<ShaderFile>& filesRead, std::string& sources) const {
    std::vector<GLuint> shaders;
    std::vector<std::pair<GLenum, std::string>> texts;
    std::string label;
    sources.clear();
    try {
        for (const ShaderStage& stage : stages_) {
            ShaderSource source = loadShaderSource(shaderDir_, stage.fileName, &filesRead,
                                                   generated_);
            sources += source.text;
            texts.emplace_back(stage.type, source.text);
            dumpForReview(source.shownPaths.front(), source.text);
            label += (label.empty() ? "" : " + ") + source.shownPaths.front();
            shaders.push_back(compileStage(stage.type, source.text, source.shownPaths));
        }
    } catch (...) {
        for (GLuint shader : shaders) glDeleteShader(shader);
        throw;
    }
    return linkProgram(shaders, texts, label);
}

std::vector<std::string> ShaderProgram::watchedFiles() const {
    std::vector<std::string> shown;
    for (const ShaderFile& file : watched_) shown.push_back(file.shownPath);
    return shown;
}

ShaderProgram::Reload ShaderProgram::reloadIfChanged() {
    std::vector<std::optional<std::string>> onDisk;
    bool changed = false;
    for (const ShaderFile& file : watched_) {
        onDisk.push_back(readShaderFile(file.path));
        changed = changed || onDisk.back() != file.text;
    }
    if (!changed) return Reload::Unchanged;

    // The program is named by its first file, the one the chapter asked for.
    const std::string name = watched_.front().shownPath;
    std::vector<ShaderFile> filesRead;
    try {
        std::string sources;
        GLuint rebuilt = build(filesRead, sources);
        glDeleteProgram(id_);
        id_ = rebuilt;
        sources_ = std::move(sources);
        watched_ = withoutRepeats(filesRead);  // an #include may have come or gone
        std::fprintf(stderr, "reloaded %s\n", name.c_str());
        return Reload::Reloaded;
    } catch (const Failure& failure) {
        // Watch what this attempt read, a new #include too, and the files it did not
        // get to as they were before it: each saved version is tried once.
        for (size_t i = 0; i < watched_.size(); ++i)
            filesRead.push_back({watched_[i].path, watched_[i].shownPath, onDisk[i]});
        watched_ = withoutRepeats(filesRead);
        std::fprintf(stderr, "%s\nkept the last good program of %s\n", failure.what(),
                     name.c_str());
        return Reload::KeptLastGood;
    }
}

// GL 4.1 sets a uniform of any program (glProgramUniform*). Before 4.1, on the GL 3.3
// appendix's contexts, only the program in use takes uniforms (glUniform*): this puts
// the program in use for the call and then puts back the one that was, so both ways
// leave the same state behind.
template <class Direct, class InUse>
static void setUniform(GLuint program, GLint location, Direct direct, InUse inUse) {
    if (GLAD_GL_VERSION_4_1) return direct(program, location);
    GLint current = 0;
    glGetIntegerv(GL_CURRENT_PROGRAM, &current);
    if (GLuint(current) != program) glUseProgram(program);
    inUse(location);
    if (GLuint(current) != program) glUseProgram(GLuint(current));
}

bool ShaderProgram::hasUniform(const char* name) const {
    return glGetUniformLocation(id_, name) != -1;
}

// "shaders/NN_name/path.comp", for messages: the program is named by its first file.
std::string ShaderProgram::name() const {
    return watched_.empty() ? std::string("a shader program") : watched_.front().shownPath;
}

#ifndef NDEBUG
namespace {

// Whether the source declares the uniform `name` ("count", "camera.eye"): its first
// word follows `uniform` in a declaration, and every member name after it is a word of
// the source (a struct's member). Words, not a parser: it is there to catch typos.
bool declaresUniform(const std::string& source, const std::string& name) {
    std::vector<std::string> words;
    static const std::regex word(R"([A-Za-z_]\w*)");
    for (auto it = std::sregex_iterator(name.begin(), name.end(), word);
         it != std::sregex_iterator(); ++it)
        words.push_back(it->str());
    if (words.empty()) return false;
    if (!std::regex_search(source, std::regex(R"(\buniform\b[^;{}]*\b)" + words[0] + R"(\b)")))
        return false;
    for (size_t i = 1; i < words.size(); ++i)
        if (!std::regex_search(source, std::regex(R"(\b)" + words[i] + R"(\b)")))
            return false;
    return true;
}

}  // namespace
#endif

GLint ShaderProgram::uniformLocation(const char* name) const {
    const GLint location = glGetUniformLocation(id_, name);
#ifndef NDEBUG
    // A typo in a name would otherwise leave the uniform at zero, silently. A uniform
    // that is declared but not read (the compiler removed it) is no mistake.
    if (location == -1 && !declaresUniform(sources_, name))
        fail(ExitCode::GlProblem, this->name() + ": no uniform '" + name +
                                      "' to set: the shader does not declare it (misspelt?)");
#endif
    return location;
}

void ShaderProgram::bindUniformBlock(const char* blockName, GLuint binding) const {
    const GLuint block = glGetUniformBlockIndex(id_, blockName);
    if (block == GL_INVALID_INDEX) {
#ifndef NDEBUG
        if (!declaresUniform(sources_, blockName))
            fail(ExitCode::GlProblem, name() + ": no uniform block '" + blockName +
                                          "' to connect: the shader does not declare it "
                                          "(misspelt?)");
#endif
        return;
    }
    glUniformBlockBinding(id_, block, binding);
}

void ShaderProgram::set(const char* name, int value) const {
    setUniform(id_, uniformLocation(name),
               [&](GLuint p, GLint at) { glProgramUniform1i(p, at, value); },
               [&](GLint at) { glUniform1i(at, value); });
}
void ShaderProgram::set(const char* name, unsigned value) const {
    setUniform(id_, uniformLocation(name),
               [&](GLuint p, GLint at) { glProgramUniform1ui(p, at, value); },
               [&](GLint at) { glUniform1ui(at, value); });
}
void ShaderProgram::set(const char* name, float value) const {
    setUniform(id_, uniformLocation(name),
               [&](GLuint p, GLint at) { glProgramUniform1f(p, at, value); },
               [&](GLint at) { glUniform1f(at, value); });
}
void ShaderProgram::set(const char* name, const glm::vec2& value) const {
    const float* v = glm::value_ptr(value);
    setUniform(id_, uniformLocation(name),
               [&](GLuint p, GLint at) { glProgramUniform2fv(p, at, 1, v); },
               [&](GLint at) { glUniform2fv(at, 1, v); });
}
void ShaderProgram::set(const char* name, const glm::vec3& value) const {
    const float* v = glm::value_ptr(value);
    setUniform(id_, uniformLocation(name),
               [&](GLuint p, GLint at) { glProgramUniform3fv(p, at, 1, v); },
               [&](GLint at) { glUniform3fv(at, 1, v); });
}
void ShaderProgram::set(const char* name, const glm::vec4& value) const {
    const float* v = glm::value_ptr(value);
    setUniform(id_, uniformLocation(name),
               [&](GLuint p, GLint at) { glProgramUniform4fv(p, at, 1, v); },
               [&](GLint at) { glUniform4fv(at, 1, v); });
}
void ShaderProgram::set(const char* name, const glm::ivec2& value) const {
    const int* v = glm::value_ptr(value);
    setUniform(id_, uniformLocation(name),
               [&](GLuint p, GLint at) { glProgramUniform2iv(p, at, 1, v); },
               [&](GLint at) { glUniform2iv(at, 1, v); });
}
void ShaderProgram::set(const char* name, const glm::uvec2& value) const {
    const unsigned* v = glm::value_ptr(value);
    setUniform(id_, uniformLocation(name),
               [&](GLuint p, GLint at) { glProgramUniform2uiv(p, at, 1, v); },
               [&](GLint at) { glUniform2uiv(at, 1, v); });
}

glm::ivec3 ShaderProgram::workGroupSize() const {
    GLint size[3] = {1, 1, 1};
    glGetProgramiv(id_, GL_COMPUTE_WORK_GROUP_SIZE, size);
    return {size[0], size[1], size[2]};
}

void ShaderProgram::dispatchCovering(int invocationsX, int invocationsY,
                                     int invocationsZ) const {
    glm::ivec3 group = workGroupSize();
    auto groupsFor = [](int invocations, int size) { return (invocations + size - 1) / size; };
    const int groups[3] = {groupsFor(invocationsX, group.x), groupsFor(invocationsY, group.y),
                           groupsFor(invocationsZ, group.z)};
    checkWorkGroupCount(groups, name());
    compileBeforeFirstDispatch();
    use();
    glDispatchCompute(groups[0], groups[1], groups[2]);
    gpuStepQueued();  // the watchdog's sign of progress
}

// A dispatch of zero groups does no work, but a GL that compiles at first use compiles
// for it. The count is read from a buffer, so that the GL cannot skip the call before
// reaching the driver, as it may for glDispatchCompute(0, 0, 0).
void ShaderProgram::compileBeforeFirstDispatch() const {
    if (compiledFor_ == id_) return;
    compiledFor_ = id_;
    GLint indirectBefore = 0;
    glGetIntegerv(GL_DISPATCH_INDIRECT_BUFFER_BINDING, &indirectBefore);
    const GLuint noGroups[3] = {0, 0, 0};
    GLuint command = 0;
    glGenBuffers(1, &command);
    glBindBuffer(GL_DISPATCH_INDIRECT_BUFFER, command);
    glBufferData(GL_DISPATCH_INDIRECT_BUFFER, sizeof noGroups, noGroups, GL_STATIC_DRAW);
    {
        ShaderCompileAllowance compiling(name());
        use();
        glDispatchComputeIndirect(0);  // llvmpipe compiles inside the call
    }
    glBindBuffer(GL_DISPATCH_INDIRECT_BUFFER, GLuint(indirectBefore));
    glDeleteBuffers(1, &command);
}

}  // namespace course
