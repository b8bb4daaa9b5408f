#include "scene_code.h"

#include <algorithm>
#include <cstdio>
#include <sstream>

#include "course/error.h"
#include "course/log.h"

namespace {

// --8<-- [start:literals]
// GLSL literals that give back exactly the numbers the buffers hold: 9 significant
// digits round-trip any float, and a float literal needs a point or an exponent.
std::string literal(float x) {
    char text[32];
    std::snprintf(text, sizeof text, "%.9g", double(x));
    std::string s = text;
    if (s.find_first_of(".e") == std::string::npos) s += ".0";
    return s;
}
std::string literal(uint32_t x) { return std::to_string(x) + "u"; }
std::string literal(int32_t x) { return std::to_string(x); }
std::string literal(glm::vec3 v) {
    return "vec3(" + literal(v.x) + ", " + literal(v.y) + ", " + literal(v.z) + ")";
}
std::string literal(glm::uvec3 v) {
    return "uvec3(" + literal(v.x) + ", " + literal(v.y) + ", " + literal(v.z) + ")";
}

// A struct's constructor from its fields, in the order shared.h declares them.
std::string literal(const gpu::Sphere& s) {
    return "Sphere(" + literal(s.center) + ", " + literal(s.radius) + ", " +
           literal(s.material) + ", " + literal(s.emitter) + ", 0u, 0u)";
}
std::string literal(const gpu::Quad& q) {
    return "Quad(" + literal(q.origin) + ", " + literal(q.material) + ", " +
           literal(q.edge1) + ", " + literal(q.emitter) + ", " + literal(q.edge2) + ", 0u)";
}
std::string literal(const gpu::Material& m) {
    return "Material(" + literal(m.albedo) + ", " + literal(m.kind) + ", " +
           literal(m.emission) + ", " + literal(m.roughness) + ", " + literal(m.eta) + ", " +
           literal(m.ior) + ", " + literal(m.k) + ", " + literal(m.textureIndex) + ")";
}
std::string literal(const gpu::Emitter& e) {
    return "Emitter(" + literal(e.shape) + ", " + literal(e.index) + ", " + literal(e.area) +
           ", " + literal(e.power) + ")";
}
// --8<-- [end:literals]

// --8<-- [start:array]
// `const Sphere SCENE_SPHERES[N] = Sphere[](...);` with one entry a line. GLSL has no
// empty arrays: an empty list gets one zeroed entry, which no loop reaches (its count
// is 0).
template <class T>
std::string constantArray(const char* type, const char* name, const std::vector<T>& items) {
    std::vector<T> written = items.empty() ? std::vector<T>(1, T{}) : items;
    std::string text = "const " + std::string(type) + " " + name + "[" +
                       std::to_string(written.size()) + "] = " + type + "[](\n";
    for (size_t i = 0; i < written.size(); ++i)
        text += "    " + literal(written[i]) + (i + 1 < written.size() ? ",\n" : ");\n");
    return text;
}

// `#define FOR_EACH_QUAD(TEST) TEST(0) TEST(1) ...`: each shape's test written out
// (scene.glsl).
std::string forEach(const char* name, size_t count) {
    std::string text = std::string("#define ") + name + "(TEST)";
    for (size_t i = 0; i < count; ++i) text += " TEST(" + std::to_string(i) + ")";
    return text + "\n";
}
// --8<-- [end:array]

// The ways' names, in the order of their MEMORY_ numbers (shared.h).
const char* const kMemoryNames[] = {"storage", "uniform", "texture", "constants"};

int memoryCode(const std::string& name) {
    for (int memory = MEMORY_STORAGE; memory < MEMORY_CONSTANTS; ++memory)
        if (name == kMemoryNames[memory]) return memory;
    return MEMORY_CONSTANTS;
}

bool fitsInCode(const GpuScene& scene, size_t times = 1) {
    return scene.spheres.size() + scene.quads.size() <= times * kMostShapesInCode &&
           scene.materials.size() <= times * kMostMaterialsInCode &&
           scene.emitters.size() <= times * kMostEmittersInCode;
}

}  // namespace

void declareSceneCodeOptions(course::CommandLine& cli, SceneCodeOptions& options) {
    cli.choice("--scene-memory", "how the shaders read the spheres, quads, materials and "
               "emitters: constants written into the shader for a small scene, else "
               "buffer textures (auto), or one way for all",
               {"auto", "storage", "uniform", "texture", "constants"}, &options.sceneMemory);
    cli.choice("--bvh-memory", "how the traversal reads the tree and the triangles",
               {"storage", "texture"}, &options.bvhMemory);
    cli.flag("--generic", "one shader for every scene, as chapter 18's: every feature "
             "compiled in, the scene read from storage buffers (for comparisons)",
             &options.generic);
    cli.flag("--bvh-leaves-by-count", "price the tree's leaves by the triangles they hold, "
             "as chapter 14 did, not as the four tests the traversal runs: more, smaller "
             "leaves (for comparisons)", &options.tree.leavesByCount);
}

std::string memoryName(int memory) { return kMemoryNames[memory]; }

void recordSceneCode(const SceneCodeChoice& choice, course::Stats& stats) {
    stats.set("scene_memory", memoryName(choice.sceneMemory));
    stats.set("bvh_memory", memoryName(choice.bvhMemory));
    stats.set("specialised", choice.specialised ? 1.0 : 0.0);
}

// --8<-- [start:choose]
SceneCodeChoice chooseSceneCode(const SceneCodeOptions& options, const GpuScene& scene,
                                const std::string& scenePath) {
    if (options.generic) return {MEMORY_STORAGE, MEMORY_STORAGE, false};
    SceneCodeChoice choice{memoryCode(options.sceneMemory), memoryCode(options.bvhMemory),
                           true};
    if (options.sceneMemory == "auto")
        choice.sceneMemory = fitsInCode(scene) ? MEMORY_CONSTANTS : MEMORY_TEXTURE;
    const size_t most = kMostInCodeByHand;
    if (choice.sceneMemory == MEMORY_CONSTANTS && !fitsInCode(scene, most))
        course::fail(course::ExitCode::BadUsage,
                     scenePath + ": too large to write into the shader (--scene-memory "
                     "constants takes at most " + std::to_string(most * kMostShapesInCode) +
                     " spheres and quads, " + std::to_string(most * kMostMaterialsInCode) +
                     " materials and " + std::to_string(most * kMostEmittersInCode) +
                     " emitters); --scene-memory texture reads any size");
    return choice;
}
// --8<-- [end:choose]

uint32_t materialKindBits(const GpuScene& scene) {
    uint32_t kinds = 0;
    for (const gpu::Material& m : scene.materials) kinds |= 1u << m.kind;
    return kinds;
}

// --8<-- [start:write]
std::string writeSceneCode(const GpuScene& scene, const SceneCodeChoice& choice,
                           bool hasEnvironment, bool hasLens) {
    // What the scene uses; a generic shader assumes everything.
    uint32_t kinds = materialKindBits(scene);
    bool textured = false;
    for (const gpu::Material& m : scene.materials)
        textured = textured || m.textureIndex != NO_TEXTURE;
    const bool all = !choice.specialised;
    std::ostringstream code;
    code << "// Written by the program for this scene (scene_code.cpp).\n"
         << "#define SCENE_MEMORY " << choice.sceneMemory << "  // "
         << memoryName(choice.sceneMemory) << "\n"
         << "#define BVH_MEMORY " << choice.bvhMemory << "  // "
         << memoryName(choice.bvhMemory) << "\n"
         << "#define SPHERE_COUNT " << scene.spheres.size() << "\n"
         << "#define QUAD_COUNT " << scene.quads.size() << "\n"
         << "#define TRIANGLE_COUNT " << scene.triangles.size() << "\n"
         << "#define EMITTER_COUNT " << scene.emitters.size() << "\n"
         << "#define HAS_TRIANGLES " << (all || !scene.triangles.empty()) << "\n"
         << "#define HAS_TEXTURES " << (all || textured) << "\n"
         << "#define HAS_ENVIRONMENT " << (all || hasEnvironment) << "\n"
         << "#define HAS_LENS " << (all || hasLens) << "\n"
         << "#define MATERIAL_KINDS " << (all ? 0xFu : kinds) << "u  // a bit per kind\n";
    if (choice.sceneMemory == MEMORY_UNIFORM) {  // fixed sizes, at least 1 (uploadScene)
        auto atLeastOne = [](size_t n) { return std::max<size_t>(n, 1); };
        code << "#define SPHERE_ARRAY_SIZE " << atLeastOne(scene.spheres.size()) << "\n"
             << "#define QUAD_ARRAY_SIZE " << atLeastOne(scene.quads.size()) << "\n"
             << "#define MATERIAL_ARRAY_SIZE " << atLeastOne(scene.materials.size()) << "\n"
             << "#define EMITTER_ARRAY_SIZE " << atLeastOne(scene.emitters.size()) << "\n";
    }
    if (choice.sceneMemory == MEMORY_CONSTANTS)
        code << constantArray("Sphere", "SCENE_SPHERES", scene.spheres)
             << constantArray("Quad", "SCENE_QUADS", scene.quads)
             << constantArray("Material", "SCENE_MATERIALS", scene.materials)
             << constantArray("Emitter", "SCENE_EMITTERS", scene.emitters)
             << forEach("FOR_EACH_SPHERE", scene.spheres.size())
             << forEach("FOR_EACH_QUAD", scene.quads.size());
    course::logInfo("scene_code.glsl, as written for this scene:\n" + code.str());
    return code.str();
}
// --8<-- [end:write]
