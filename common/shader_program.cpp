#include "course/shader_program.h"

#include <cstdio>
#include <utility>

#include <glm/gtc/type_ptr.hpp>

#include "course/error.h"
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

GLuint linkProgram(const std::vector<GLuint>& shaders, const std::string& label) {
    GLuint program = glCreateProgram();
    for (GLuint shader : shaders) glAttachShader(program, shader);
    glLinkProgram(program);
    for (GLuint shader : shaders) glDeleteShader(shader);  // the program keeps them
    GLint ok = GL_FALSE;
    glGetProgramiv(program, GL_LINK_STATUS, &ok);
    if (!ok) {
        std::string log = infoLog(program, true);
        glDeleteProgram(program);
        fail(ExitCode::GlProblem, label + ": shader link failed:\n" + log);
    }
    return program;
}

}  // namespace

GLuint buildProgramFromText(const std::vector<std::pair<GLenum, std::string>>& stages,
                            const std::string& label) {
    std::vector<GLuint> shaders;
    for (const auto& [type, text] : stages) shaders.push_back(compileStage(type, text, {label}));
    return linkProgram(shaders, label);
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

ShaderProgram::ShaderProgram(std::string shaderDir, std::vector<ShaderStage> stages)
    : shaderDir_(std::move(shaderDir)), stages_(std::move(stages)) {
    std::vector<ShaderFile> filesRead;
    id_ = build(filesRead);
    watched_ = withoutRepeats(filesRead);
}

ShaderProgram::~ShaderProgram() {
    if (id_) glDeleteProgram(id_);
}

ShaderProgram::ShaderProgram(ShaderProgram&& other) noexcept
    : id_(std::exchange(other.id_, 0)), shaderDir_(std::move(other.shaderDir_)),
      stages_(std::move(other.stages_)), watched_(std::move(other.watched_)) {}

ShaderProgram& ShaderProgram::operator=(ShaderProgram&& other) noexcept {
    if (this != &other) {
        if (id_) glDeleteProgram(id_);
        id_ = std::exchange(other.id_, 0);
        shaderDir_ = std::move(other.shaderDir_);
        stages_ = std::move(other.stages_);
        watched_ = std::move(other.watched_);
    }
    return *this;
}

GLuint ShaderProgram::build(std::vector<ShaderFile>& filesRead) const {
    std::vector<GLuint> shaders;
    std::string label;
    try {
        for (const ShaderStage& stage : stages_) {
            ShaderSource source = loadShaderSource(shaderDir_, stage.fileName, &filesRead);
            label += (label.empty() ? "" : " + ") + source.shownPaths.front();
            shaders.push_back(compileStage(stage.type, source.text, source.shownPaths));
        }
    } catch (...) {
        for (GLuint shader : shaders) glDeleteShader(shader);
        throw;
    }
    return linkProgram(shaders, label);
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
        GLuint rebuilt = build(filesRead);
        glDeleteProgram(id_);
        id_ = rebuilt;
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
static void setUniform(GLuint program, const char* name, Direct direct, InUse inUse) {
    GLint location = glGetUniformLocation(program, name);
    if (GLAD_GL_VERSION_4_1) return direct(program, location);
    GLint current = 0;
    glGetIntegerv(GL_CURRENT_PROGRAM, &current);
    if (GLuint(current) != program) glUseProgram(program);
    inUse(location);
    if (GLuint(current) != program) glUseProgram(GLuint(current));
}

void ShaderProgram::set(const char* name, int value) const {
    setUniform(id_, name, [&](GLuint p, GLint at) { glProgramUniform1i(p, at, value); },
               [&](GLint at) { glUniform1i(at, value); });
}
void ShaderProgram::set(const char* name, unsigned value) const {
    setUniform(id_, name, [&](GLuint p, GLint at) { glProgramUniform1ui(p, at, value); },
               [&](GLint at) { glUniform1ui(at, value); });
}
void ShaderProgram::set(const char* name, float value) const {
    setUniform(id_, name, [&](GLuint p, GLint at) { glProgramUniform1f(p, at, value); },
               [&](GLint at) { glUniform1f(at, value); });
}
void ShaderProgram::set(const char* name, const glm::vec2& value) const {
    const float* v = glm::value_ptr(value);
    setUniform(id_, name, [&](GLuint p, GLint at) { glProgramUniform2fv(p, at, 1, v); },
               [&](GLint at) { glUniform2fv(at, 1, v); });
}
void ShaderProgram::set(const char* name, const glm::vec3& value) const {
    const float* v = glm::value_ptr(value);
    setUniform(id_, name, [&](GLuint p, GLint at) { glProgramUniform3fv(p, at, 1, v); },
               [&](GLint at) { glUniform3fv(at, 1, v); });
}
void ShaderProgram::set(const char* name, const glm::vec4& value) const {
    const float* v = glm::value_ptr(value);
    setUniform(id_, name, [&](GLuint p, GLint at) { glProgramUniform4fv(p, at, 1, v); },
               [&](GLint at) { glUniform4fv(at, 1, v); });
}
void ShaderProgram::set(const char* name, const glm::ivec2& value) const {
    const int* v = glm::value_ptr(value);
    setUniform(id_, name, [&](GLuint p, GLint at) { glProgramUniform2iv(p, at, 1, v); },
               [&](GLint at) { glUniform2iv(at, 1, v); });
}
void ShaderProgram::set(const char* name, const glm::uvec2& value) const {
    const unsigned* v = glm::value_ptr(value);
    setUniform(id_, name, [&](GLuint p, GLint at) { glProgramUniform2uiv(p, at, 1, v); },
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
    use();
    glDispatchCompute(groupsFor(invocationsX, group.x), groupsFor(invocationsY, group.y),
                      groupsFor(invocationsZ, group.z));
}

}  // namespace course
