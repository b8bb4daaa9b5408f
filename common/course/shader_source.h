// Reads a GLSL file the way the course writes them: `#include "file.glsl"` pulls in a
// file from the same shader folder, and `#line` directives keep every line traceable,
// so a compiler message "0:12(5): error" can be turned back into file.comp:12.
// Pure C++, no GL: unit-tested on its own.
#pragma once
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace course {

struct ShaderSource {
    std::string text;                    // what the GL compiler gets
    std::vector<std::string> shownPaths;  // source-string number -> path shown to people
    std::vector<std::string> filePaths;   // source-string number -> absolute path
};

// One file as the preprocessor read it: hot reload compares it with the file on disk.
struct ShaderFile {
    std::string path;                // absolute
    std::string shownPath;           // "shaders/NN_name/file.glsl"
    std::optional<std::string> text;  // none: it could not be read
};

// Files a program writes itself rather than reads from the shader folder (code written
// for the scene it renders): `#include "name"` takes the text of `name` from here first. They do not
// change while the program runs, so hot reload does not watch them.
using GeneratedFiles = std::map<std::string, std::string>;

// Throws Failure(GlProblem) naming the file (and the #include line) that is missing,
// empty, without #version, or included in a cycle. `filesRead`, when given, gets every
// file the preprocessor opened, in order, even when it fails: a missing or empty
// #include is worth watching too.
ShaderSource loadShaderSource(const std::string& shaderDir, const std::string& fileName,
                              std::vector<ShaderFile>* filesRead = nullptr,
                              const GeneratedFiles& generated = {});

// The whole file as bytes, or none when it cannot be read.
std::optional<std::string> readShaderFile(const std::string& path);

// Rewrites compiler messages from the driver's "string:line" forms (Mesa "0:12(5):",
// NVIDIA "0(12) :", AMD/Intel "ERROR: 0:12:") into "shaders/NN/file.comp:12: ...".
std::string translateShaderLog(const std::string& log,
                               const std::vector<std::string>& shownPaths);

}  // namespace course
