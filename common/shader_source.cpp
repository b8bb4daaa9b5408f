#include "course/shader_source.h"

#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>

#include "course/error.h"

namespace fs = std::filesystem;

namespace course {
namespace {

constexpr int kMaxIncludeDepth = 16;

// `#line N S` should make the compiler report source string S, but Mesa reports every
// message as string 0. So line numbers carry the file too: included file S starts at
// line S * kLinesPerFile + 1, which any driver reports faithfully.
constexpr int kLinesPerFile = 10000;

std::string lineDirective(int sourceNumber, int line) {
    return "#line " + std::to_string(sourceNumber * kLinesPerFile + line) + " " +
           std::to_string(sourceNumber) + "\n";
}

// "shaders/NN_name/sphere.glsl" when the folder is a checkpoint's shader folder,
// otherwise the absolute path: short where it can be, never ambiguous.
std::string shownPathOf(const fs::path& file) {
    fs::path folder = file.parent_path();
    if (folder.parent_path().filename() == "shaders")
        return (fs::path("shaders") / folder.filename() / file.filename()).string();
    return file.string();
}

[[noreturn]] void shaderFailure(const std::string& where, const std::string& what) {
    fail(ExitCode::GlProblem, where + ": " + what);
}

// A header that C++ and GLSL both read (shared.h) keeps what only C++ needs between
// `#ifdef __cplusplus` and `#endif`: `#include <glm/glm.hpp>`, `namespace gpu {`,
// static_asserts. GLSL's own preprocessor would skip those lines, but this one runs
// first and resolves #include itself, so it must know them too: it passes them on as
// blank lines (the line numbers stay) and leaves their #includes alone. The directives
// themselves go through unchanged, so GLSL sees the same #if structure.
//
// One open #if, #ifdef or #ifndef of the file being read.
struct Conditional {
    enum Kind { Other, Cplusplus, NotCplusplus } kind;
    bool pastElse = false;  // after its #else or an #elif
    bool passedOn = true;   // its directives reach GLSL (it is not inside C++-only lines)
    int line = 0;
};

// What an #if / #ifdef / #ifndef line tests: `__cplusplus` (#ifdef __cplusplus,
// #if defined(__cplusplus)), its negation, or anything else.
Conditional::Kind kindOf(const std::string& directive, std::string condition) {
    condition = condition.substr(0, condition.find("//"));  // `#ifdef __cplusplus // ...`
    static const std::regex defined(
        R"(^\s*(!\s*)?defined\s*(\(\s*__cplusplus\s*\)|\s__cplusplus)\s*$)");
    static const std::regex name(R"(^\s*__cplusplus\s*$)");
    std::smatch match;
    if (directive == "ifdef" || directive == "ifndef") {
        if (!std::regex_match(condition, name)) return Conditional::Other;
        return directive == "ifdef" ? Conditional::Cplusplus : Conditional::NotCplusplus;
    }
    if (!std::regex_match(condition, match, defined)) return Conditional::Other;
    return match[1].matched ? Conditional::NotCplusplus : Conditional::Cplusplus;
}

// Is a line at this point for the C++ compiler only?
bool insideCplusplusOnly(const std::vector<Conditional>& open) {
    for (const Conditional& c : open)
        if ((c.kind == Conditional::Cplusplus && !c.pastElse) ||
            (c.kind == Conditional::NotCplusplus && c.pastElse))
            return true;
    return false;
}

struct Preprocessor {
    fs::path folder;
    ShaderSource result;
    std::vector<ShaderFile>* filesRead = nullptr;
    const GeneratedFiles* generated = nullptr;
    std::vector<fs::path> includeStack;

    // A generated file's text, if `file` is one: it lives in the shader folder by name.
    const std::string* generatedText(const fs::path& file) const {
        if (file.parent_path() != folder) return nullptr;
        auto found = generated->find(file.filename().string());
        return found == generated->end() ? nullptr : &found->second;
    }
    std::string shownPathOf(const fs::path& file) const {
        return generatedText(file) ? course::shownPathOf(file) + " (generated)"
                                   : course::shownPathOf(file);
    }

    void append(const fs::path& file, const std::string& includedFrom, int depth) {
        if (depth > kMaxIncludeDepth)
            shaderFailure(includedFrom, "#include nested deeper than 16 levels");
        for (const auto& open : includeStack)
            if (open == file)
                shaderFailure(includedFrom, "#include cycle: " + shownPathOf(file) +
                                                " includes itself");
        const std::string* made = generatedText(file);
        std::optional<std::string> read = made ? *made : readShaderFile(file.string());
        if (filesRead && !made) filesRead->push_back({file.string(), shownPathOf(file), read});
        if (!read)
            shaderFailure(includedFrom.empty() ? shownPathOf(file) : includedFrom,
                          "cannot read shader file " + file.string());
        const std::string& text = *read;
        if (text.find_first_not_of(" \t\r\n") == std::string::npos)
            shaderFailure(shownPathOf(file), "shader file is empty: " + file.string());

        const int sourceNumber = static_cast<int>(result.shownPaths.size());
        result.shownPaths.push_back(shownPathOf(file));
        result.filePaths.push_back(file.string());
        includeStack.push_back(file);
        if (depth > 0) result.text += lineDirective(sourceNumber, 1);

        static const std::regex includeLine(R"(^\s*#\s*include\s*"([^"]+)\"\s*$)");
        static const std::regex badInclude(R"(^\s*#\s*include\b.*)");
        static const std::regex conditional(
            R"(^\s*#\s*(if|ifdef|ifndef|elif|else|endif)\b(.*)$)");
        std::istringstream lines(text);
        std::string line;
        bool sawVersion = false;
        std::vector<Conditional> open;  // this file's #if nesting
        for (int lineNumber = 1; std::getline(lines, line); ++lineNumber) {
            if (!line.empty() && line.back() == '\r') line.pop_back();
            const std::string here = shownPathOf(file) + ":" + std::to_string(lineNumber);
            if (depth > 0 && lineNumber >= kLinesPerFile)
                shaderFailure(here, "an included file may have at most 9999 lines");
            std::smatch match;
            const bool cplusplusOnly = insideCplusplusOnly(open);
            if (std::regex_match(line, match, conditional)) {
                const std::string directive = match[1].str();
                bool passedOn = !cplusplusOnly;
                if (directive == "if" || directive == "ifdef" || directive == "ifndef") {
                    open.push_back({kindOf(directive, match[2].str()), false, passedOn,
                                    lineNumber});
                } else if (!open.empty()) {
                    passedOn = open.back().passedOn;
                    if (directive == "endif")
                        open.pop_back();
                    else
                        open.back().pastElse = true;
                }
                result.text += (passedOn ? line : std::string()) + "\n";
                continue;
            }
            if (cplusplusOnly) {
                result.text += "\n";  // for C++ only: blank, so that the lines still count
                continue;
            }
            if (std::regex_match(line, match, includeLine)) {
                fs::path included = folder / match[1].str();
                append(included.lexically_normal(), here, depth + 1);
                // Back in this file: the next line is lineNumber + 1 of this source.
                result.text += lineDirective(sourceNumber, lineNumber + 1);
                continue;
            }
            if (std::regex_match(line, badInclude))
                shaderFailure(here, "#include needs a quoted file name: " + line +
                                        " (a C++ header goes inside #ifdef __cplusplus)");
            if (line.find("#version") != std::string::npos) sawVersion = true;
            result.text += line + "\n";
        }
        for (const Conditional& c : open)
            if (c.kind != Conditional::Other)
                shaderFailure(shownPathOf(file) + ":" + std::to_string(c.line),
                              "this #if on __cplusplus has no #endif in the same file");
        if (depth == 0 && !sawVersion)
            shaderFailure(shownPathOf(file) + ":1", "the shader has no #version line");
        includeStack.pop_back();
    }
};

}  // namespace

std::optional<std::string> readShaderFile(const std::string& path) {
    std::error_code error;
    if (fs::is_directory(path, error)) return std::nullopt;
    std::ifstream stream(path, std::ios::binary);
    if (!stream) return std::nullopt;
    std::stringstream content;
    content << stream.rdbuf();
    return content.str();
}

ShaderSource loadShaderSource(const std::string& shaderDir, const std::string& fileName,
                              std::vector<ShaderFile>* filesRead,
                              const GeneratedFiles& generated) {
    Preprocessor preprocessor;
    preprocessor.generated = &generated;
    preprocessor.folder = fs::absolute(shaderDir).lexically_normal();
    preprocessor.filesRead = filesRead;
    preprocessor.append(preprocessor.folder / fileName, "", 0);
    return preprocessor.result;
}

std::string translateShaderLog(const std::string& log,
                               const std::vector<std::string>& shownPaths) {
    // Mesa: "0:12(5): error: ..."  NVIDIA: "0(12) : error C1008: ..."
    // AMD / Intel Windows: "ERROR: 0:12: ..."
    static const std::regex mesa(R"(^(\d+):(\d+)\(\d+\):\s*(.*)$)");
    static const std::regex nvidia(R"(^(\d+)\((\d+)\)\s*:\s*(.*)$)");
    static const std::regex amd(R"(^(ERROR|WARNING):\s*(\d+):(\d+):\s*(.*)$)");
    // "file:line" from the reported source number and line (see kLinesPerFile).
    auto where = [&](const std::string& number, const std::string& lineText) {
        size_t index = std::stoul(number), line = std::stoul(lineText);
        if (line >= size_t(kLinesPerFile)) {
            index = line / kLinesPerFile;
            line %= kLinesPerFile;
        }
        std::string file = index < shownPaths.size() ? shownPaths[index]
                                                     : "source " + std::to_string(index);
        return file + ":" + std::to_string(line);
    };
    std::istringstream lines(log);
    std::string line, out;
    while (std::getline(lines, line)) {
        std::smatch m;
        if (std::regex_match(line, m, mesa) || std::regex_match(line, m, nvidia))
            out += where(m[1], m[2]) + ": " + m[3].str() + "\n";
        else if (std::regex_match(line, m, amd))
            out += where(m[2], m[3]) + ": " + m[1].str() + ": " + m[4].str() + "\n";
        else if (!line.empty())
            out += line + "\n";
    }
    return out;
}

}  // namespace course
