// A linked GL program built from the checkpoint's shader files. Compile and link
// errors come out as "shaders/NN_name/file.comp:LINE: message" (exit code 4).
// In window mode, reloadIfChanged() rebuilds it when a file changed on disk and keeps
// the last good program when the new source does not compile.
#pragma once
#include <string>
#include <utility>
#include <vector>

#include <glm/glm.hpp>

#include "course/gl.h"
#include "course/shader_source.h"

namespace course {

struct ShaderStage {
    GLenum type;           // GL_COMPUTE_SHADER, GL_VERTEX_SHADER, ...
    std::string fileName;  // inside the shader folder
};

class ShaderProgram {
public:
    ShaderProgram() = default;
    // `generated`: files the program wrote itself, which #include finds by name first.
    ShaderProgram(std::string shaderDir, std::vector<ShaderStage> stages,
                  GeneratedFiles generated = {});
    static ShaderProgram compute(const std::string& shaderDir, const std::string& fileName,
                                 GeneratedFiles generated = {}) {
        return ShaderProgram(shaderDir, {{GL_COMPUTE_SHADER, fileName}}, std::move(generated));
    }
    ~ShaderProgram();
    ShaderProgram(ShaderProgram&& other) noexcept;
    ShaderProgram& operator=(ShaderProgram&& other) noexcept;

    void use() const { glUseProgram(id_); }
    GLuint id() const { return id_; }

    // Uniforms by name. GL ignores a name the program has no active uniform for; in a
    // debug build (no NDEBUG) a name its source does not even declare, a misspelt one,
    // is exit code 4, naming the uniform and the program's file. (A declared uniform
    // that the shader does not read, which the compiler removes, is still ignored: a
    // starter's stub may not read it yet.) Per-dispatch values are better one typed
    // uniform block, a struct shared with C++ through shared.h: GpuBuffer::bindUniform.
    void set(const char* name, int value) const;
    void set(const char* name, unsigned value) const;
    void set(const char* name, float value) const;
    void set(const char* name, const glm::vec2& value) const;
    void set(const char* name, const glm::vec3& value) const;
    void set(const char* name, const glm::vec4& value) const;
    void set(const char* name, const glm::ivec2& value) const;
    void set(const char* name, const glm::uvec2& value) const;
    // Whether the program has this active uniform, for code that serves several
    // programs and sets only what each one uses.
    bool hasUniform(const char* name) const;
    // GLSL 3.30 has no layout(binding = N) for a uniform block: this connects the block
    // called `blockName` to binding point N by name. A new program starts unconnected,
    // so call it after every (re)link, e.g. before each pass. A block the source does
    // not declare is exit code 4 in a debug build, as for set().
    void bindUniformBlock(const char* blockName, GLuint binding) const;

    // Work groups of a compute shader, as declared by its local_size layout.
    glm::ivec3 workGroupSize() const;
    // glDispatchCompute with enough groups to cover `invocations`, rounded up.
    void dispatchCovering(int invocationsX, int invocationsY = 1, int invocationsZ = 1) const;
    // Has the GL compile the compute shader now, if it waits for the first dispatch to
    // (Mesa's llvmpipe does, on the CPU: seconds for a large shader, more on a busy
    // machine), so that the compile is not taken for a step that never ends. Once per
    // link; dispatchCovering calls it, and so should code that dispatches by itself.
    void compileBeforeFirstDispatch() const;

    // Hot reload. Reads every file the program was built from (includes too) and
    // compares its text with what the last build read: the contents, not the time of
    // change, which many file systems keep to a few milliseconds or to the second, so
    // two saves close together could look like one. Each saved version is built once:
    // "reloaded FILE", or the compiler's message and "kept the last good program".
    enum class Reload { Unchanged, Reloaded, KeptLastGood };
    Reload reloadIfChanged();
    // The files it watches, as messages show them: "shaders/NN_name/path.comp".
    std::vector<std::string> watchedFiles() const;

private:
    // Throws Failure(GlProblem); `sources` gets the text each stage was compiled from.
    GLuint build(std::vector<ShaderFile>& filesRead, std::string& sources) const;
    GLint uniformLocation(const char* name) const;  // checked in debug builds
    std::string name() const;                        // for messages

    GLuint id_ = 0;
    std::string shaderDir_;
    std::vector<ShaderStage> stages_;
    GeneratedFiles generated_;         // the same text at every reload
    std::vector<ShaderFile> watched_;  // every file read, includes too, as last read
    std::string sources_;              // the stages' preprocessed text, for name checks
    mutable GLuint compiledFor_ = 0;   // the id_ compileBeforeFirstDispatch last did
};

// Compiles and links program text that lives in C++ (the window display); errors name
// `label`. Returns the program id.
GLuint buildProgramFromText(const std::vector<std::pair<GLenum, std::string>>& stages,
                            const std::string& label);

}  // namespace course
