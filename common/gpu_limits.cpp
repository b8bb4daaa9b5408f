#include "course/gpu_limits.h"

#include <cstdlib>
#include <map>
#include <regex>

#include "course/error.h"
#include "course/log.h"

namespace course {
namespace {

// The limits of one shader stage, and what a message calls it.
struct StageLimits {
    GLenum stage;
    const char* name;
    GLenum referencedBy;  // program-interface property: the stage uses the resource
    GLenum storageBlocks, uniformBlocks, textureUnits, imageUniforms;
    const char *storageBlocksName, *uniformBlocksName, *textureUnitsName, *imageUniformsName;
};

const StageLimits kStages[] = {
    {GL_COMPUTE_SHADER, "compute shader", GL_REFERENCED_BY_COMPUTE_SHADER,
     GL_MAX_COMPUTE_SHADER_STORAGE_BLOCKS, GL_MAX_COMPUTE_UNIFORM_BLOCKS,
     GL_MAX_COMPUTE_TEXTURE_IMAGE_UNITS, GL_MAX_COMPUTE_IMAGE_UNIFORMS,
     "GL_MAX_COMPUTE_SHADER_STORAGE_BLOCKS", "GL_MAX_COMPUTE_UNIFORM_BLOCKS",
     "GL_MAX_COMPUTE_TEXTURE_IMAGE_UNITS", "GL_MAX_COMPUTE_IMAGE_UNIFORMS"},
    {GL_VERTEX_SHADER, "vertex shader", GL_REFERENCED_BY_VERTEX_SHADER,
     GL_MAX_VERTEX_SHADER_STORAGE_BLOCKS, GL_MAX_VERTEX_UNIFORM_BLOCKS,
     GL_MAX_VERTEX_TEXTURE_IMAGE_UNITS, GL_MAX_VERTEX_IMAGE_UNIFORMS,
     "GL_MAX_VERTEX_SHADER_STORAGE_BLOCKS", "GL_MAX_VERTEX_UNIFORM_BLOCKS",
     "GL_MAX_VERTEX_TEXTURE_IMAGE_UNITS", "GL_MAX_VERTEX_IMAGE_UNIFORMS"},
    {GL_FRAGMENT_SHADER, "fragment shader", GL_REFERENCED_BY_FRAGMENT_SHADER,
     GL_MAX_FRAGMENT_SHADER_STORAGE_BLOCKS, GL_MAX_FRAGMENT_UNIFORM_BLOCKS,
     GL_MAX_TEXTURE_IMAGE_UNITS, GL_MAX_FRAGMENT_IMAGE_UNIFORMS,
     "GL_MAX_FRAGMENT_SHADER_STORAGE_BLOCKS", "GL_MAX_FRAGMENT_UNIFORM_BLOCKS",
     "GL_MAX_TEXTURE_IMAGE_UNITS", "GL_MAX_FRAGMENT_IMAGE_UNIFORMS"},
};

const StageLimits* limitsOf(GLenum stage) {
    for (const StageLimits& limits : kStages)
        if (limits.stage == stage) return &limits;
    return nullptr;
}

// Where a chapter goes when this GL is short of something.
const char* const kStorageAdvice =
    "Every OpenGL 4.3 gives a compute shader at least 8, which the early chapters keep "
    "within; a newer driver may give more, and the OpenGL 3.3 appendix reads its scene "
    "without any.";
const char* const kDriverAdvice = "A newer graphics driver may give more.";

// "GL_MAX_X (lowered from 16 by COURSE_GL_LIMIT_MAX_X)" when a test lowered it.
std::string limitText(const char* glName, int index = -1) {
    std::string text = glName;
    if (index >= 0) text += "[" + std::to_string(index) + "]";
    const std::string variable = std::string("COURSE_GL_LIMIT_") + (glName + 3);
    if (std::getenv(variable.c_str())) text += ", as " + variable + " sets it";
    return text;
}

// "<label>: its compute shader uses 16 storage blocks, but this GL allows 8 (LIMIT). ..."
[[noreturn]] void failShort(const std::string& label, const std::string& need,
                            long long have, const std::string& limit, const char* advice) {
    fail(ExitCode::GlProblem, label + ": " + need + ", but this GL allows " +
                                  std::to_string(have) + " (" + limit + "). " + advice);
}

std::string count(long long n, const char* things) { return std::to_string(n) + " " + things; }

bool isSampler(GLenum type) {
    switch (type) {
        case GL_SAMPLER_1D: case GL_SAMPLER_2D: case GL_SAMPLER_3D: case GL_SAMPLER_CUBE:
        case GL_SAMPLER_2D_ARRAY: case GL_SAMPLER_BUFFER: case GL_SAMPLER_2D_SHADOW:
        case GL_INT_SAMPLER_2D: case GL_INT_SAMPLER_3D: case GL_INT_SAMPLER_BUFFER:
        case GL_UNSIGNED_INT_SAMPLER_2D: case GL_UNSIGNED_INT_SAMPLER_3D:
        case GL_UNSIGNED_INT_SAMPLER_BUFFER: case GL_SAMPLER_2D_RECT:
            return true;
        default: return false;
    }
}

bool isImage(GLenum type) {
    switch (type) {
        case GL_IMAGE_2D: case GL_IMAGE_3D: case GL_IMAGE_BUFFER: case GL_IMAGE_2D_ARRAY:
        case GL_INT_IMAGE_2D: case GL_UNSIGNED_INT_IMAGE_2D: case GL_INT_IMAGE_BUFFER:
        case GL_UNSIGNED_INT_IMAGE_BUFFER:
            return true;
        default: return false;
    }
}

// One resource of the program's `interface`: its properties, in the order asked.
std::vector<GLint> resourceProperties(GLuint program, GLenum interface, GLuint index,
                                      const std::vector<GLenum>& properties) {
    std::vector<GLint> values(properties.size(), 0);
    if (!GLAD_GL_VERSION_4_3) return values;  // no program interface query before 4.3
    glGetProgramResourceiv(program, interface, index, GLsizei(properties.size()),
                           properties.data(), GLsizei(values.size()), nullptr, values.data());
    return values;
}

// The stage a resource counts against: the first whose GL_REFERENCED_BY_* property
// (values[first + s] for stage s) says it uses it. Mesa 22 says none for storage
// blocks; then the stage that reads the scene in every chapter: the compute shader, or
// the fragment shader beside a full-screen vertex shader.
GLenum stageUsing(const std::vector<GLenum>& stages, const std::vector<GLint>& values,
                  size_t first) {
    for (size_t s = 0; s < stages.size(); ++s)
        if (values[first + s]) return stages[s];
    for (GLenum worker : {GL_COMPUTE_SHADER, GL_FRAGMENT_SHADER})
        for (GLenum stage : stages)
            if (stage == worker) return stage;
    return stages.front();
}

GLint activeResources(GLuint program, GLenum interface) {
    GLint count = 0;
    if (!GLAD_GL_VERSION_4_3) return count;
    glGetProgramInterfaceiv(program, interface, GL_ACTIVE_RESOURCES, &count);
    return count;
}

// Storage or uniform blocks: how many each stage uses, and the highest binding.
void checkBlocks(GLuint program, const std::vector<GLenum>& stages, const std::string& label,
                 bool storage) {
    const GLenum interface = storage ? GL_SHADER_STORAGE_BLOCK : GL_UNIFORM_BLOCK;
    const char* kind = storage ? "storage blocks" : "uniform blocks";
    int highestBinding = -1;
    std::map<GLenum, int> perStage;
    const GLint blocks = activeResources(program, interface);
    for (GLint block = 0; block < blocks; ++block) {
        std::vector<GLenum> properties = {GL_BUFFER_BINDING};
        for (GLenum stage : stages) properties.push_back(limitsOf(stage)->referencedBy);
        std::vector<GLint> values = resourceProperties(program, interface, block, properties);
        highestBinding = std::max(highestBinding, values[0]);
        perStage[stageUsing(stages, values, 1)] += 1;
    }
    for (GLenum stage : stages) {
        const StageLimits& limits = *limitsOf(stage);
        const GLenum name = storage ? limits.storageBlocks : limits.uniformBlocks;
        const char* glName = storage ? limits.storageBlocksName : limits.uniformBlocksName;
        const long long have = glLimit(name, glName);
        if (perStage[stage] > have)
            failShort(label, std::string("its ") + limits.name + " uses " +
                                 count(perStage[stage], kind),
                      have, limitText(glName),
                      storage ? kStorageAdvice : kDriverAdvice);
    }
    const GLenum bindings =
        storage ? GL_MAX_SHADER_STORAGE_BUFFER_BINDINGS : GL_MAX_UNIFORM_BUFFER_BINDINGS;
    const char* bindingsName = storage ? "GL_MAX_SHADER_STORAGE_BUFFER_BINDINGS"
                                       : "GL_MAX_UNIFORM_BUFFER_BINDINGS";
    const long long bindingCount = glLimit(bindings, bindingsName);
    if (highestBinding >= bindingCount)
        failShort(label, std::string("it binds ") + kind + " up to binding " +
                                 std::to_string(highestBinding),
                  bindingCount, limitText(bindingsName) + ": bindings 0 to " +
                                    std::to_string(bindingCount - 1),
                  kDriverAdvice);
}

// Samplers (texture units) and images each stage uses.
void checkTexturesAndImages(GLuint program, const std::vector<GLenum>& stages,
                            const std::string& label) {
    std::map<GLenum, int> samplers, images;
    const GLint uniforms = activeResources(program, GL_UNIFORM);
    for (GLint uniform = 0; uniform < uniforms; ++uniform) {
        std::vector<GLenum> properties = {GL_TYPE, GL_ARRAY_SIZE, GL_BLOCK_INDEX};
        for (GLenum stage : stages) properties.push_back(limitsOf(stage)->referencedBy);
        std::vector<GLint> values = resourceProperties(program, GL_UNIFORM, uniform, properties);
        const GLenum type = GLenum(values[0]);
        if (values[2] != -1 || !(isSampler(type) || isImage(type))) continue;
        (isSampler(type) ? samplers : images)[stageUsing(stages, values, 3)] += values[1];
    }
    for (GLenum stage : stages) {
        const StageLimits& limits = *limitsOf(stage);
        const long long units = glLimit(limits.textureUnits, limits.textureUnitsName);
        if (samplers[stage] > units)
            failShort(label, std::string("its ") + limits.name + " reads " +
                                 count(samplers[stage], "textures (texture units)"),
                      units, limitText(limits.textureUnitsName),
                      "A chapter that can read its scene from storage buffers instead "
                      "(see its --help) needs fewer; a newer driver may give more.");
        const long long imageUnits = glLimit(limits.imageUniforms, limits.imageUniformsName);
        if (images[stage] > imageUnits)
            failShort(label, std::string("its ") + limits.name + " uses " +
                                 count(images[stage], "images"),
                      imageUnits, limitText(limits.imageUniformsName),
                      kDriverAdvice);
    }
}

void checkWorkGroupSize(GLuint program, const std::string& label) {
    GLint size[3] = {1, 1, 1};
    glGetProgramiv(program, GL_COMPUTE_WORK_GROUP_SIZE, size);
    for (int axis = 0; axis < 3; ++axis) {
        const long long most =
            glLimit(GL_MAX_COMPUTE_WORK_GROUP_SIZE, "GL_MAX_COMPUTE_WORK_GROUP_SIZE", axis);
        if (size[axis] > most)
            failShort(label, std::string("its work groups are ") + std::to_string(size[axis]) +
                                 " invocations along " + "xyz"[axis],
                      most, limitText("GL_MAX_COMPUTE_WORK_GROUP_SIZE", axis),
                      kDriverAdvice);
    }
    const long long invocations = glLimit(GL_MAX_COMPUTE_WORK_GROUP_INVOCATIONS,
                                          "GL_MAX_COMPUTE_WORK_GROUP_INVOCATIONS");
    const long long total = 1LL * size[0] * size[1] * size[2];
    if (total > invocations)
        failShort(label, "its work groups have " + count(total, "invocations"), invocations,
                  limitText("GL_MAX_COMPUTE_WORK_GROUP_INVOCATIONS"), kDriverAdvice);
}

// The text without comments, so that a commented-out declaration does not count.
std::string withoutComments(const std::string& source) {
    static const std::regex comments(R"(//[^\n]*|/\*[\s\S]*?\*/)");
    return std::regex_replace(source, comments, " ");
}

}  // namespace

long long glLimit(GLenum name, const char* glName, int index) {
    // Asked once a process: some drivers wait for their queue on a glGet, and a limit
    // is the same for every context of one driver.
    static std::map<std::pair<GLenum, int>, GLint64> asked;
    auto known = asked.find({name, index});
    if (known == asked.end()) {
        GLint64 answer = 0;
        if (index < 0)
            glGetInteger64v(name, &answer);
        else
            glGetInteger64i_v(name, GLuint(index), &answer);
        known = asked.emplace(std::make_pair(name, index), answer).first;
    }
    const GLint64 value = known->second;
    const std::string variable = std::string("COURSE_GL_LIMIT_") + (glName + 3);
    if (const char* lowered = std::getenv(variable.c_str())) {
        char* end = nullptr;
        const long long wanted = std::strtoll(lowered, &end, 10);
        if (*lowered == '\0' || *end != '\0' || wanted < 0)
            fail(ExitCode::BadUsage, variable + " must be a whole number >= 0, got '" +
                                         lowered + "'");
        if (wanted < value) {
            logInfo(variable + ": " + glName + " taken as " + std::to_string(wanted) +
                    " (the GL gives " + std::to_string(value) + ")");
            return wanted;
        }
    }
    return value;
}

void checkProgramLimits(GLuint program, const std::vector<GLenum>& stages,
                        const std::string& label) {
    // Below 4.3 (the GL 3.3 appendix) there is no program interface query, and no
    // storage block; its one uniform block and texture are within every 3.3's minimum.
    if (!GLAD_GL_VERSION_4_3) return;
    for (GLenum stage : stages)
        if (!limitsOf(stage)) return;  // a stage the course does not use
    checkBlocks(program, stages, label, /*storage=*/true);
    checkBlocks(program, stages, label, /*storage=*/false);
    checkTexturesAndImages(program, stages, label);
    if (stages.size() == 1 && stages[0] == GL_COMPUTE_SHADER) checkWorkGroupSize(program, label);
}

DeclaredBlocks declaredBlocks(const std::string& source) {
    const std::string text = withoutComments(source);
    std::map<std::string, int> defines;  // #define NAME 12
    static const std::regex define(R"(#\s*define\s+(\w+)\s+(\d+)\b)");
    for (auto it = std::sregex_iterator(text.begin(), text.end(), define);
         it != std::sregex_iterator(); ++it)
        defines[(*it)[1]] = std::stoi((*it)[2]);
    static const std::regex block(
        R"(layout\s*\(([^)]*)\)\s*((?:readonly|writeonly|restrict|coherent|volatile)\s+)*buffer\s+\w+\s*\{)");
    static const std::regex binding(R"(binding\s*=\s*(\w+))");
    DeclaredBlocks declared;
    for (auto it = std::sregex_iterator(text.begin(), text.end(), block);
         it != std::sregex_iterator(); ++it) {
        ++declared.storageBlocks;
        const std::string qualifiers = (*it)[1];
        std::smatch at;
        if (!std::regex_search(qualifiers, at, binding)) continue;
        const std::string value = at[1];
        const int number = std::isdigit(static_cast<unsigned char>(value[0]))
                               ? std::stoi(value)
                               : (defines.count(value) ? defines[value] : -1);
        declared.highestStorageBinding = std::max(declared.highestStorageBinding, number);
    }
    return declared;
}

std::string explainLinkFailure(const std::vector<std::pair<GLenum, std::string>>& stages) {
    if (!GLAD_GL_VERSION_4_3) return {};
    std::string explanation;
    for (const auto& [stage, source] : stages) {
        const StageLimits* limits = limitsOf(stage);
        if (!limits) continue;
        const DeclaredBlocks declared = declaredBlocks(source);
        const long long have = glLimit(limits->storageBlocks, limits->storageBlocksName);
        if (declared.storageBlocks > have)
            explanation += std::string("its ") + limits->name + " declares " +
                           std::to_string(declared.storageBlocks) +
                           " storage blocks, and this GL allows " + std::to_string(have) +
                           " (" + limitText(limits->storageBlocksName) +
                           "; some drivers count unused ones too). " + kStorageAdvice + "\n";
        const long long bindings = glLimit(GL_MAX_SHADER_STORAGE_BUFFER_BINDINGS,
                                           "GL_MAX_SHADER_STORAGE_BUFFER_BINDINGS");
        if (declared.highestStorageBinding >= bindings)
            explanation += std::string("its ") + limits->name + " binds storage block " +
                           std::to_string(declared.highestStorageBinding) +
                           ", and this GL's bindings end at " + std::to_string(bindings - 1) +
                           " (" + limitText("GL_MAX_SHADER_STORAGE_BUFFER_BINDINGS") + ").\n";
    }
    return explanation;
}

void checkWorkGroupCount(const int groups[3], const std::string& label) {
    for (int axis = 0; axis < 3; ++axis) {
        const long long most =
            glLimit(GL_MAX_COMPUTE_WORK_GROUP_COUNT, "GL_MAX_COMPUTE_WORK_GROUP_COUNT", axis);
        if (groups[axis] > most)
            failShort(label, "a dispatch needs " + count(groups[axis], "work groups") +
                                 " along " + "xyz"[axis],
                      most, limitText("GL_MAX_COMPUTE_WORK_GROUP_COUNT", axis),
                      "A smaller --width or --height needs fewer.");
    }
}

}  // namespace course
