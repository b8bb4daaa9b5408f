// Scenes from text files (course/scene_file.h). The file is read whole and walked line
// by line with course/text_file.h, as the chapters' OBJ loader is; each
// statement is checked as it is read, and what needs the whole file (materials used
// before their line, the camera, an emitter) is checked at the end.
#include "course/scene_file.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <system_error>
#include <unordered_map>
#include <utility>

#include <glm/gtc/matrix_transform.hpp>

#include "course/error.h"
#include "course/image_read.h"
#include "course/text_file.h"
#include "course/volume_grid.h"

namespace course {
namespace {

namespace fs = std::filesystem;

// A scene file is a few kilobytes: meshes live in OBJ files. This only stops a wrong
// file (a video, a disk image) from being read into memory whole.
constexpr std::uintmax_t kMostBytes = std::uintmax_t(16) << 20;
// No statement has more fields than a camera with a lens, a medium and a shutter (26
// words); an instance's steps may repeat, up to this many words in all.
constexpr size_t kMostWords = 64;
constexpr const char* kNameRule =
    "use letters, digits, '_' and '-', starting with a letter or '_'";

// ---------------------------------------------------------------------------------------
// Characters and words
// ---------------------------------------------------------------------------------------

// Material and shape names: letters, digits, '_' and '-', starting with a letter or '_'.
bool isName(std::string_view word) {
    if (!isLetter(word[0]) && word[0] != '_')
        return false;
    for (char c : word)
        if (!isLetter(c) && !isDigit(c) && c != '_' && c != '-')
            return false;
    return true;
}

bool isRegularFile(const fs::path& path) {
    std::error_code error;
    return fs::is_regular_file(path, error);
}

// ---------------------------------------------------------------------------------------
// The parser
// ---------------------------------------------------------------------------------------

using Words = std::vector<std::string_view>;

// A shape's material as written; its index is filled in once the whole file is read,
// so that a material may be defined after the shapes that use it.
enum class ShapeKind { Sphere, Quad, Triangle, Mesh };
struct MaterialUse {
    std::string name;
    size_t line;
    ShapeKind kind;
    size_t shape;    // index into the scene's (or the object's) vector of that kind of shape
    int32_t object;  // the object the shape belongs to (SceneFile::objects), or -1: the world
};

// An instance's object as written; resolved at the end, as materials are.
struct ObjectUse {
    std::string name;
    size_t line;
    size_t instance;  // index into SceneFile::instances
};

// The three kinds of words a number may start with, and digits: a step's numbers end
// where a word that is no number begins (the next step's name).
bool looksLikeNumber(std::string_view word) {
    return isDigit(word[0]) || word[0] == '-' || word[0] == '+' || word[0] == '.';
}

// A medium named by a sphere's or a mesh's `interior`, or by the camera; resolved at
// the end, as materials are.
enum class MediumPlace { Sphere, Mesh, Camera };
struct MediumUse {
    std::string name;
    size_t line;
    MediumPlace place;
    size_t shape;  // index into the spheres or meshes
};

class SceneParser {
public:
    SceneParser(std::string shownPath, std::vector<std::string> meshFolders,
                SceneSupport support)
        : path_(std::move(shownPath)), meshFolders_(std::move(meshFolders)),
          support_(std::move(support)) {
        scene_.path = path_;
    }

    // One line, its comment already cut off (course::forEachLine).
    void readLine(std::string_view line, size_t lineNumber) {
        lineNumber_ = lineNumber;
        Words words;
        for (std::string_view word = nextWord(line); !word.empty(); word = nextWord(line)) {
            if (words.size() == kMostWords)
                fail("too many fields for any statement");
            words.push_back(word);
        }
        if (words.empty())
            return;  // a blank line, or only a comment
        const std::string_view keyword = words.front();
        words.erase(words.begin());
        if (openObject_ >= 0 && keyword != "sphere" && keyword != "quad" &&
            keyword != "triangle" && keyword != "mesh" && keyword != "end")
            refuseInObject(keyword, words);
        if (keyword == "camera")
            readCamera(words);
        else if (keyword == "texture")
            readTexture(words);
        else if (keyword == "material")
            readMaterial(words);
        else if (keyword == "sphere")
            readSphere(words);
        else if (keyword == "quad")
            readQuad(words);
        else if (keyword == "triangle")
            readTriangle(words);
        else if (keyword == "mesh")
            readMesh(words);
        else if (keyword == "environment")
            readEnvironment(words);
        else if (keyword == "medium")
            readMedium(words);
        else if (keyword == "object")
            readObject(words);
        else if (keyword == "end")
            readEnd(words);
        else if (keyword == "instance")
            readInstance(words);
        else
            fail("unknown keyword " + inQuotes(keyword) +
                 " (expected camera, texture, material, medium, sphere, quad, triangle, "
                 "mesh, environment, object, end or instance)");
    }

    SceneFile finish() {
        if (openObject_ >= 0) {
            const SceneObject& open = scene_.objects[size_t(openObject_)];
            failAt(open.line, "object " + inQuotes(open.name) + " has no 'end'");
        }
        for (const MaterialUse& use : uses_) {  // in file order: the first error is named
            const auto found = materialIndex_.find(use.name);
            if (found == materialIndex_.end())
                failAt(use.line, "material " + inQuotes(use.name) + " is not defined");
            materialOf(use) = found->second;
            if (use.object >= 0 && scene_.materials[found->second].emits())
                failAt(use.line, "object " + inQuotes(scene_.objects[size_t(use.object)].name) +
                                     ": material " + inQuotes(use.name) +
                                     " emits, and an object's shapes may not (a light is "
                                     "placed as it is, not through instances)");
            const bool hasUv = use.kind == ShapeKind::Quad || use.kind == ShapeKind::Mesh;
            if (scene_.materials[found->second].texture >= 0 && !hasUv)
                failAt(use.line, "material " + inQuotes(use.name) +
                                     " is textured, and this shape has no texture "
                                     "coordinates: textures apply to quads and meshes");
        }
        for (const MediumUse& use : mediumUses_) {
            const auto found = mediumIndex_.find(use.name);
            if (found == mediumIndex_.end())
                failAt(use.line, "medium " + inQuotes(use.name) + " is not defined");
            const int32_t medium = int32_t(found->second);
            if (use.place == MediumPlace::Camera) {
                scene_.camera.medium = medium;
                continue;
            }
            const bool sphere = use.place == MediumPlace::Sphere;
            const uint32_t material = sphere ? scene_.spheres[use.shape].material
                                             : scene_.meshes[use.shape].material;
            const MaterialKind kind = scene_.materials[material].kind;
            if (kind != MaterialKind::Boundary && kind != MaterialKind::Dielectric)
                failAt(use.line, "an interior medium needs a surface light passes through, "
                                 "a 'boundary' or 'dielectric' material; " +
                                     inQuotes(scene_.materials[material].name) + " is " +
                                     materialKindWord(kind));
            (sphere ? scene_.spheres[use.shape].interior : scene_.meshes[use.shape].interior) =
                medium;
        }
        for (const ObjectUse& use : objectUses_) {
            const auto found = objectIndex_.find(use.name);
            if (found == objectIndex_.end())
                failAt(use.line, "object " + inQuotes(use.name) + " is not defined");
            scene_.instances[use.instance].object = found->second;
        }
        // What this program does not read: exit code 3 at the first line that uses it.
        const SceneSupport& reads = support_;
        if (!reads.instances.read && (!scene_.objects.empty() || !scene_.instances.empty())) {
            const size_t first = scene_.objects.empty() ? scene_.instances.front().line
                                 : scene_.instances.empty()
                                     ? scene_.objects.front().line
                                     : std::min(scene_.objects.front().line,
                                                scene_.instances.front().line);
            failAt(first, "this program draws no objects or instances (object ... end, "
                          "instance)" + comesIn("instances come", reads.instances));
        }
        if (!reads.motion.read) {
            for (const SceneInstance& instance : scene_.instances)
                if (instance.motion != glm::vec3(0.0f))
                    failAt(instance.line, "this program renders nothing that moves "
                                          "(moving X Y Z)" + comesIn("motion comes", reads.motion));
            if (shutterWritten_)
                failAt(cameraLine_, "the camera has a shutter: this program renders nothing "
                                    "that moves" + comesIn("motion comes", reads.motion));
        }
        if (!reads.media.read) {
            size_t first = scene_.media.empty() ? 0 : scene_.media.front().line;
            auto earlier = [&first](size_t line) { first = first ? std::min(first, line) : line; };
            for (const SceneMaterial& material : scene_.materials)
                if (material.kind == MaterialKind::Boundary) earlier(material.line);
            for (const MediumUse& use : mediumUses_) earlier(use.line);
            if (first)
                failAt(first, "this program renders no participating media (medium "
                              "statements, boundary materials)" +
                                  comesIn("media come", reads.media));
        }
        if (!reads.environment.read && scene_.hasEnvironment())
            failAt(scene_.environment.line, "this program has no environment light" +
                                                comesIn("it comes", reads.environment));
        if (!reads.textures.read && !scene_.textures.empty())
            failAt(scene_.textures.front().line,
                   "texture " + inQuotes(scene_.textures.front().name) +
                       ": this program has no textures" +
                       comesIn("textures come", reads.textures));
        if (!reads.lens.read && scene_.camera.lensRadius > 0.0f)
            failAt(cameraLine_, "the camera has a lens: this program has a pinhole camera" +
                                    comesIn("the thin lens comes", reads.lens));
        for (const SceneMaterial& material : scene_.materials) {
            const bool glass = material.kind == MaterialKind::Dielectric;
            const bool metal = !glass && material.kind != MaterialKind::Diffuse;
            if ((glass && !reads.glass.read) || (metal && !reads.metals.read))
                failAt(material.line,
                       "material " + inQuotes(material.name) + " is a " +
                           materialKindWord(material.kind) +
                           (reads.metals.read ? ": this program renders only opaque materials "
                                                "(albedo, mirror, conductor)"
                                              : ": this program renders only diffuse materials "
                                                "('albedo R G B')") +
                           (glass ? comesIn("glass comes", reads.glass)
                                  : comesIn("mirrors and conductors come", reads.metals)));
        }
        if (cameraLine_ == 0)
            failAt(0, "no camera: a scene needs one 'camera' line");
        if (scene_.emitterCount() == 0 && !scene_.hasEnvironment())
            failAt(0, "no emitter: no shape uses a material with an emission");
        return std::move(scene_);
    }

    // "; glass comes in chapter NN", or nothing where no chapter at hand reads it.
    static std::string comesIn(const std::string& what, const SceneFeature& feature) {
        return feature.firstReadBy.empty() ? "" : "; " + what + " in " + feature.firstReadBy;
    }

    [[noreturn]] void failAt(size_t lineNumber, const std::string& what) const {
        failAtLine(path_, lineNumber, what);
    }

private:
    [[noreturn]] void fail(const std::string& what) const { failAt(lineNumber_, what); }

    float readNumber(std::string_view word) const {
        return course::readNumber(word, path_, lineNumber_);
    }

    glm::vec3 readVector(const Words& words, size_t first) const {
        return {readNumber(words[first]), readNumber(words[first + 1]),
                readNumber(words[first + 2])};
    }

    void expectFieldCount(std::string_view keyword, const Words& words, size_t count,
                          const char* fields) const {
        if (words.size() != count)
            fail(inQuotes(keyword) + " needs " + std::to_string(count) + " fields (" + fields +
                 "), got " + std::to_string(words.size()));
    }

    void expectLabel(const Words& words, size_t index, std::string_view label,
                     std::string_view statement) const {
        if (words[index] != label)
            fail(inQuotes(statement) + " expects " + inQuotes(label) + " here, got " +
                 inQuotes(words[index]));
    }

    // camera eye X Y Z look X Y Z up X Y Z focal F sensor S [lens RADIUS focus DISTANCE]
    //        [medium MEDIUM]
    void readCamera(Words words) {
        // shutter OPEN CLOSE, anywhere after the sensor: taken out first, so that the rest
        // reads as it always has.
        float shutterOpen = 0.0f, shutterClose = 0.0f;
        for (size_t i = 16; i < words.size(); ++i) {
            if (words[i] != "shutter") continue;
            if (shutterWritten_ || i + 2 >= words.size() || !looksLikeNumber(words[i + 1]) ||
                !looksLikeNumber(words[i + 2]))
                fail("the camera's shutter needs two numbers, OPEN CLOSE (seconds), once");
            shutterOpen = readNumber(words[i + 1]);
            shutterClose = readNumber(words[i + 2]);
            if (!(shutterOpen >= 0.0f) || !(shutterClose >= shutterOpen))
                fail("the camera's shutter " + inQuotes(words[i + 1]) + " " +
                     inQuotes(words[i + 2]) + " must open at 0 or later and close no "
                     "earlier than it opens");
            shutterWritten_ = true;
            words.erase(words.begin() + std::ptrdiff_t(i), words.begin() + std::ptrdiff_t(i) + 3);
            break;
        }
        if (words.size() < 16 || words.size() > 22 || words.size() % 2 != 0)
            expectFieldCount("camera", words, 16,
                             "eye X Y Z look X Y Z up X Y Z focal F sensor S, then "
                             "optionally lens RADIUS focus DISTANCE and medium MEDIUM");
        if (cameraLine_ != 0)
            fail("a second camera (the first is on line " + std::to_string(cameraLine_) + ")");
        const char* labels[] = {"eye", "look", "up"};
        for (size_t i = 0; i < 3; ++i)
            expectLabel(words, 4 * i, labels[i], "camera");
        expectLabel(words, 12, "focal", "camera");
        expectLabel(words, 14, "sensor", "camera");

        SceneCamera camera;
        camera.eye = readVector(words, 1);
        camera.look = readVector(words, 5);
        camera.up = readVector(words, 9);
        camera.focalLength = readNumber(words[13]);
        camera.sensorWidth = readNumber(words[15]);
        if (glm::length(camera.look) == 0.0f)
            fail("the camera's look direction must not be zero");
        if (glm::length(camera.up) == 0.0f)
            fail("the camera's up direction must not be zero");
        const glm::dvec3 look(camera.look), up(camera.up);
        if (glm::length(glm::cross(look, up)) <= 1e-6 * glm::length(look) * glm::length(up))
            fail("the camera's up must not be parallel to its look direction");
        if (!(camera.focalLength > 0.0f) || !(camera.sensorWidth > 0.0f))
            fail("the camera's focal length and sensor width must be positive");
        bool seenLens = false, seenMedium = false;
        for (size_t i = 16; i < words.size();) {
            if (words[i] == "lens" && !seenLens && i + 4 <= words.size()) {
                expectLabel(words, i + 2, "focus", "camera");
                camera.lensRadius = readNumber(words[i + 1]);
                camera.focusDistance = readNumber(words[i + 3]);
                if (!(camera.lensRadius >= 0.0f))
                    fail("the lens radius " + inQuotes(words[i + 1]) + " must be 0 or more");
                if (!(camera.focusDistance > 0.0f))
                    fail("the focus distance " + inQuotes(words[i + 3]) + " must be positive");
                seenLens = true;
                i += 4;
            } else if (words[i] == "medium" && !seenMedium) {
                useMedium(words[i + 1], MediumPlace::Camera, 0);
                seenMedium = true;
                i += 2;
            } else {
                fail("unexpected " + inQuotes(words[i]) +
                     " in 'camera' (after the sensor: lens RADIUS focus DISTANCE, "
                     "medium MEDIUM, shutter OPEN CLOSE, each once)");
            }
        }
        camera.shutterOpen = shutterOpen;
        camera.shutterClose = shutterClose;
        scene_.camera = camera;
        cameraLine_ = lineNumber_;
    }

    // material NAME albedo R G B [emission R G B]
    //          NAME mirror [reflectance R G B]
    //          NAME conductor eta R G B k R G B [roughness A]
    //          NAME dielectric ior N [roughness A]
    void readMaterial(const Words& words) {
        if (words.size() < 2)
            fail("'material' needs a name and a kind (NAME albedo R G B, NAME mirror, "
                 "NAME conductor eta R G B k R G B, NAME dielectric ior N)");
        const std::string_view name = words[0];
        if (!isName(name))
            fail("material name " + inQuotes(name) + ": " + kNameRule);
        const std::string key(name);
        const auto earlier = materialLines_.find(key);
        if (earlier != materialLines_.end())
            fail("material " + inQuotes(name) + " is already defined on line " +
                 std::to_string(earlier->second));

        SceneMaterial material;
        material.name = key;
        material.line = lineNumber_;
        const std::string_view kind = words[1];
        size_t next = 2;  // the first word after the kind
        if (kind == "albedo" && words.size() > 2 && words[2] == "texture") {
            material.kind = MaterialKind::Diffuse;
            if (words.size() < 4)
                fail("'albedo texture' needs the name of a texture");
            material.texture = int32_t(textureIndex(words[3]));
            next += 2;
        } else if (kind == "albedo") {
            material.kind = MaterialKind::Diffuse;
            material.albedo = readFraction(words, next, "albedo");
            next += 3;
        } else if (kind == "mirror") {
            material.kind = MaterialKind::Mirror;
        } else if (kind == "boundary") {
            material.kind = MaterialKind::Boundary;
        } else if (kind == "conductor") {
            material.kind = MaterialKind::Conductor;
            expectWords(words, next + 8, "conductor eta R G B k R G B");
            expectLabel(words, next, "eta", "material");
            material.eta = readVector(words, next + 1);
            expectLabel(words, next + 4, "k", "material");
            material.k = readVector(words, next + 5);
            for (int c = 0; c < 3; ++c) {
                if (!(material.eta[c] > 0.0f))
                    fail("eta " + inQuotes(words[next + 1 + c]) + " must be above 0");
                if (material.k[c] < 0.0f)
                    fail("k " + inQuotes(words[next + 5 + c]) + " is negative");
            }
            next += 8;
        } else if (kind == "dielectric") {
            material.kind = MaterialKind::Dielectric;
            expectWords(words, next + 2, "dielectric ior N");
            expectLabel(words, next, "ior", "material");
            material.ior = readNumber(words[next + 1]);
            if (!(material.ior > 0.0f))
                fail("ior " + inQuotes(words[next + 1]) + " must be above 0");
            next += 2;
        } else {
            fail("unknown material kind " + inQuotes(kind) +
                 " (expected albedo, mirror, conductor, dielectric or boundary)");
        }
        // The optional words, each once, each only where it means something.
        const std::string described =
            "material " + inQuotes(name) + " (" + materialKindWord(material.kind) + ")";
        bool seenEmission = false, seenReflectance = false, seenRoughness = false;
        while (next < words.size()) {
            const std::string_view option = words[next];
            if (option == "emission" && material.kind != MaterialKind::Diffuse) {
                fail("only an 'albedo' material may have an emission, not " + described);
            } else if (option == "emission" && !seenEmission) {
                material.emission = readNonNegative(words, next + 1, "emission");
                seenEmission = true;
                next += 4;
            } else if (option == "reflectance" && material.kind == MaterialKind::Mirror &&
                       !seenReflectance) {
                material.reflectance = readFraction(words, next + 1, "reflectance");
                seenReflectance = true;
                next += 4;
            } else if (option == "roughness" && !seenRoughness &&
                       (material.kind == MaterialKind::Conductor ||
                        material.kind == MaterialKind::Dielectric)) {
                if (next + 1 >= words.size())
                    fail("roughness needs a number, the GGX alpha");
                material.roughness = readNumber(words[next + 1]);
                if (material.roughness < 0.0f)
                    fail("roughness " + inQuotes(words[next + 1]) + " is negative");
                seenRoughness = true;
                next += 2;
            } else {
                fail("unexpected " + inQuotes(option) + " in " + described);
            }
        }
        materialLines_[key] = lineNumber_;
        materialIndex_[key] = uint32_t(scene_.materials.size());
        scene_.materials.push_back(material);
    }

    // texture NAME image PATH [linear]
    //         NAME checker R G B R G B [scale S]
    void readTexture(const Words& words) {
        if (words.size() < 2)
            fail("'texture' needs a name and a kind (NAME image PATH [linear], "
                 "NAME checker R G B R G B [scale S])");
        const std::string_view name = words[0];
        if (!isName(name))
            fail("texture name " + inQuotes(name) + ": " + kNameRule);
        const std::string key(name);
        if (const auto earlier = textureIndex_.find(key); earlier != textureIndex_.end())
            fail("texture " + inQuotes(name) + " is already defined on line " +
                 std::to_string(scene_.textures[earlier->second].line));
        SceneTexture texture;
        texture.name = key;
        texture.line = lineNumber_;
        if (words[1] == "image") {
            const bool linear = words.size() == 4 && words[3] == "linear";
            if (words.size() != 3 && !linear)
                fail("'texture NAME image PATH' takes only the word 'linear' after PATH");
            texture.kind = TextureKind::Image;
            texture.writtenPath = std::string(words[2]);
            texture.path = findFile(texture.writtenPath, "image file");
            texture.linear = linear;
            const std::string problem = imageProblem(texture.path);
            if (!problem.empty())
                fail("image " + inQuotes(texture.writtenPath) + " (" + texture.path +
                     ") is " + (problem.rfind("not ", 0) == 0 ? "" : "too big: ") + problem);
        } else if (words[1] == "checker") {
            texture.kind = TextureKind::Checker;
            texture.color0 = readFraction(words, 2, "checker colour");
            texture.color1 = readFraction(words, 5, "checker colour");
            if (words.size() == 10) {
                expectLabel(words, 8, "scale", "texture");
                texture.scale = readNumber(words[9]);
                if (!(texture.scale > 0.0f))
                    fail("the checker's scale " + inQuotes(words[9]) + " must be positive");
            } else if (words.size() != 8) {
                fail("'texture NAME checker' needs two colours R G B R G B, then "
                     "optionally scale S");
            }
        } else {
            fail("unknown texture kind " + inQuotes(words[1]) + " (expected image or checker)");
        }
        textureIndex_[key] = uint32_t(scene_.textures.size());
        scene_.textures.push_back(texture);
    }

    // Unlike materials, textures are defined before they are used.
    uint32_t textureIndex(std::string_view name) const {
        const auto found = textureIndex_.find(std::string(name));
        if (found == textureIndex_.end())
            fail("texture " + inQuotes(name) + " is not defined on an earlier line");
        return found->second;
    }

    void expectWords(const Words& words, size_t atLeast, const char* form) const {
        if (words.size() < atLeast)
            fail("'material' " + std::string(form) + ": too few fields");
    }

    glm::vec3 readNonNegative(const Words& words, size_t first, std::string_view what) const {
        if (first + 3 > words.size())
            fail(std::string(what) + " needs three numbers R G B");
        const glm::vec3 value = readVector(words, first);
        for (int c = 0; c < 3; ++c)
            if (value[c] < 0.0f)
                fail(std::string(what) + " " + inQuotes(words[first + c]) + " is negative");
        return value;
    }

    glm::vec3 readFraction(const Words& words, size_t first, std::string_view what) const {
        const glm::vec3 value = readNonNegative(words, first, what);
        for (int c = 0; c < 3; ++c)
            if (value[c] > 1.0f)
                fail(std::string(what) + " " + inQuotes(words[first + c]) +
                     " is outside [0, 1]: a surface cannot reflect more light than reaches it");
        return value;
    }

    // Called before the shape is appended to its vector: `shape` is its index there.
    void useMaterial(std::string_view name, ShapeKind kind, size_t shape) {
        uses_.push_back({std::string(name), lineNumber_, kind, shape, openObject_});
    }

    // Where shapes go: the world's lists, or an object's between its begin and end.
    struct ShapeLists {
        std::vector<SceneSphere>& spheres;
        std::vector<SceneQuad>& quads;
        std::vector<SceneTriangle>& triangles;
        std::vector<SceneMesh>& meshes;
    };
    ShapeLists shapesOf(int32_t object) {
        if (object < 0)
            return {scene_.spheres, scene_.quads, scene_.triangles, scene_.meshes};
        SceneObject& o = scene_.objects[size_t(object)];
        return {o.spheres, o.quads, o.triangles, o.meshes};
    }
    ShapeLists shapes() { return shapesOf(openObject_); }

    uint32_t& materialOf(const MaterialUse& use) {
        ShapeLists lists = shapesOf(use.object);
        switch (use.kind) {
        case ShapeKind::Sphere: return lists.spheres[use.shape].material;
        case ShapeKind::Quad: return lists.quads[use.shape].material;
        case ShapeKind::Triangle: return lists.triangles[use.shape].material;
        case ShapeKind::Mesh: break;
        }
        return lists.meshes[use.shape].material;
    }

    // The fields of a sphere, quad or triangle, then optionally `name NAME`.
    std::string readShapeFields(std::string_view keyword, const Words& words, size_t count,
                                const char* fields) const {
        if (words.size() == count + 2) {
            expectLabel(words, count, "name", keyword);
            return readShapeName(words[count + 1]);
        }
        if (words.size() != count)
            fail(inQuotes(keyword) + " needs " + std::to_string(count) + " fields (" + fields +
                 "), then optionally name NAME; got " + std::to_string(words.size()));
        return "";
    }

    std::string readShapeName(std::string_view name) const {
        if (!isName(name))
            fail("shape name " + inQuotes(name) + ": " + kNameRule);
        return std::string(name);
    }

    // sphere CX CY CZ RADIUS MATERIAL [interior MEDIUM] [name NAME]
    void readSphere(const Words& words) {
        SceneSphere sphere;
        const size_t count = 5;
        if (words.size() < count)
            fail("'sphere' needs 5 fields (CX CY CZ RADIUS MATERIAL), then optionally "
                 "interior MEDIUM and name NAME; got " + std::to_string(words.size()));
        bool seenInterior = false, seenName = false;
        for (size_t i = count; i < words.size(); i += 2) {
            const bool interior = words[i] == "interior" && !seenInterior;
            const bool name = words[i] == "name" && !seenName;
            if ((!interior && !name) || i + 1 >= words.size())
                fail("'sphere' takes after its 5 fields only interior MEDIUM and name NAME, "
                     "each once; got " + inQuotes(words[i]));
            if (interior)
                useMedium(words[i + 1], MediumPlace::Sphere, shapes().spheres.size());
            else
                sphere.name = readShapeName(words[i + 1]);
            (interior ? seenInterior : seenName) = true;
        }
        sphere.center = readVector(words, 0);
        sphere.radius = readNumber(words[3]);
        if (!(sphere.radius > 0.0f))
            fail("the sphere's radius must be positive, got " + inQuotes(words[3]));
        useMaterial(words[4], ShapeKind::Sphere, shapes().spheres.size());
        shapes().spheres.push_back(sphere);
    }

    // Zero when the two edges are parallel or either is zero; in double precision, so
    // that a long thin but real shape is not taken for a degenerate one.
    static double parallelogramArea(glm::vec3 edge1, glm::vec3 edge2) {
        return glm::length(glm::cross(glm::dvec3(edge1), glm::dvec3(edge2)));
    }

    static bool isDegenerate(glm::vec3 edge1, glm::vec3 edge2) {
        const double area = parallelogramArea(edge1, edge2);
        return area <= 1e-7 * glm::length(glm::dvec3(edge1)) * glm::length(glm::dvec3(edge2));
    }

    // quad OX OY OZ EX EY EZ FX FY FZ MATERIAL [name NAME]
    void readQuad(const Words& words) {
        SceneQuad quad;
        quad.name = readShapeFields("quad", words, 10, "OX OY OZ EX EY EZ FX FY FZ MATERIAL");
        quad.origin = readVector(words, 0);
        quad.edge1 = readVector(words, 3);
        quad.edge2 = readVector(words, 6);
        if (isDegenerate(quad.edge1, quad.edge2))
            fail("the quad has zero area: an edge is zero or the two edges are parallel");
        useMaterial(words[9], ShapeKind::Quad, shapes().quads.size());
        shapes().quads.push_back(quad);
    }

    // triangle AX AY AZ BX BY BZ CX CY CZ MATERIAL [name NAME]
    void readTriangle(const Words& words) {
        SceneTriangle triangle;
        triangle.name =
            readShapeFields("triangle", words, 10, "AX AY AZ BX BY BZ CX CY CZ MATERIAL");
        triangle.p0 = readVector(words, 0);
        triangle.p1 = readVector(words, 3);
        triangle.p2 = readVector(words, 6);
        if (isDegenerate(triangle.p1 - triangle.p0, triangle.p2 - triangle.p0))
            fail("the triangle has zero area: its corners are on one line");
        useMaterial(words[9], ShapeKind::Triangle, shapes().triangles.size());
        shapes().triangles.push_back(triangle);
    }

    // mesh PATH MATERIAL [scale S] [rotate_y DEGREES] [translate X Y Z] [name NAME]
    void readMesh(const Words& words) {
        if (words.size() < 2)
            fail("'mesh' needs a PATH and a MATERIAL, then optionally scale S, "
                 "rotate_y DEGREES, translate X Y Z, name NAME");
        SceneMesh mesh;
        mesh.writtenPath = std::string(words[0]);
        mesh.path = findFile(mesh.writtenPath, "mesh file");
        mesh.line = lineNumber_;
        bool seen[5] = {false, false, false, false, false};
        for (size_t i = 2; i < words.size();) {
            const std::string_view option = words[i];
            const int which = option == "scale" ? 0 : option == "rotate_y" ? 1
                            : option == "translate" ? 2 : option == "name" ? 3
                            : option == "interior" ? 4 : -1;
            if (which < 0)
                fail("unknown mesh option " + inQuotes(option) +
                     " (expected scale, rotate_y, translate, interior or name)");
            if (seen[which])
                fail(inQuotes(option) + " is given twice");
            seen[which] = true;
            const size_t count = which == 2 ? 3 : 1;
            if (words.size() - (i + 1) < count)
                fail(inQuotes(option) + " needs " + std::to_string(count) +
                     (which >= 3 ? " name" : count == 1 ? " number" : " numbers"));
            if (which == 0) {
                mesh.scale = readNumber(words[i + 1]);
                if (!(mesh.scale > 0.0f))
                    fail("the mesh's scale must be positive, got " + inQuotes(words[i + 1]));
            } else if (which == 1) {
                mesh.rotationYDegrees = readNumber(words[i + 1]);
            } else if (which == 3) {
                mesh.name = readShapeName(words[i + 1]);
            } else if (which == 4) {
                useMedium(words[i + 1], MediumPlace::Mesh, shapes().meshes.size());
            } else {
                mesh.translation = readVector(words, i + 1);
            }
            i += 1 + count;
        }
        useMaterial(words[1], ShapeKind::Mesh, shapes().meshes.size());
        shapes().meshes.push_back(mesh);
    }

    void useMedium(std::string_view name, MediumPlace place, size_t shape) {
        if (openObject_ >= 0)
            fail("object " + inQuotes(scene_.objects[size_t(openObject_)].name) +
                 ": an object's shapes hold no medium (interior)");
        mediumUses_.push_back({std::string(name), lineNumber_, place, shape});
    }

    // --8<-- [start:objects]
    // object NAME begin
    void readObject(const Words& words) {
        if (words.size() != 2 || words[1] != "begin")
            fail("'object' needs a name and the word begin: object NAME begin");
        const std::string_view name = words[0];
        if (!isName(name))
            fail("object name " + inQuotes(name) + ": " + kNameRule);
        const std::string key(name);
        if (const auto earlier = objectIndex_.find(key); earlier != objectIndex_.end())
            fail("object " + inQuotes(name) + " is already defined on line " +
                 std::to_string(scene_.objects[earlier->second].line));
        SceneObject object;
        object.name = key;
        object.line = lineNumber_;
        objectIndex_[key] = uint32_t(scene_.objects.size());
        openObject_ = int32_t(scene_.objects.size());
        scene_.objects.push_back(object);
    }

    // end
    void readEnd(const Words& words) {
        if (openObject_ < 0)
            fail("'end' without an 'object NAME begin' before it");
        if (!words.empty())
            fail("'end' takes nothing after it, got " + inQuotes(words[0]));
        const SceneObject& object = scene_.objects[size_t(openObject_)];
        if (object.spheres.empty() && object.quads.empty() && object.triangles.empty() &&
            object.meshes.empty())
            failAt(object.line, "object " + inQuotes(object.name) +
                                    " is empty: put shapes between its begin and end");
        openObject_ = -1;
    }

    // Between an object's begin and end only shapes (and its end) may stand.
    [[noreturn]] void refuseInObject(std::string_view keyword, const Words& words) const {
        const SceneObject& object = scene_.objects[size_t(openObject_)];
        if (keyword == "instance" && !words.empty() && words[0] == object.name)
            fail("object " + inQuotes(object.name) + " is used inside itself");
        if (keyword == "instance" || keyword == "object")
            fail(inQuotes(keyword) + " inside object " + inQuotes(object.name) +
                 " (line " + std::to_string(object.line) + "): objects hold shapes, not "
                 "objects or instances; 'end' it first");
        fail(inQuotes(keyword) + " inside object " + inQuotes(object.name) + " (line " +
             std::to_string(object.line) + "): only sphere, quad, triangle and mesh "
             "statements stand between its begin and end");
    }

    // instance OBJECT [scale S | scale X Y Z] [rotate X Y Z DEGREES] [rotate_y DEGREES]
    //          [translate X Y Z] [moving X Y Z] [name NAME]
    void readInstance(const Words& words) {
        if (words.empty())
            fail("'instance' needs the name of an object, then its placement");
        if (!isName(words[0]))
            fail("object name " + inQuotes(words[0]) + ": " + kNameRule);
        SceneInstance instance;
        instance.line = lineNumber_;
        bool seenMoving = false, seenName = false;
        for (size_t i = 1; i < words.size();) {
            const std::string_view step = words[i];
            // How many numbers follow the step's word.
            size_t numbers = 0;
            while (i + 1 + numbers < words.size() && looksLikeNumber(words[i + 1 + numbers]))
                ++numbers;
            auto need = [&](size_t count, const char* form) {
                if (numbers != count)
                    fail(inQuotes(step) + " needs " + form + ", got " +
                         std::to_string(numbers) + (numbers == 1 ? " number" : " numbers"));
            };
            PlacementStep placed;
            if (step == "scale") {
                if (numbers != 1) need(3, "1 number (S) or 3 (X Y Z)");
                placed.kind = PlacementStepKind::Scale;
                const glm::vec3 factors =
                    numbers == 1 ? glm::vec3(readNumber(words[i + 1])) : readVector(words, i + 1);
                if (factors.x == 0.0f || factors.y == 0.0f || factors.z == 0.0f)
                    fail("scale by 0 squashes the object flat");
                placed.values = glm::vec4(factors, 0.0f);
            } else if (step == "rotate") {
                need(4, "4 numbers (axis X Y Z, DEGREES)");
                placed.kind = PlacementStepKind::Rotate;
                placed.values = glm::vec4(readVector(words, i + 1), readNumber(words[i + 4]));
                if (glm::vec3(placed.values) == glm::vec3(0.0f))
                    fail("rotate needs an axis that is not 0 0 0");
            } else if (step == "rotate_y") {
                need(1, "1 number (DEGREES)");
                placed.kind = PlacementStepKind::RotateY;
                placed.values.w = readNumber(words[i + 1]);
            } else if (step == "translate") {
                need(3, "3 numbers (X Y Z)");
                placed.values = glm::vec4(readVector(words, i + 1), 0.0f);
            } else if (step == "moving" && !seenMoving) {
                need(3, "3 numbers (X Y Z)");
                instance.motion = readVector(words, i + 1);
                seenMoving = true;
                i += 4;
                continue;
            } else if (step == "name" && !seenName && i + 1 < words.size()) {
                instance.name = readShapeName(words[i + 1]);
                seenName = true;
                i += 2;
                continue;
            } else {
                fail("unexpected " + inQuotes(step) + " in 'instance' (expected scale, rotate, "
                     "rotate_y, translate, and moving X Y Z and name NAME once each)");
            }
            instance.steps.push_back(placed);
            i += 1 + numbers;
        }
        const glm::dmat3 linear(glm::mat3(instance.worldFromObject()));
        const double determinant = glm::determinant(linear);
        if (!std::isfinite(determinant) || !(std::abs(determinant) > 1e-24)) {
            char shown[32];
            std::snprintf(shown, sizeof shown, "%.3g", determinant);
            fail("the placement squashes the object flat or blows it up (the determinant of "
                 "its matrix is " + std::string(shown) + ")");
        }
        objectUses_.push_back({std::string(words[0]), lineNumber_, scene_.instances.size()});
        scene_.instances.push_back(instance);
    }
    // --8<-- [end:objects]

    // medium NAME homogeneous sigma_a R G B sigma_s R G B [g G]
    //        NAME grid PATH albedo R G B [scale S] [g G]
    void readMedium(const Words& words) {
        if (words.size() < 2)
            fail("'medium' needs a name and a kind (NAME homogeneous sigma_a R G B sigma_s "
                 "R G B, NAME grid PATH albedo R G B)");
        const std::string_view name = words[0];
        if (!isName(name))
            fail("medium name " + inQuotes(name) + ": " + kNameRule);
        const std::string key(name);
        if (const auto earlier = mediumIndex_.find(key); earlier != mediumIndex_.end())
            fail("medium " + inQuotes(name) + " is already defined on line " +
                 std::to_string(scene_.media[earlier->second].line));
        SceneMedium medium;
        medium.name = key;
        medium.line = lineNumber_;
        size_t next = 0;
        if (words[1] == "homogeneous") {
            if (words.size() < 10)
                fail("'medium NAME homogeneous' needs sigma_a R G B sigma_s R G B");
            expectLabel(words, 2, "sigma_a", "medium");
            medium.sigmaA = readNonNegative(words, 3, "sigma_a");
            expectLabel(words, 6, "sigma_s", "medium");
            medium.sigmaS = readNonNegative(words, 7, "sigma_s");
            next = 10;
        } else if (words[1] == "grid") {
            medium.kind = MediumKind::Grid;
            if (words.size() < 7)
                fail("'medium NAME grid' needs PATH albedo R G B");
            medium.writtenPath = std::string(words[2]);
            medium.path = findFile(medium.writtenPath, "grid file");
            const std::string problem = volumeGridProblem(medium.path);
            if (!problem.empty())
                fail("grid " + inQuotes(medium.writtenPath) + " (" + medium.path + "): " +
                     problem);
            expectLabel(words, 3, "albedo", "medium");
            medium.albedo = readFraction(words, 4, "albedo");
            next = 7;
        } else {
            fail("unknown medium kind " + inQuotes(words[1]) + " (expected homogeneous or grid)");
        }
        bool seenG = false, seenScale = false;
        for (; next < words.size(); next += 2) {
            const std::string_view option = words[next];
            const bool scale = option == "scale" && medium.kind == MediumKind::Grid;
            if ((option != "g" && !scale) || (option == "g" ? seenG : seenScale))
                fail("unexpected " + inQuotes(option) + " in medium " + inQuotes(name) +
                     (medium.kind == MediumKind::Grid ? " (after the albedo: scale S, g G)"
                                                      : " (after sigma_s: g G)"));
            if (next + 1 >= words.size())
                fail(inQuotes(option) + " needs a number");
            const float value = readNumber(words[next + 1]);
            if (scale && !(value > 0.0f))
                fail("the grid's scale " + inQuotes(words[next + 1]) + " must be positive");
            if (!scale && !(value > -1.0f && value < 1.0f))
                fail("g " + inQuotes(words[next + 1]) +
                     " must lie strictly between -1 and 1 (the phase function's mean cosine)");
            (scale ? medium.scale : medium.g) = value;
            (scale ? seenScale : seenG) = true;
        }
        mediumIndex_[key] = uint32_t(scene_.media.size());
        scene_.media.push_back(medium);
    }

    // environment PATH [scale S] [rotate_y DEGREES]
    void readEnvironment(const Words& words) {
        if (scene_.hasEnvironment())
            fail("a second environment (the first is on line " +
                 std::to_string(scene_.environment.line) + ")");
        if (words.empty())
            fail("'environment' needs a PATH, then optionally scale S, rotate_y DEGREES");
        SceneEnvironment environment;
        environment.writtenPath = std::string(words[0]);
        environment.path = findFile(environment.writtenPath, "environment file");
        bool seenScale = false, seenRotation = false;
        for (size_t i = 1; i < words.size(); i += 2) {
            const std::string_view option = words[i];
            bool& seen = option == "scale" ? seenScale : seenRotation;
            if (option != "scale" && option != "rotate_y")
                fail("unknown environment option " + inQuotes(option) +
                     " (expected scale or rotate_y)");
            if (seen)
                fail(inQuotes(option) + " is given twice");
            seen = true;
            if (i + 1 >= words.size())
                fail(inQuotes(option) + " needs 1 number");
            const float value = readNumber(words[i + 1]);
            if (option == "scale" && !(value > 0.0f))
                fail("the environment's scale must be positive, got " +
                     inQuotes(words[i + 1]));
            (option == "scale" ? environment.scale : environment.rotationYDegrees) = value;
        }
        const std::string problem = radianceMapProblem(environment.path);
        if (!problem.empty())
            fail("environment " + inQuotes(environment.writtenPath) + " (" +
                 environment.path + ") is " +
                 (problem.find(" a side") == std::string::npos ? "" : "too big: ") + problem);
        environment.line = lineNumber_;
        scene_.environment = environment;
    }

    // The scene file's folder first, then the folders the program passed in.
    std::string findFile(const std::string& written, const char* what) const {
        const fs::path relative(written);
        std::vector<fs::path> candidates;
        if (relative.is_absolute()) {
            candidates.push_back(relative);
        } else {
            candidates.push_back(fs::path(path_).parent_path() / relative);
            for (const std::string& folder : meshFolders_)
                candidates.push_back(fs::path(folder) / relative);
        }
        std::string tried;
        for (const fs::path& candidate : candidates) {
            if (isRegularFile(candidate))
                return absolutePath(candidate.string());
            tried += (tried.empty() ? "" : ", ") + absolutePath(candidate.string());
        }
        fail(what + (" " + inQuotes(written)) + " not found (looked for " + tried + ")");
    }

    std::string path_;
    std::vector<std::string> meshFolders_;
    SceneSupport support_;
    size_t lineNumber_ = 0;
    size_t cameraLine_ = 0;
    std::unordered_map<std::string, size_t> materialLines_;
    std::unordered_map<std::string, uint32_t> materialIndex_;
    std::unordered_map<std::string, uint32_t> textureIndex_;
    std::vector<MaterialUse> uses_;
    std::unordered_map<std::string, uint32_t> mediumIndex_;
    std::vector<MediumUse> mediumUses_;
    std::unordered_map<std::string, uint32_t> objectIndex_;
    std::vector<ObjectUse> objectUses_;
    int32_t openObject_ = -1;  // the object between its begin and end, or -1
    bool shutterWritten_ = false;
    SceneFile scene_;
};

}  // namespace

// --8<-- [start:load]
SceneFile parseSceneText(std::string_view text, const std::string& shownPath,
                         const std::vector<std::string>& meshFolders,
                         const SceneSupport& support) {
    SceneParser parser(shownPath, meshFolders, support);
    forEachLine(text, shownPath, [&parser](std::string_view line, size_t lineNumber) {
        parser.readLine(line, lineNumber);
    });
    return parser.finish();
}

SceneFile loadSceneFile(const std::string& path, const std::vector<std::string>& meshFolders,
                        const SceneSupport& support) {
    const std::string shownPath = absolutePath(path);
    const std::string text = readWholeFile(path, kMostBytes, "a scene file");
    return parseSceneText(text, shownPath, meshFolders, support);
}

const char* materialKindWord(MaterialKind kind) {
    switch (kind) {
    case MaterialKind::Mirror: return "mirror";
    case MaterialKind::Conductor: return "conductor";
    case MaterialKind::Dielectric: return "dielectric";
    case MaterialKind::Boundary: return "boundary";
    case MaterialKind::Diffuse: break;
    }
    return "albedo";
}
// --8<-- [end:load]

size_t SceneFile::emitterCount() const {
    auto emits = [this](uint32_t material) {
        return material < materials.size() && materials[material].emits();
    };
    size_t count = 0;
    for (const SceneSphere& sphere : spheres)
        count += emits(sphere.material);
    for (const SceneQuad& quad : quads)
        count += emits(quad.material);
    for (const SceneTriangle& triangle : triangles)
        count += emits(triangle.material);
    for (const SceneMesh& mesh : meshes)
        count += emits(mesh.material);
    return count;
}

// --8<-- [start:transform]
glm::mat4 SceneMesh::worldFromMesh() const {
    // Read right to left: scale first, then turn about y, then move.
    const glm::mat4 identity(1.0f);
    return glm::translate(identity, translation) *
           glm::rotate(identity, glm::radians(rotationYDegrees), glm::vec3(0, 1, 0)) *
           glm::scale(identity, glm::vec3(scale));
}
// --8<-- [end:transform]

// --8<-- [start:placement]
glm::mat4 SceneInstance::worldFromObject() const {
    // Each step multiplies from the left: the first written applies to the object first.
    const glm::mat4 identity(1.0f);
    glm::mat4 world(1.0f);
    for (const PlacementStep& step : steps) {
        const glm::vec3 v(step.values);
        switch (step.kind) {
        case PlacementStepKind::Scale: world = glm::scale(identity, v) * world; break;
        case PlacementStepKind::Rotate:
            world = glm::rotate(identity, glm::radians(step.values.w), glm::normalize(v)) * world;
            break;
        case PlacementStepKind::RotateY:
            world = glm::rotate(identity, glm::radians(step.values.w), glm::vec3(0, 1, 0)) *
                    world;
            break;
        case PlacementStepKind::Translate: world = glm::translate(identity, v) * world; break;
        }
    }
    return world;
}
// --8<-- [end:placement]

namespace {

// Nine significant digits read back as the same float.
std::string number(float value) {
    char text[32];
    std::snprintf(text, sizeof text, "%.9g", double(value));
    return text;
}

std::string numbers(glm::vec3 v) { return number(v.x) + " " + number(v.y) + " " + number(v.z); }

}  // namespace

std::string formatSceneFile(const SceneFile& scene) {
    const SceneCamera& camera = scene.camera;
    std::string text = "camera eye " + numbers(camera.eye) + " look " + numbers(camera.look) +
                       " up " + numbers(camera.up) + " focal " + number(camera.focalLength) +
                       " sensor " + number(camera.sensorWidth);
    if (camera.lensRadius > 0.0f)
        text += " lens " + number(camera.lensRadius) + " focus " + number(camera.focusDistance);
    if (camera.medium >= 0) text += " medium " + scene.media.at(size_t(camera.medium)).name;
    if (camera.shutterOpen > 0.0f || camera.shutterClose > 0.0f)
        text += " shutter " + number(camera.shutterOpen) + " " + number(camera.shutterClose);
    text += "\n";
    for (const SceneTexture& texture : scene.textures) {
        if (texture.kind == TextureKind::Image)
            text += "texture " + texture.name + " image " + texture.writtenPath +
                    (texture.linear ? " linear\n" : "\n");
        else
            text += "texture " + texture.name + " checker " + numbers(texture.color0) + " " +
                    numbers(texture.color1) + " scale " + number(texture.scale) + "\n";
    }
    for (const SceneMaterial& material : scene.materials) {
        text += "material " + material.name + " " + materialKindWord(material.kind);
        switch (material.kind) {
        case MaterialKind::Diffuse:
            if (material.texture >= 0)
                text += " texture " + scene.textures.at(size_t(material.texture)).name;
            else
                text += " " + numbers(material.albedo);
            if (material.emits()) text += " emission " + numbers(material.emission);
            break;
        case MaterialKind::Mirror:
            text += " reflectance " + numbers(material.reflectance);
            break;
        case MaterialKind::Conductor:
            text += " eta " + numbers(material.eta) + " k " + numbers(material.k);
            break;
        case MaterialKind::Dielectric:
            text += " ior " + number(material.ior);
            break;
        case MaterialKind::Boundary:
            break;
        }
        if (material.roughness > 0.0f) text += " roughness " + number(material.roughness);
        text += "\n";
    }
    for (const SceneMedium& medium : scene.media) {
        if (medium.kind == MediumKind::Homogeneous)
            text += "medium " + medium.name + " homogeneous sigma_a " + numbers(medium.sigmaA) +
                    " sigma_s " + numbers(medium.sigmaS);
        else
            text += "medium " + medium.name + " grid " + medium.writtenPath + " albedo " +
                    numbers(medium.albedo) + " scale " + number(medium.scale);
        text += " g " + number(medium.g) + "\n";
    }
    auto interior = [&scene](int32_t medium) {
        return medium < 0 ? std::string() : " interior " + scene.media.at(size_t(medium)).name;
    };
    auto name = [&scene](uint32_t material) { return scene.materials.at(material).name; };
    auto shapeName = [](const std::string& name) {
        return name.empty() ? std::string("\n") : " name " + name + "\n";
    };
    auto writeShapes = [&](const std::vector<SceneSphere>& spheres,
                           const std::vector<SceneQuad>& quads,
                           const std::vector<SceneTriangle>& triangles,
                           const std::vector<SceneMesh>& meshes) {
        for (const SceneSphere& sphere : spheres)
            text += "sphere " + numbers(sphere.center) + " " + number(sphere.radius) + " " +
                    name(sphere.material) + interior(sphere.interior) + shapeName(sphere.name);
        for (const SceneQuad& quad : quads)
            text += "quad " + numbers(quad.origin) + " " + numbers(quad.edge1) + " " +
                    numbers(quad.edge2) + " " + name(quad.material) + shapeName(quad.name);
        for (const SceneTriangle& triangle : triangles)
            text += "triangle " + numbers(triangle.p0) + " " + numbers(triangle.p1) + " " +
                    numbers(triangle.p2) + " " + name(triangle.material) +
                    shapeName(triangle.name);
        for (const SceneMesh& mesh : meshes)
            text += "mesh " + mesh.writtenPath + " " + name(mesh.material) + " scale " +
                    number(mesh.scale) + " rotate_y " + number(mesh.rotationYDegrees) +
                    " translate " + numbers(mesh.translation) + interior(mesh.interior) +
                    shapeName(mesh.name);
    };
    writeShapes(scene.spheres, scene.quads, scene.triangles, scene.meshes);
    for (const SceneObject& object : scene.objects) {
        text += "object " + object.name + " begin\n";
        writeShapes(object.spheres, object.quads, object.triangles, object.meshes);
        text += "end\n";
    }
    for (const SceneInstance& instance : scene.instances) {
        text += "instance " + scene.objects.at(instance.object).name;
        for (const PlacementStep& step : instance.steps) {
            const glm::vec3 v(step.values);
            switch (step.kind) {
            case PlacementStepKind::Scale: text += " scale " + numbers(v); break;
            case PlacementStepKind::Rotate:
                text += " rotate " + numbers(v) + " " + number(step.values.w);
                break;
            case PlacementStepKind::RotateY: text += " rotate_y " + number(step.values.w); break;
            case PlacementStepKind::Translate: text += " translate " + numbers(v); break;
            }
        }
        if (instance.motion != glm::vec3(0.0f)) text += " moving " + numbers(instance.motion);
        text += shapeName(instance.name);
    }
    if (scene.hasEnvironment())
        text += "environment " + scene.environment.writtenPath + " scale " +
                number(scene.environment.scale) + " rotate_y " +
                number(scene.environment.rotationYDegrees) + "\n";
    return text;
}

}  // namespace course
