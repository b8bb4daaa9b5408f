// The scene files of chapters 11, 12, 13 and the appendix (common/course/scene_file.h):
// every statement read as documented, the exact message for every mistake, round trips
// through formatSceneFile, the shipped scenes, and no crash or hang on garbage.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>

#include "course/error.h"
#include "course/image_file.h"
#include "course/scene_file.h"
#include "course/volume_grid.h"

namespace fs = std::filesystem;
using course::ExitCode;
using course::formatSceneFile;
using course::loadSceneFile;
using course::parseSceneText;
using course::SceneFeature;
using course::SceneSupport;
using course::MaterialKind;
using course::SceneFile;
using course::SceneMesh;
using course::SceneQuad;

namespace {

// What a program reads, as a chapter's kSceneSupport says (scene_support.h, written by
// the build from the manifests). Each includes the one before, as the chapters add them.
SceneSupport allMaterials() {
    SceneSupport support;
    support.metals.read = support.glass.read = true;
    return support;
}
SceneSupport lensAndTextures() {
    SceneSupport support = allMaterials();
    support.lens.read = support.textures.read = true;
    return support;
}
SceneSupport everything() {
    SceneSupport support = lensAndTextures();
    support.environment.read = true;
    return support;
}
SceneSupport withMedia() {
    SceneSupport support = everything();
    support.media.read = true;
    return support;
}
SceneSupport withInstances() {
    SceneSupport support = everything();
    support.instances.read = true;
    return support;
}
SceneSupport withMotion() {
    SceneSupport support = withInstances();
    support.motion.read = true;
    return support;
}

const fs::path kScenes = fs::path(COURSE_SOURCE_DIR) / "assets" / "scenes";

// A fresh folder per test, removed afterwards.
class SceneFileTest : public ::testing::Test {
protected:
    void SetUp() override {
        const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
        folder_ = fs::temp_directory_path() /
                  ("scene_file_" + std::to_string(getpid()) + "_" + info->name());
        fs::remove_all(folder_);
        fs::create_directories(folder_);
    }
    void TearDown() override { fs::remove_all(folder_); }

    fs::path write(const std::string& name, const std::string& text) const {
        const fs::path path = folder_ / name;
        fs::create_directories(path.parent_path());
        std::ofstream(path, std::ios::binary) << text;
        return path;
    }

    // The message loadSceneFile throws for `text`; fails the test if it loads.
    std::string failure(const std::string& text,
                        const std::vector<std::string>& meshFolders = {},
                        const SceneSupport& support = {}) const {
        const fs::path path = write("bad.scene", text);
        try {
            loadSceneFile(path.string(), meshFolders, support);
            ADD_FAILURE() << "loaded:\n" << text;
        } catch (const course::Failure& error) {
            EXPECT_EQ(error.code(), ExitCode::BadInput) << error.what();
            return error.what();
        }
        return "";
    }

    // "<absolute path of bad.scene>:<line>: <message>"
    std::string at(size_t line, const std::string& message) const {
        return (folder_ / "bad.scene").string() + ":" + std::to_string(line) + ": " + message;
    }

    fs::path folder_;
};

// The smallest valid scene, and lines that follow it in the error tests: line 4 is the
// first line a test appends.
const std::string kCamera = "camera eye 0 1 4 look 0 0 -1 up 0 1 0 focal 0.035 sensor 0.036\n";
const std::string kValid = kCamera +
                           "material lamp albedo 0.5 0.5 0.5 emission 1 2 3\n"
                           "sphere 0 3 0 0.5 lamp\n";

void expectSameVector(glm::vec3 a, glm::vec3 b) {
    EXPECT_EQ(a.x, b.x);
    EXPECT_EQ(a.y, b.y);
    EXPECT_EQ(a.z, b.z);
}

void expectSameScene(const SceneFile& a, const SceneFile& b) {
    expectSameVector(a.camera.eye, b.camera.eye);
    expectSameVector(a.camera.look, b.camera.look);
    expectSameVector(a.camera.up, b.camera.up);
    EXPECT_EQ(a.camera.focalLength, b.camera.focalLength);
    EXPECT_EQ(a.camera.sensorWidth, b.camera.sensorWidth);
    EXPECT_EQ(a.camera.lensRadius, b.camera.lensRadius);
    if (a.camera.lensRadius > 0.0f) {
        EXPECT_EQ(a.camera.focusDistance, b.camera.focusDistance);
    }
    ASSERT_EQ(a.textures.size(), b.textures.size());
    for (size_t i = 0; i < a.textures.size(); ++i) {
        EXPECT_EQ(a.textures[i].name, b.textures[i].name);
        EXPECT_EQ(a.textures[i].kind, b.textures[i].kind);
        EXPECT_EQ(a.textures[i].path, b.textures[i].path);
        EXPECT_EQ(a.textures[i].linear, b.textures[i].linear);
        expectSameVector(a.textures[i].color0, b.textures[i].color0);
        expectSameVector(a.textures[i].color1, b.textures[i].color1);
        EXPECT_EQ(a.textures[i].scale, b.textures[i].scale);
    }
    ASSERT_EQ(a.materials.size(), b.materials.size());
    for (size_t i = 0; i < a.materials.size(); ++i) {
        EXPECT_EQ(a.materials[i].texture, b.materials[i].texture);
        EXPECT_EQ(a.materials[i].name, b.materials[i].name);
        expectSameVector(a.materials[i].albedo, b.materials[i].albedo);
        expectSameVector(a.materials[i].emission, b.materials[i].emission);
        EXPECT_EQ(a.materials[i].kind, b.materials[i].kind);
        expectSameVector(a.materials[i].reflectance, b.materials[i].reflectance);
        expectSameVector(a.materials[i].eta, b.materials[i].eta);
        expectSameVector(a.materials[i].k, b.materials[i].k);
        EXPECT_EQ(a.materials[i].ior, b.materials[i].ior);
        EXPECT_EQ(a.materials[i].roughness, b.materials[i].roughness);
    }
    ASSERT_EQ(a.spheres.size(), b.spheres.size());
    for (size_t i = 0; i < a.spheres.size(); ++i) {
        expectSameVector(a.spheres[i].center, b.spheres[i].center);
        EXPECT_EQ(a.spheres[i].radius, b.spheres[i].radius);
        EXPECT_EQ(a.spheres[i].material, b.spheres[i].material);
        EXPECT_EQ(a.spheres[i].name, b.spheres[i].name);
    }
    ASSERT_EQ(a.quads.size(), b.quads.size());
    for (size_t i = 0; i < a.quads.size(); ++i) {
        expectSameVector(a.quads[i].origin, b.quads[i].origin);
        expectSameVector(a.quads[i].edge1, b.quads[i].edge1);
        expectSameVector(a.quads[i].edge2, b.quads[i].edge2);
        EXPECT_EQ(a.quads[i].material, b.quads[i].material);
        EXPECT_EQ(a.quads[i].name, b.quads[i].name);
    }
    ASSERT_EQ(a.triangles.size(), b.triangles.size());
    for (size_t i = 0; i < a.triangles.size(); ++i) {
        expectSameVector(a.triangles[i].p0, b.triangles[i].p0);
        expectSameVector(a.triangles[i].p1, b.triangles[i].p1);
        expectSameVector(a.triangles[i].p2, b.triangles[i].p2);
        EXPECT_EQ(a.triangles[i].material, b.triangles[i].material);
        EXPECT_EQ(a.triangles[i].name, b.triangles[i].name);
    }
    ASSERT_EQ(a.meshes.size(), b.meshes.size());
    for (size_t i = 0; i < a.meshes.size(); ++i) {
        EXPECT_EQ(a.meshes[i].path, b.meshes[i].path);
        EXPECT_EQ(a.meshes[i].writtenPath, b.meshes[i].writtenPath);
        EXPECT_EQ(a.meshes[i].material, b.meshes[i].material);
        EXPECT_EQ(a.meshes[i].scale, b.meshes[i].scale);
        EXPECT_EQ(a.meshes[i].rotationYDegrees, b.meshes[i].rotationYDegrees);
        expectSameVector(a.meshes[i].translation, b.meshes[i].translation);
        EXPECT_EQ(a.meshes[i].name, b.meshes[i].name);
    }
}

// ---------------------------------------------------------------------------------------
// Reading what is written
// ---------------------------------------------------------------------------------------

TEST_F(SceneFileTest, ReadsEveryStatement) {
    write("meshes/gem.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    const fs::path path = write("all.scene",
        "# a comment line\n"
        "camera eye 1 2 3 look 0 0 -1 up 0 1 0 focal 0.05 sensor 0.025  # the camera\n"
        "\n"
        "material white albedo 0.8 0.7 0.6\n"
        "material lamp albedo 0.1 0.2 0.3 emission 10 20 30\n"
        "sphere 0 1 2 0.5 white\n"
        "sphere 3 4 5 1.5 lamp name sun\n"
        "quad -1 0 1  2 0 0  0 0 -2 white name floor\n"
        "triangle 0 0 0  1 0 0  0 1 0 lamp\n"
        "\tmesh meshes/gem.obj white translate 1 2 3 scale 2 rotate_y 90 name gem\n"
        "mesh meshes/gem.obj lamp\n");
    const SceneFile scene = loadSceneFile(path.string());

    EXPECT_EQ(scene.path, path.string());
    expectSameVector(scene.camera.eye, {1, 2, 3});
    expectSameVector(scene.camera.look, {0, 0, -1});
    expectSameVector(scene.camera.up, {0, 1, 0});
    EXPECT_EQ(scene.camera.focalLength, 0.05f);
    EXPECT_EQ(scene.camera.sensorWidth, 0.025f);

    ASSERT_EQ(scene.materials.size(), 2u);
    EXPECT_EQ(scene.materials[0].name, "white");
    expectSameVector(scene.materials[0].albedo, {0.8f, 0.7f, 0.6f});
    EXPECT_FALSE(scene.materials[0].emits());
    expectSameVector(scene.materials[1].emission, {10, 20, 30});
    EXPECT_TRUE(scene.materials[1].emits());

    ASSERT_EQ(scene.spheres.size(), 2u);
    expectSameVector(scene.spheres[1].center, {3, 4, 5});
    EXPECT_EQ(scene.spheres[1].radius, 1.5f);
    EXPECT_EQ(scene.spheres[0].material, 0u);
    EXPECT_EQ(scene.spheres[1].material, 1u);
    EXPECT_EQ(scene.spheres[0].name, "");
    EXPECT_EQ(scene.spheres[1].name, "sun");

    ASSERT_EQ(scene.quads.size(), 1u);
    expectSameVector(scene.quads[0].origin, {-1, 0, 1});
    expectSameVector(scene.quads[0].edge1, {2, 0, 0});
    expectSameVector(scene.quads[0].edge2, {0, 0, -2});
    EXPECT_EQ(scene.quads[0].name, "floor");

    ASSERT_EQ(scene.triangles.size(), 1u);
    expectSameVector(scene.triangles[0].p1, {1, 0, 0});
    EXPECT_EQ(scene.triangles[0].material, 1u);

    ASSERT_EQ(scene.meshes.size(), 2u);
    const SceneMesh& gem = scene.meshes[0];
    EXPECT_EQ(gem.path, (folder_ / "meshes" / "gem.obj").string());
    EXPECT_EQ(gem.writtenPath, "meshes/gem.obj");
    EXPECT_EQ(gem.scale, 2.0f);
    EXPECT_EQ(gem.rotationYDegrees, 90.0f);
    expectSameVector(gem.translation, {1, 2, 3});
    EXPECT_EQ(gem.name, "gem");
    EXPECT_EQ(gem.line, 10u);
    EXPECT_EQ(scene.meshes[1].scale, 1.0f);  // defaults
    EXPECT_EQ(scene.meshes[1].rotationYDegrees, 0.0f);

    // sun, the triangle and the second mesh use the emitting material.
    EXPECT_EQ(scene.emitterCount(), 3u);
}

TEST_F(SceneFileTest, MeshTransformScalesThenTurnsThenMoves) {
    SceneMesh mesh;
    mesh.scale = 2;
    mesh.rotationYDegrees = 90;  // counter-clockwise seen from above: +x goes to -z
    mesh.translation = {1, 0, 0};
    const glm::vec4 point = mesh.worldFromMesh() * glm::vec4(1, 1, 0, 1);
    EXPECT_NEAR(point.x, 1.0f, 1e-6f);
    EXPECT_NEAR(point.y, 2.0f, 1e-6f);
    EXPECT_NEAR(point.z, -2.0f, 1e-6f);
}

TEST_F(SceneFileTest, MaterialsMayComeAfterTheirShapes) {
    const SceneFile scene = parseSceneText(kCamera +
                                               "sphere 0 0 0 1 lamp\n"
                                               "quad 0 0 0 1 0 0 0 1 0 white\n"
                                               "material white albedo 1 1 1\n"
                                               "material lamp albedo 0 0 0 emission 1 1 1\n",
                                           (folder_ / "x.scene").string());
    EXPECT_EQ(scene.spheres[0].material, 1u);
    EXPECT_EQ(scene.quads[0].material, 0u);
}

TEST_F(SceneFileTest, AcceptsWindowsLineEndsByteOrderMarkAndPlusSigns) {
    const std::string text = "\xEF\xBB\xBF" + kCamera.substr(0, kCamera.size() - 1) +
                             "\r\nmaterial lamp albedo +0.5 0.5 5e-1 emission 1 1 1\r\n"
                             "sphere 0 0 0 +1 lamp\r\n";
    const SceneFile scene = loadSceneFile(write("crlf.scene", text).string());
    EXPECT_EQ(scene.materials[0].albedo.z, 0.5f);
    EXPECT_EQ(scene.spheres[0].radius, 1.0f);
}

TEST_F(SceneFileTest, MeshesAreFoundInTheSceneFolderThenInMeshFolders) {
    const fs::path generated = folder_ / "generated";
    write("generated/meshes/a.obj", "v 0 0 0\n");
    write("generated/meshes/b.obj", "v 0 0 0\n");
    write("scenes/meshes/b.obj", "v 0 0 0\n");  // the scene's folder wins
    const fs::path scenePath = write("scenes/s.scene", kValid +
                                                           "mesh meshes/a.obj lamp\n"
                                                           "mesh meshes/b.obj lamp\n");
    const SceneFile scene = loadSceneFile(scenePath.string(), {generated.string()});
    EXPECT_EQ(scene.meshes[0].path, (generated / "meshes" / "a.obj").string());
    EXPECT_EQ(scene.meshes[1].path, (folder_ / "scenes" / "meshes" / "b.obj").string());

    // An absolute path is taken as it is.
    const std::string absolute = (generated / "meshes" / "a.obj").string();
    const SceneFile other =
        loadSceneFile(write("t.scene", kValid + "mesh " + absolute + " lamp\n").string());
    EXPECT_EQ(other.meshes[0].path, absolute);
}

// ---------------------------------------------------------------------------------------
// Round trips
// ---------------------------------------------------------------------------------------

TEST_F(SceneFileTest, FormatReadsBackAsTheSameScene) {
    write("m.obj", "v 0 0 0\n");
    const std::string text = kCamera +
                             "material a albedo 0.1 0.2 0.30000001 emission 1e-3 0 7\n"
                             "material b-2 albedo 1 0 0.333333343\n"
                             "sphere 0.1 -0.2 3e5 0.25 a name s\n"
                             "quad 1 2 3 4 5 6 7 8 10 b-2\n"
                             "triangle 0 0 0 1 0 0 0 1e-3 0 a name t\n"
                             "mesh m.obj b-2 scale 0.3 rotate_y -17.5 translate 1 2 3 name m\n";
    const std::string path = (folder_ / "x.scene").string();
    const SceneFile scene = parseSceneText(text, path);
    const std::string formatted = formatSceneFile(scene);
    const SceneFile again = parseSceneText(formatted, path);
    expectSameScene(scene, again);
    EXPECT_EQ(formatSceneFile(again), formatted);
}

TEST_F(SceneFileTest, ShippedScenesRoundTrip) {
    // The meshes (gems, teapots) and grids are generated at build time; any files with
    // their names will do here: a stand-in for each `mesh` and grid line's path.
    const fs::path generated = folder_ / "generated";
    size_t count = 0;
    for (const auto& entry : fs::directory_iterator(kScenes)) {
        if (entry.path().extension() != ".scene")
            continue;
        SCOPED_TRACE(entry.path().string());
        std::ifstream text(entry.path());
        for (std::string line; std::getline(text, line);) {
            std::istringstream words(line);
            std::string keyword, first, kind, imagePath;
            if (words >> keyword >> first && keyword == "mesh")
                write("generated/" + first, "v 0 0 0\n");
            if (keyword == "environment")
                write("generated/" + first, "PF\n1 1\n-1.0\n" + std::string(12, '\0'));
            if (keyword == "texture" && words >> kind >> imagePath && kind == "image") {
                fs::create_directories((generated / imagePath).parent_path());
                course::writeImage((generated / imagePath).string(), {1, 1, {1, 1, 1, 1}});
            }
            if (keyword == "medium" && words >> kind >> imagePath && kind == "grid") {
                fs::create_directories((generated / imagePath).parent_path());
                course::VolumeGrid grid;  // chapter 25's grids: one cell will do here
                grid.resolution = glm::ivec3(1);
                grid.boxMax = glm::vec3(1.0f);
                grid.density = {1.0f};
                course::writeVolumeGrid((generated / imagePath).string(), grid);
            }
        }
        // Every kind of material: chapters 15 and 16 ship metals and glass.
        SceneSupport all = withMedia();  // and chapter 26's instances
        all.instances.read = all.motion.read = true;
        const SceneFile scene = loadSceneFile(entry.path().string(), {generated.string()}, all);
        // Every scene is lit, by shapes or by its environment (chapter 18); the
        // grader's scene of two lights has two (chapter 12's choice of light).
        EXPECT_TRUE(scene.emitterCount() >= 1u || scene.hasEnvironment());
        if (entry.path().stem() == "cornell_two_lights") {
            EXPECT_EQ(scene.emitterCount(), 2u);
        }
        const SceneFile again = parseSceneText(formatSceneFile(scene), scene.path,
                                               {generated.string()}, all);
        expectSameScene(scene, again);
        ++count;
    }
    EXPECT_GE(count, 3u);
}

TEST_F(SceneFileTest, CornellSpheresHoldsMitsubasCornellBox) {
    const SceneFile scene = loadSceneFile((kScenes / "cornell_spheres.scene").string());
    // Mitsuba's camera: from (0, 0, 3.9) towards the origin, 39.3077 degrees wide.
    expectSameVector(scene.camera.eye, {0, 0, 3.9f});
    const double fov = 2.0 * std::atan(scene.camera.sensorWidth /
                                       (2.0 * scene.camera.focalLength)) * 180.0 / M_PI;
    EXPECT_NEAR(fov, 39.3077, 1e-4);
    // Its light: 0.46 x 0.38 at y = 0.99, facing down, radiance (18.387, 13.9873, 6.75357).
    ASSERT_EQ(scene.emitterCount(), 1u);
    const SceneQuad* light = nullptr;
    for (const SceneQuad& quad : scene.quads)
        if (scene.materials[quad.material].emits())
            light = &quad;
    ASSERT_NE(light, nullptr);
    expectSameVector(light->origin, {-0.23f, 0.99f, -0.18f});
    expectSameVector(light->edge1 + light->edge2, {0.46f, 0, 0.38f});
    EXPECT_LT(glm::cross(light->edge1, light->edge2).y, 0.0f);
    expectSameVector(scene.materials[light->material].emission, {18.387f, 13.9873f, 6.75357f});
    // Every wall faces into the room.
    for (const SceneQuad& quad : scene.quads) {
        const glm::vec3 center = quad.origin + 0.5f * (quad.edge1 + quad.edge2);
        EXPECT_LT(glm::dot(glm::cross(quad.edge1, quad.edge2), center), 0.0f) << quad.name;
    }
    EXPECT_EQ(scene.spheres.size(), 2u);
}

// ---------------------------------------------------------------------------------------
// Mistakes: each with its file:line and message
// ---------------------------------------------------------------------------------------

TEST_F(SceneFileTest, EmptyFile) { EXPECT_EQ(failure(""), at(0, "empty file")); }

TEST_F(SceneFileTest, UnknownKeyword) {
    EXPECT_EQ(failure(kValid + "cylinder 0 0 0 1 lamp\n"),
              at(4, "unknown keyword 'cylinder' (expected camera, texture, material, medium, "
                    "sphere, quad, triangle, mesh, environment, object, end or instance)"));
}

TEST_F(SceneFileTest, WrongNumberOfFields) {
    EXPECT_EQ(failure(kValid + "sphere 0 0 0 lamp\n"),
              at(4, "'sphere' needs 5 fields (CX CY CZ RADIUS MATERIAL), then optionally "
                    "interior MEDIUM and name NAME; got 4"));
    EXPECT_EQ(failure(kValid + "quad 0 0 0 1 0 0 0 1 0 lamp extra\n"),
              at(4, "'quad' needs 10 fields (OX OY OZ EX EY EZ FX FY FZ MATERIAL), then "
                    "optionally name NAME; got 11"));
    EXPECT_EQ(failure(kValid + "triangle 0 0 0 1 0 0 0 1 lamp\n"),
              at(4, "'triangle' needs 10 fields (AX AY AZ BX BY BZ CX CY CZ MATERIAL), then "
                    "optionally name NAME; got 9"));
    EXPECT_EQ(failure(kValid + "material m albedo 1 1\n"),
              at(4, "albedo needs three numbers R G B"));
    EXPECT_EQ(failure(kValid + "material m\n"),
              at(4, "'material' needs a name and a kind (NAME albedo R G B, NAME mirror, "
                    "NAME conductor eta R G B k R G B, NAME dielectric ior N)"));
    EXPECT_EQ(failure("camera eye 0 0 0 look 0 0 -1 up 0 1 0 focal 1\n"),
              at(1, "'camera' needs 16 fields (eye X Y Z look X Y Z up X Y Z focal F sensor "
                    "S, then optionally lens RADIUS focus DISTANCE and medium MEDIUM), got 14"));
    EXPECT_EQ(failure(kValid + "mesh x.obj\n"),
              at(4, "'mesh' needs a PATH and a MATERIAL, then optionally scale S, rotate_y "
                    "DEGREES, translate X Y Z, name NAME"));
    EXPECT_EQ(failure(kValid + "sphere 0 0 0 1 lamp label x\n"),
              at(4, "'sphere' takes after its 5 fields only interior MEDIUM and name NAME, "
                    "each once; got 'label'"));
}

TEST_F(SceneFileTest, WrongLabels) {
    EXPECT_EQ(failure("camera eye 0 0 0 at 0 0 -1 up 0 1 0 focal 1 sensor 1\n"),
              at(1, "'camera' expects 'look' here, got 'at'"));
    EXPECT_EQ(failure(kValid + "material m colour 1 1 1\n"),
              at(4, "unknown material kind 'colour' (expected albedo, mirror, conductor, "
                    "dielectric or boundary)"));
    EXPECT_EQ(failure(kValid + "material m albedo 1 1 1 glow 1 1 1\n"),
              at(4, "unexpected 'glow' in material 'm' (albedo)"));
}

TEST_F(SceneFileTest, BadNumbers) {
    EXPECT_EQ(failure(kValid + "sphere 0 0 zero 1 lamp\n"), at(4, "'zero' is not a number"));
    EXPECT_EQ(failure(kValid + "sphere 0 0 1.5.2 1 lamp\n"), at(4, "'1.5.2' is not a number"));
    const std::string notFinite = " is not a finite number";
    EXPECT_EQ(failure(kValid + "sphere 0 0 0 nan lamp\n"), at(4, "'nan'" + notFinite));
    EXPECT_EQ(failure(kValid + "sphere inf 0 0 1 lamp\n"), at(4, "'inf'" + notFinite));
    EXPECT_EQ(failure(kValid + "sphere -INF 0 0 1 lamp\n"),
              at(4, "'-INF' is not a finite number"));
    EXPECT_EQ(failure(kValid + "sphere 1e39 0 0 1 lamp\n"),
              at(4, "'1e39' is too large for a float"));
    EXPECT_EQ(failure(kValid + "sphere 1e999 0 0 1 lamp\n"),
              at(4, "'1e999' is out of range for a number"));
}

TEST_F(SceneFileTest, UndefinedMaterial) {
    EXPECT_EQ(failure(kValid + "\n# comment\nsphere 0 0 0 1 gold\n"),
              at(6, "material 'gold' is not defined"));
}

TEST_F(SceneFileTest, DuplicateMaterial) {
    EXPECT_EQ(failure(kValid + "material lamp albedo 1 1 1\n"),
              at(4, "material 'lamp' is already defined on line 2"));
}

TEST_F(SceneFileTest, BadMaterialValues) {
    EXPECT_EQ(failure(kValid + "material m albedo 1.2 0 0\n"),
              at(4, "albedo '1.2' is outside [0, 1]: a surface cannot reflect more light "
                    "than reaches it"));
    EXPECT_EQ(failure(kValid + "material m albedo 0 0 0 emission 1 -1 1\n"),
              at(4, "emission '-1' is negative"));
    EXPECT_EQ(failure(kValid + "material 9lives albedo 0 0 0\n"),
              at(4, "material name '9lives': use letters, digits, '_' and '-', starting "
                    "with a letter or '_'"));
    EXPECT_EQ(failure(kValid + "sphere 0 0 0 1 lamp name a.b\n"),
              at(4, "shape name 'a.b': use letters, digits, '_' and '-', starting with a "
                    "letter or '_'"));
}

// The kinds of material: the words, their defaults, and the writer writing them back.
TEST_F(SceneFileTest, MaterialKinds) {
    const std::string text = kValid +
                             "material m mirror\n"
                             "material r mirror reflectance 0.9 0.8 0.7\n"
                             "material gold conductor eta 0.2 0.4 1.4 k 3.6 2.4 1.8\n"
                             "material brushed conductor eta 0.2 0.4 1.4 k 3.6 2.4 1.8 "
                             "roughness 0.2\n"
                             "material glass dielectric ior 1.5\n"
                             "material frosted dielectric ior 1.33 roughness 0.1\n";
    const std::string path = (folder_ / "kinds.scene").string();
    const SceneFile scene = parseSceneText(text, path, {}, allMaterials());
    ASSERT_EQ(scene.materials.size(), 7u);
    const auto& m = scene.materials;
    EXPECT_EQ(m[0].kind, MaterialKind::Diffuse);
    EXPECT_EQ(m[1].kind, MaterialKind::Mirror);
    expectSameVector(m[1].reflectance, glm::vec3(1.0f));
    expectSameVector(m[2].reflectance, glm::vec3(0.9f, 0.8f, 0.7f));
    EXPECT_EQ(m[3].kind, MaterialKind::Conductor);
    expectSameVector(m[3].eta, glm::vec3(0.2f, 0.4f, 1.4f));
    expectSameVector(m[3].k, glm::vec3(3.6f, 2.4f, 1.8f));
    EXPECT_EQ(m[3].roughness, 0.0f);
    EXPECT_EQ(m[4].roughness, 0.2f);
    EXPECT_EQ(m[5].kind, MaterialKind::Dielectric);
    EXPECT_EQ(m[5].ior, 1.5f);
    EXPECT_EQ(m[6].ior, 1.33f);
    EXPECT_EQ(m[6].roughness, 0.1f);
    EXPECT_EQ(m[6].line, 9u);
    const SceneFile again =
        parseSceneText(formatSceneFile(scene), path, {}, allMaterials());
    expectSameScene(scene, again);
}

TEST_F(SceneFileTest, MaterialMistakes) {
    auto all = [this](const std::string& line) {
        return failure(kValid + line + "\n", {}, allMaterials());
    };
    EXPECT_EQ(all("material m metal"),
              at(4, "unknown material kind 'metal' (expected albedo, mirror, conductor, "
                    "dielectric or boundary)"));
    EXPECT_EQ(all("material m conductor eta 1 1 1 k 1 1 1 roughness -0.1"),
              at(4, "roughness '-0.1' is negative"));
    EXPECT_EQ(all("material m conductor eta 1 0 1 k 1 1 1"), at(4, "eta '0' must be above 0"));
    EXPECT_EQ(all("material m conductor eta 1 1 1 k -1 0 0"), at(4, "k '-1' is negative"));
    EXPECT_EQ(all("material m conductor eta 1 1 1"),
              at(4, "'material' conductor eta R G B k R G B: too few fields"));
    EXPECT_EQ(all("material m dielectric ior 0"), at(4, "ior '0' must be above 0"));
    EXPECT_EQ(all("material m dielectric ior -1.5"), at(4, "ior '-1.5' must be above 0"));
    EXPECT_EQ(all("material m mirror emission 1 1 1"),
              at(4, "only an 'albedo' material may have an emission, not material 'm' "
                    "(mirror)"));
    EXPECT_EQ(all("material m dielectric ior 1.5 shiny"),
              at(4, "unexpected 'shiny' in material 'm' (dielectric)"));
    EXPECT_EQ(all("material m mirror roughness 0.1"),
              at(4, "unexpected 'roughness' in material 'm' (mirror)"));
    EXPECT_EQ(all("material m albedo 1 1 1 emission 1 1 1 emission 2 2 2"),
              at(4, "unexpected 'emission' in material 'm' (albedo)"));
    EXPECT_EQ(all("material m mirror reflectance 2 1 1"),
              at(4, "reflectance '2' is outside [0, 1]: a surface cannot reflect more light "
                    "than reaches it"));
    EXPECT_EQ(all("material m dielectric ior 1.5 roughness"),
              at(4, "roughness needs a number, the GGX alpha"));
}

TEST_F(SceneFileTest, ProgramsThatRenderOnlyDiffuseSayWhichMaterialTheyMet) {
    EXPECT_EQ(failure(kValid + "sphere 0 0 0 1 glass\nmaterial glass dielectric ior 1.5\n"),
              at(5, "material 'glass' is a dielectric: this program renders only diffuse "
                    "materials ('albedo R G B')"));
}

TEST_F(SceneFileTest, NonPositiveRadius) {
    EXPECT_EQ(failure(kValid + "sphere 0 0 0 -1 lamp\n"),
              at(4, "the sphere's radius must be positive, got '-1'"));
    EXPECT_EQ(failure(kValid + "sphere 0 0 0 0 lamp\n"),
              at(4, "the sphere's radius must be positive, got '0'"));
}

TEST_F(SceneFileTest, ZeroAreaShapes) {
    const std::string quad = "the quad has zero area: an edge is zero or the two edges are "
                             "parallel";
    EXPECT_EQ(failure(kValid + "quad 0 0 0  1 0 0  2 0 0 lamp\n"), at(4, quad));
    EXPECT_EQ(failure(kValid + "quad 0 0 0  0 0 0  0 1 0 lamp\n"), at(4, quad));
    EXPECT_EQ(failure(kValid + "triangle 0 0 0  1 1 1  2 2 2 lamp\n"),
              at(4, "the triangle has zero area: its corners are on one line"));
    // Thin is not zero: a 1 mm by 10 m quad is a real quad.
    EXPECT_NO_THROW(parseSceneText(kValid + "quad 0 0 0 10 0 0 0 0.001 0 lamp\n", "x"));
}

TEST_F(SceneFileTest, Camera) {
    EXPECT_EQ(failure(kValid + kCamera),
              at(4, "a second camera (the first is on line 1)"));
    EXPECT_EQ(failure("camera eye 0 0 0 look 0 0 0 up 0 1 0 focal 1 sensor 1\n"),
              at(1, "the camera's look direction must not be zero"));
    EXPECT_EQ(failure("camera eye 0 0 0 look 0 2 0 up 0 1 0 focal 1 sensor 1\n"),
              at(1, "the camera's up must not be parallel to its look direction"));
    EXPECT_EQ(failure("camera eye 0 0 0 look 0 0 -1 up 0 1 0 focal 0 sensor 1\n"),
              at(1, "the camera's focal length and sensor width must be positive"));
    EXPECT_EQ(failure("material lamp albedo 0 0 0 emission 1 1 1\nsphere 0 0 0 1 lamp\n"),
              at(0, "no camera: a scene needs one 'camera' line"));
    EXPECT_EQ(failure("# only a comment\n"),
              at(0, "no camera: a scene needs one 'camera' line"));
}

// ---------------------------------------------------------------------------------------
// The thin lens and textures (chapter 17 on)
// ---------------------------------------------------------------------------------------

const std::string kLensCamera =
    "camera eye 0 1 4 look 0 0 -1 up 0 1 0 focal 0.035 sensor 0.036 lens 0.01 focus 2.5\n";

TEST_F(SceneFileTest, LensAndTexturesAreReadAndWrittenBack) {
    course::Image tiny{2, 1, {0.2f, 0.4f, 0.6f, 1, 1, 1, 1, 1}};
    fs::create_directories(folder_ / "generated" / "textures");
    course::writeImage((folder_ / "generated" / "textures" / "tiny.png").string(), tiny);
    write("m.obj", "v 0 0 0\n");
    const std::string text = kLensCamera +
                             "texture photo image textures/tiny.png\n"
                             "texture normals image textures/tiny.png linear\n"
                             "texture tiles checker 0.1 0.2 0.3 0.9 0.8 0.7 scale 4\n"
                             "texture plain checker 0 0 0 1 1 1\n"
                             "material floor albedo texture tiles\n"
                             "material lamp albedo texture photo emission 1 1 1\n"
                             "quad 0 0 0 1 0 0 0 0 -1 floor\n"
                             "mesh m.obj lamp\n";
    const std::string path = (folder_ / "x.scene").string();
    const std::vector<std::string> folders = {(folder_ / "generated").string()};
    const SceneFile scene = parseSceneText(text, path, folders, lensAndTextures());
    EXPECT_EQ(scene.camera.lensRadius, 0.01f);
    EXPECT_EQ(scene.camera.focusDistance, 2.5f);
    ASSERT_EQ(scene.textures.size(), 4u);
    EXPECT_EQ(scene.textures[0].kind, course::TextureKind::Image);
    EXPECT_EQ(scene.textures[0].path, (folder_ / "generated" / "textures" / "tiny.png").string());
    EXPECT_FALSE(scene.textures[0].linear);
    EXPECT_TRUE(scene.textures[1].linear);
    EXPECT_EQ(scene.textures[2].kind, course::TextureKind::Checker);
    expectSameVector(scene.textures[2].color1, {0.9f, 0.8f, 0.7f});
    EXPECT_EQ(scene.textures[2].scale, 4.0f);
    EXPECT_EQ(scene.textures[3].scale, 1.0f);
    EXPECT_EQ(scene.materials[0].texture, 2);
    EXPECT_EQ(scene.materials[1].texture, 0);
    EXPECT_EQ(scene.materials[1].emission, glm::vec3(1.0f));
    const std::string formatted = formatSceneFile(scene);
    const SceneFile again = parseSceneText(formatted, path, folders, lensAndTextures());
    expectSameScene(scene, again);
    EXPECT_EQ(formatSceneFile(again), formatted);
}

TEST_F(SceneFileTest, LensAndTextureMistakes) {
    auto lens = [this](const std::string& text) {
        return failure(text, {}, lensAndTextures());
    };
    const std::string pinhole = kCamera.substr(0, kCamera.size() - 1);
    EXPECT_EQ(lens(pinhole + " lens -0.1 focus 2\n"),
              at(1, "the lens radius '-0.1' must be 0 or more"));
    EXPECT_EQ(lens(pinhole + " lens 0.1 focus 0\n"),
              at(1, "the focus distance '0' must be positive"));
    EXPECT_EQ(lens(pinhole + " lens 0.1 focal 2\n"),
              at(1, "'camera' expects 'focus' here, got 'focal'"));
    EXPECT_EQ(lens(kValid + "material m albedo texture wood\ntexture wood checker 0 0 0 1 1 1\n"),
              at(4, "texture 'wood' is not defined on an earlier line"));
    EXPECT_EQ(lens(kValid + "texture t checker 0 0 0 1 1 1\ntexture t checker 0 0 0 1 1 1\n"),
              at(5, "texture 't' is already defined on line 4"));
    EXPECT_EQ(lens(kValid + "texture t checker 0 0 0 1 1 2\n"),
              at(4, "checker colour '2' is outside [0, 1]: a surface cannot reflect more "
                    "light than reaches it"));
    EXPECT_EQ(lens(kValid + "texture t checker 0 0 0 1 1 1 scale -2\n"),
              at(4, "the checker's scale '-2' must be positive"));
    EXPECT_EQ(lens(kValid + "texture t marble\n"),
              at(4, "unknown texture kind 'marble' (expected image or checker)"));
    EXPECT_EQ(lens(kValid + "texture t image missing.png\n"),
              at(4, "image file 'missing.png' not found (looked for " +
                        (folder_ / "missing.png").string() + ")"));
    write("fake.png", "this is text, not a picture\n");
    EXPECT_EQ(lens(kValid + "texture t image fake.png\n"),
              at(4, "image 'fake.png' (" + (folder_ / "fake.png").string() +
                        ") is not a PNG or JPEG image (unknown image type)"));
    EXPECT_EQ(lens(kValid + "texture t image fake.png srgb\n"),
              at(4, "'texture NAME image PATH' takes only the word 'linear' after PATH"));
    // A textured material on a shape without texture coordinates, wherever it is defined.
    EXPECT_EQ(lens(kValid + "sphere 0 0 0 1 tiled\ntexture t checker 0 0 0 1 1 1\n"
                            "material tiled albedo texture t\n"),
              at(4, "material 'tiled' is textured, and this shape has no texture coordinates: "
                    "textures apply to quads and meshes"));
}

TEST_F(SceneFileTest, ProgramsWithoutLensOrTexturesSaySo) {
    EXPECT_EQ(failure(kValid + "texture t checker 0 0 0 1 1 1\n"),
              at(4, "texture 't': this program has no textures"));
    EXPECT_EQ(failure(kLensCamera + kValid.substr(kCamera.size())),
              at(1, "the camera has a lens: this program has a pinhole camera"));
    // A lens of radius 0 is a pinhole: every program renders it.
    const std::string pinhole = kCamera.substr(0, kCamera.size() - 1) + " lens 0 focus 3\n";
    EXPECT_NO_THROW(parseSceneText(pinhole + kValid.substr(kCamera.size()), "x"));
}

// Where the course first reads what a program does not is the chapter's to say (its
// manifest, through kSceneSupport): the reader adds it to the message, and says nothing
// of chapters when it is not given.
TEST_F(SceneFileTest, MessagesNameTheChapterThatFirstReadsWhatIsMissing) {
    SceneSupport diffuse;
    diffuse.metals.firstReadBy = "chapter 15";
    diffuse.glass.firstReadBy = "chapter 16";
    diffuse.lens.firstReadBy = diffuse.textures.firstReadBy = "chapter 17";
    diffuse.environment.firstReadBy = "chapter 18";
    EXPECT_EQ(failure(kValid + "sphere 0 0 0 1 m\nmaterial m mirror\n", {}, diffuse),
              at(5, "material 'm' is a mirror: this program renders only diffuse materials "
                    "('albedo R G B'); mirrors and conductors come in chapter 15"));
    const std::string glass = kValid + "sphere 0 0 0 1 g\nmaterial g dielectric ior 1.5\n";
    EXPECT_EQ(failure(glass, {}, diffuse),
              at(5, "material 'g' is a dielectric: this program renders only diffuse "
                    "materials ('albedo R G B'); glass comes in chapter 16"));
    SceneSupport opaque = diffuse;
    opaque.metals = SceneFeature{true, ""};
    EXPECT_EQ(failure(glass, {}, opaque),
              at(5, "material 'g' is a dielectric: this program renders only opaque "
                    "materials (albedo, mirror, conductor); glass comes in chapter 16"));
    EXPECT_NO_THROW(parseSceneText(kValid + "sphere 0 0 0 1 m\nmaterial m mirror\n", "x",
                                   {}, opaque));
    EXPECT_EQ(failure(kValid + "texture t checker 0 0 0 1 1 1\n", {}, opaque),
              at(4, "texture 't': this program has no textures; textures come in chapter 17"));
    EXPECT_EQ(failure(kLensCamera + kValid.substr(kCamera.size()), {}, opaque),
              at(1, "the camera has a lens: this program has a pinhole camera; the thin lens "
                    "comes in chapter 17"));
    write("sky.pfm", std::string("PF\n1 1\n-1.0\n") + std::string(12, '\0'));
    EXPECT_EQ(failure(kValid + "environment sky.pfm\n", {}, opaque),
              at(4, "this program has no environment light; it comes in chapter 18"));
}

// ---------------------------------------------------------------------------------------
// The environment (chapter 18 on)
// ---------------------------------------------------------------------------------------

// A 2 x 1 PFM: one black texel, one grey.
const std::string kTinyPfm = std::string("PF\n2 1\n-1.0\n") + std::string(12, '\0') +
                             std::string("\0\0\0\x3f\0\0\0\x3f\0\0\0\x3f", 12);

TEST_F(SceneFileTest, EnvironmentIsReadAndWrittenBack) {
    write("sky.pfm", kTinyPfm);
    // No emitting shape: the environment lights the scene.
    const std::string text = kCamera + "material grey albedo 0.5 0.5 0.5\n"
                                       "sphere 0 0 0 1 grey\n"
                                       "environment sky.pfm rotate_y 30 scale 2.5\n";
    const std::string path = (folder_ / "x.scene").string();
    const SceneFile scene = parseSceneText(text, path, {}, everything());
    ASSERT_TRUE(scene.hasEnvironment());
    EXPECT_EQ(scene.environment.path, (folder_ / "sky.pfm").string());
    EXPECT_EQ(scene.environment.scale, 2.5f);
    EXPECT_EQ(scene.environment.rotationYDegrees, 30.0f);
    EXPECT_EQ(scene.environment.line, 4u);
    const SceneFile again =
        parseSceneText(formatSceneFile(scene), path, {}, everything());
    EXPECT_EQ(again.environment.scale, 2.5f);
    EXPECT_EQ(again.environment.rotationYDegrees, 30.0f);
    EXPECT_EQ(again.environment.path, scene.environment.path);
}

TEST_F(SceneFileTest, EnvironmentMistakes) {
    write("sky.pfm", kTinyPfm);
    write("photo.pfm", "P6\n2 1\n255\n");
    write("short.pfm", "PF\n4 4\n-1.0\n" + std::string(12, '\0'));
    auto env = [this](const std::string& line) {
        return failure(kValid + line + "\n", {}, everything());
    };
    EXPECT_EQ(env("environment sky.pfm\nenvironment sky.pfm"),
              at(5, "a second environment (the first is on line 4)"));
    EXPECT_EQ(env("environment sky.pfm scale 0"),
              at(4, "the environment's scale must be positive, got '0'"));
    EXPECT_EQ(env("environment sky.pfm scale 1 scale 2"), at(4, "'scale' is given twice"));
    EXPECT_EQ(env("environment sky.pfm rotate_x 3"),
              at(4, "unknown environment option 'rotate_x' (expected scale or rotate_y)"));
    EXPECT_EQ(env("environment sky.pfm rotate_y"), at(4, "'rotate_y' needs 1 number"));
    EXPECT_EQ(env("environment nowhere.pfm"),
              at(4, "environment file 'nowhere.pfm' not found (looked for " +
                        (folder_ / "nowhere.pfm").string() + ")"));
    EXPECT_EQ(env("environment photo.pfm"),
              at(4, "environment 'photo.pfm' (" + (folder_ / "photo.pfm").string() +
                        ") is not a PFM or OpenEXR image (it starts with neither PF, Pf nor "
                        "the EXR magic number)"));
    EXPECT_EQ(env("environment short.pfm"),
              at(4, "environment 'short.pfm' (" + (folder_ / "short.pfm").string() +
                        ") is not a whole PFM image (the file ends before its last row)"));
    EXPECT_EQ(failure(kValid + "environment sky.pfm\n", {}, lensAndTextures()),
              at(4, "this program has no environment light"));
}

TEST_F(SceneFileTest, NoEmitter) {
    const std::string message = "no emitter: no shape uses a material with an emission";
    EXPECT_EQ(failure(kCamera + "material white albedo 1 1 1\nsphere 0 0 0 1 white\n"),
              at(0, message));
    // An emitting material that no shape uses lights nothing.
    EXPECT_EQ(failure(kCamera + "material lamp albedo 0 0 0 emission 1 1 1\n"), at(0, message));
    EXPECT_EQ(failure(kCamera + "material dark albedo 0 0 0 emission 0 0 0\n"
                                "sphere 0 0 0 1 dark\n"),
              at(0, message));
}

TEST_F(SceneFileTest, BinaryBytes) {
    EXPECT_EQ(failure(kValid + std::string("sphere 0 0 0 1 lamp\0\n", 21)),
              at(4, "binary data (a control byte) in what should be a text file"));
    EXPECT_EQ(failure(std::string("\x7f" "ELF\x02\x01\x01", 7)),
              at(1, "binary data (a control byte) in what should be a text file"));
}

TEST_F(SceneFileTest, MeshMistakes) {
    write("m.obj", "v 0 0 0\n");
    EXPECT_EQ(failure(kValid + "mesh m.obj lamp scale 0\n"),
              at(4, "the mesh's scale must be positive, got '0'"));
    EXPECT_EQ(failure(kValid + "mesh m.obj lamp scale 1 scale 2\n"),
              at(4, "'scale' is given twice"));
    EXPECT_EQ(failure(kValid + "mesh m.obj lamp translate 1 2\n"),
              at(4, "'translate' needs 3 numbers"));
    EXPECT_EQ(failure(kValid + "mesh m.obj lamp name\n"), at(4, "'name' needs 1 name"));
    EXPECT_EQ(failure(kValid + "mesh m.obj lamp rotate_x 90\n"),
              at(4, "unknown mesh option 'rotate_x' (expected scale, rotate_y, translate, "
                    "interior or name)"));
    EXPECT_EQ(failure(kValid + "mesh missing.obj lamp\n", {"/nonexistent/generated"}),
              at(4, "mesh file 'missing.obj' not found (looked for " +
                        (folder_ / "missing.obj").string() +
                        ", /nonexistent/generated/missing.obj)"));
    EXPECT_EQ(failure(kValid + "mesh m.obj gold\n"), at(4, "material 'gold' is not defined"));
}

TEST_F(SceneFileTest, FilesThatCannotBeRead) {
    const std::string missing = (folder_ / "missing.scene").string();
    try {
        loadSceneFile(missing);
        FAIL() << "loaded a missing file";
    } catch (const course::Failure& error) {
        EXPECT_EQ(error.code(), ExitCode::BadInput);
        EXPECT_EQ(std::string(error.what()),
                  missing + ": cannot open (No such file or directory)");
    }
    try {
        loadSceneFile(folder_.string());
        FAIL() << "loaded a directory";
    } catch (const course::Failure& error) {
        EXPECT_EQ(std::string(error.what()),
                  folder_.string() + ": cannot open: it is a directory");
    }
}

TEST_F(SceneFileTest, GarbageNeverCrashes) {
    // Random bytes, and random mixes of the format's own words: every outcome is a scene
    // or a BadInput message naming the file, quickly.
    std::mt19937 random(7);
    const std::vector<std::string> words = {
        "camera", "material", "sphere", "quad", "triangle", "mesh", "eye", "look", "up",
        "focal", "sensor", "albedo", "emission", "name", "scale", "rotate_y", "translate",
        "lamp", "0", "1", "-1", "1e3", "nan", "#", "\n", "\n", " ", "\t", "x.obj",
        "texture", "checker", "image", "lens", "focus", "medium", "homogeneous", "grid",
        "sigma_a", "sigma_s", "g", "interior", "boundary", "fog", "0.5", "smoke.vol"};
    for (int trial = 0; trial < 400; ++trial) {
        std::string text = trial % 4 == 0 ? std::string() : kValid;
        const int length = int(random() % 60);
        for (int i = 0; i < length; ++i) {
            if (trial % 2 == 0)
                text += char(random() % 256);
            else
                text += words[random() % words.size()] + " ";
        }
        try {
            parseSceneText(text, "garbage.scene", {}, withMedia());
        } catch (const course::Failure& error) {
            EXPECT_EQ(error.code(), ExitCode::BadInput);
            EXPECT_EQ(std::string(error.what()).rfind("garbage.scene:", 0), 0u) << error.what();
        }
    }
}

// ---------------------------------------------------------------- participating media

// A 2 x 1 x 1 grid of densities 0.25 and 4 in the box [-1, 1] x [0, 1] x [0, 1].
std::string tinyGrid() {
    course::VolumeGrid grid;
    grid.resolution = {2, 1, 1};
    grid.boxMin = {-1.0f, 0.0f, 0.0f};
    grid.boxMax = {1.0f, 1.0f, 1.0f};
    grid.density = {0.25f, 4.0f};
    const fs::path path = fs::temp_directory_path() / ("tiny_" + std::to_string(getpid()) + ".vol");
    course::writeVolumeGrid(path.string(), grid);
    std::ifstream file(path, std::ios::binary);
    std::string bytes((std::istreambuf_iterator<char>(file)), std::istreambuf_iterator<char>());
    fs::remove(path);
    return bytes;
}

TEST_F(SceneFileTest, MediaAreReadAndWrittenBack) {
    write("smoke.vol", tinyGrid());
    write("box.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    const std::string text =
        "camera eye 0 1 4 look 0 0 -1 up 0 1 0 focal 0.035 sensor 0.036 medium fog lens "
        "0.01 focus 3\n"
        "medium fog homogeneous sigma_a 0.01 0.02 0.03 sigma_s 0.1 0.2 0.3\n"
        "medium smoke grid smoke.vol albedo 0.9 0.8 0.7 scale 20 g 0.6\n"
        "medium ink homogeneous sigma_a 5 1 0.5 sigma_s 0 0 0 g -0.3\n"
        "material edge boundary\n"
        "material glass dielectric ior 1.5\n"
        "material lamp albedo 0 0 0 emission 5 5 5\n"
        "sphere 0 3 0 0.5 lamp\n"
        "sphere 0 0 0 1 edge interior smoke name cloud\n"
        "sphere 2 0 0 1 glass name bauble interior ink\n"
        "mesh box.obj glass interior ink scale 2\n";
    const std::string path = (folder_ / "media.scene").string();
    const SceneFile scene = parseSceneText(text, path, {}, withMedia());
    ASSERT_EQ(scene.media.size(), 3u);
    EXPECT_EQ(scene.camera.medium, 0);
    EXPECT_EQ(scene.camera.lensRadius, 0.01f);
    expectSameVector(scene.media[0].sigmaA, {0.01f, 0.02f, 0.03f});
    expectSameVector(scene.media[0].sigmaS, {0.1f, 0.2f, 0.3f});
    EXPECT_EQ(scene.media[0].g, 0.0f);
    EXPECT_EQ(scene.media[1].kind, course::MediumKind::Grid);
    EXPECT_EQ(scene.media[1].path, (folder_ / "smoke.vol").string());
    EXPECT_EQ(scene.media[1].scale, 20.0f);
    EXPECT_EQ(scene.media[1].g, 0.6f);
    EXPECT_EQ(scene.media[2].g, -0.3f);
    EXPECT_EQ(scene.materials[0].kind, MaterialKind::Boundary);
    EXPECT_EQ(scene.spheres[0].interior, -1);
    EXPECT_EQ(scene.spheres[1].interior, 1);
    EXPECT_EQ(scene.spheres[1].name, "cloud");
    EXPECT_EQ(scene.spheres[2].interior, 2);
    EXPECT_EQ(scene.meshes[0].interior, 2);
    EXPECT_EQ(scene.meshes[0].scale, 2.0f);
    const std::string formatted = formatSceneFile(scene);
    const SceneFile again = parseSceneText(formatted, path, {}, withMedia());
    EXPECT_EQ(formatSceneFile(again), formatted);
    EXPECT_EQ(again.camera.medium, 0);
    EXPECT_EQ(again.spheres[1].interior, 1);
    EXPECT_EQ(again.meshes[0].interior, 2);
    EXPECT_EQ(again.media[1].albedo, scene.media[1].albedo);
}

TEST_F(SceneFileTest, MediumMistakesAreExit3AtTheirLine) {
    write("smoke.vol", tinyGrid());
    write("short.vol", tinyGrid().substr(0, 50));
    write("text.vol", "not a grid at all, but long enough to have a header of 48 bytes...");
    auto bad = [this](const std::string& lines) {
        return failure(kValid + lines + "\n", {}, withMedia());
    };
    const std::string fog = "medium fog homogeneous sigma_a 0 0 0 sigma_s 1 1 1";
    EXPECT_EQ(bad("material e boundary\nsphere 0 0 0 1 e interior mist"),
              at(5, "medium 'mist' is not defined"));
    EXPECT_EQ(bad("medium fog homogeneous sigma_a 0 -1 0 sigma_s 1 1 1"),
              at(4, "sigma_a '-1' is negative"));
    EXPECT_EQ(bad(fog + " g 1"),
              at(4, "g '1' must lie strictly between -1 and 1 (the phase function's mean "
                    "cosine)"));
    EXPECT_EQ(bad(fog + " g -1.5"),
              at(4, "g '-1.5' must lie strictly between -1 and 1 (the phase function's mean "
                    "cosine)"));
    EXPECT_EQ(bad(fog + " scale 2"),
              at(4, "unexpected 'scale' in medium 'fog' (after sigma_s: g G)"));
    EXPECT_EQ(bad(fog + "\n" + fog),
              at(5, "medium 'fog' is already defined on line 4"));
    EXPECT_EQ(bad("medium fog cloudy 1"),
              at(4, "unknown medium kind 'cloudy' (expected homogeneous or grid)"));
    EXPECT_EQ(bad(fog + "\nmaterial w albedo 1 1 1\nsphere 0 0 0 1 w interior fog"),
              at(6, "an interior medium needs a surface light passes through, a 'boundary' "
                    "or 'dielectric' material; 'w' is albedo"));
    EXPECT_EQ(bad("medium s grid nowhere.vol albedo 1 1 1"),
              at(4, "grid file 'nowhere.vol' not found (looked for " +
                        (folder_ / "nowhere.vol").string() + ")"));
    EXPECT_EQ(bad("medium s grid short.vol albedo 1 1 1"),
              at(4, "grid 'short.vol' (" + (folder_ / "short.vol").string() +
                        "): 50 bytes, where its header promises 56"));
    EXPECT_EQ(bad("medium s grid text.vol albedo 1 1 1"),
              at(4, "grid 'text.vol' (" + (folder_ / "text.vol").string() +
                        "): not a .vol grid (no 'VOL' at its start)"));
    EXPECT_EQ(bad("medium s grid smoke.vol albedo 1 2 1"),
              at(4, "albedo '2' is outside [0, 1]: a surface cannot reflect more light than "
                    "reaches it"));
    EXPECT_EQ(bad("medium s grid smoke.vol albedo 1 1 1 scale 0"),
              at(4, "the grid's scale '0' must be positive"));
    EXPECT_EQ(failure("camera eye 0 1 4 look 0 0 -1 up 0 1 0 focal 0.035 sensor 0.036 "
                      "medium fog medium fog\n", {}, withMedia()),
              at(1, "unexpected 'medium' in 'camera' (after the sensor: lens RADIUS focus "
                    "DISTANCE, medium MEDIUM, shutter OPEN CLOSE, each once)"));
    // A program that renders no media says so at the first line that needs them.
    EXPECT_EQ(failure(kValid + "material e boundary\n" + fog + "\n", {}, everything()),
              at(4, "this program renders no participating media (medium statements, "
                    "boundary materials)"));
}

TEST_F(SceneFileTest, AVolumeGridReadsBackAsWritten) {
    write("smoke.vol", tinyGrid());
    const course::VolumeGrid grid = course::readVolumeGrid((folder_ / "smoke.vol").string());
    EXPECT_EQ(grid.resolution, glm::ivec3(2, 1, 1));
    expectSameVector(grid.boxMin, {-1.0f, 0.0f, 0.0f});
    expectSameVector(grid.boxMax, {1.0f, 1.0f, 1.0f});
    EXPECT_EQ(grid.at(0, 0, 0), 0.25f);
    EXPECT_EQ(grid.at(1, 0, 0), 4.0f);
    std::string negative = tinyGrid();
    const float minusOne = -1.0f;
    std::memcpy(negative.data() + 48, &minusOne, 4);
    write("negative.vol", negative);
    try {
        course::readVolumeGrid((folder_ / "negative.vol").string());
        ADD_FAILURE() << "read a negative density";
    } catch (const course::Failure& error) {
        EXPECT_EQ(error.code(), ExitCode::BadInput);
        EXPECT_NE(std::string(error.what()).find("density 0 is negative"), std::string::npos);
    }
}

}  // namespace

// ---------------------------------------------------------------------------------------
// Objects and instances
// ---------------------------------------------------------------------------------------

const std::string kObjects =
    "material white albedo 0.8 0.8 0.8\n"
    "object pot begin\n"
    "  sphere 0 0.5 0 0.5 white name lid\n"
    "  quad 0 0 0 1 0 0 0 0 1 white\n"
    "  triangle 0 0 0 1 0 0 0 1 0 white\n"
    "end\n"
    "instance pot\n"
    "instance pot scale 2 rotate_y 30 translate 1 0 -2 name big\n"
    "instance pot scale -1 1 0.5 rotate 1 1 0 45 translate 0 1 0 moving 0.5 0 0\n";

TEST_F(SceneFileTest, ObjectsAndInstancesAreReadAndWrittenBack) {
    const std::string text =
        "camera eye 0 1 4 look 0 0 -1 up 0 1 0 focal 0.035 sensor 0.036 shutter 0 0.5\n"
        "material lamp albedo 0 0 0 emission 1 1 1\nsphere 0 3 0 0.5 lamp\n" + kObjects;
    const std::string path = (folder_ / "objects.scene").string();
    const SceneFile scene = parseSceneText(text, path, {}, withMotion());
    ASSERT_EQ(scene.objects.size(), 1u);
    EXPECT_EQ(scene.spheres.size(), 1u);  // the lamp: the object's shapes are its own
    const course::SceneObject& pot = scene.objects[0];
    EXPECT_EQ(pot.name, "pot");
    EXPECT_EQ(pot.line, 5u);
    EXPECT_EQ(pot.spheres.size(), 1u);
    EXPECT_EQ(pot.spheres[0].name, "lid");
    EXPECT_EQ(pot.quads.size(), 1u);
    EXPECT_EQ(pot.triangles.size(), 1u);
    EXPECT_EQ(pot.triangles[0].material, 1u);
    ASSERT_EQ(scene.instances.size(), 3u);
    EXPECT_TRUE(scene.instances[0].steps.empty());
    EXPECT_EQ(scene.instances[1].name, "big");
    EXPECT_EQ(scene.instances[1].steps.size(), 3u);
    expectSameVector(scene.instances[2].motion, {0.5f, 0.0f, 0.0f});
    EXPECT_EQ(scene.camera.shutterOpen, 0.0f);
    EXPECT_EQ(scene.camera.shutterClose, 0.5f);
    EXPECT_EQ(scene.emitterCount(), 1u);
    const std::string formatted = formatSceneFile(scene);
    const SceneFile again = parseSceneText(formatted, path, {}, withMotion());
    EXPECT_EQ(formatSceneFile(again), formatted);
    expectSameScene(scene, again);
    ASSERT_EQ(again.instances.size(), 3u);
    for (size_t i = 0; i < 3; ++i)
        EXPECT_EQ(again.instances[i].worldFromObject(), scene.instances[i].worldFromObject());
    EXPECT_EQ(again.camera.shutterClose, 0.5f);
}

TEST_F(SceneFileTest, StepsApplyInTheOrderWritten) {
    auto place = [this](const std::string& steps) {
        const SceneFile scene = parseSceneText(
            kValid + "object o begin\nsphere 0 0 0 1 w\nend\nmaterial w albedo 1 1 1\n"
                     "instance o " + steps + "\n",
            (folder_ / "x.scene").string(), {}, withInstances());
        return scene.instances.at(0).worldFromObject();
    };
    const glm::vec4 x(1, 0, 0, 1);
    EXPECT_EQ(place("scale 2 translate 1 0 0") * x, glm::vec4(3, 0, 0, 1));
    EXPECT_EQ(place("translate 1 0 0 scale 2") * x, glm::vec4(4, 0, 0, 1));
    const glm::vec4 turned = place("rotate_y 90") * x;  // right-handed: x goes to -z
    EXPECT_NEAR(turned.x, 0.0f, 1e-6f);
    EXPECT_NEAR(turned.z, -1.0f, 1e-6f);
    const glm::mat4 axis = place("rotate 0 3 0 33"), y = place("rotate_y 33");
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r)
            EXPECT_NEAR(axis[c][r], y[c][r], 1e-6f);
    EXPECT_EQ(place("scale -1 2 3") * x, glm::vec4(-1, 0, 0, 1));
}

TEST_F(SceneFileTest, ObjectMistakesAreExit3AtTheirLine) {
    auto bad = [this](const std::string& lines, const SceneSupport& support = withMotion()) {
        return failure(kValid + "material w albedo 1 1 1\n" + lines + "\n", {}, support);
    };
    const std::string ball = "object o begin\nsphere 0 0 0 1 w\nend\n";
    EXPECT_EQ(bad("instance nothing"), at(5, "object 'nothing' is not defined"));
    EXPECT_EQ(bad("object o begin\nend"),
              at(5, "object 'o' is empty: put shapes between its begin and end"));
    EXPECT_EQ(bad("object o begin\nsphere 0 0 0 1 w\ninstance o\nend"),
              at(7, "object 'o' is used inside itself"));
    EXPECT_EQ(bad(ball + "object p begin\ninstance o\nend"),
              at(9, "'instance' inside object 'p' (line 8): objects hold shapes, not objects "
                    "or instances; 'end' it first"));
    EXPECT_EQ(bad("object o begin\nobject p begin"),
              at(6, "'object' inside object 'o' (line 5): objects hold shapes, not objects "
                    "or instances; 'end' it first"));
    EXPECT_EQ(bad("object o begin\nmaterial x albedo 1 1 1"),
              at(6, "'material' inside object 'o' (line 5): only sphere, quad, triangle and "
                    "mesh statements stand between its begin and end"));
    EXPECT_EQ(bad("end"), at(5, "'end' without an 'object NAME begin' before it"));
    EXPECT_EQ(bad(ball + "end"), at(8, "'end' without an 'object NAME begin' before it"));
    EXPECT_EQ(bad("object o begin\nsphere 0 0 0 1 w"), at(5, "object 'o' has no 'end'"));
    EXPECT_EQ(bad("object o"), at(5, "'object' needs a name and the word begin: object NAME "
                                     "begin"));
    EXPECT_EQ(bad("object 9 begin"),
              at(5, "object name '9': use letters, digits, '_' and '-', starting with a "
                    "letter or '_'"));
    EXPECT_EQ(bad(ball + ball), at(8, "object 'o' is already defined on line 5"));
    EXPECT_EQ(bad("object o begin\nsphere 0 0 0 1 lamp\nend"),
              at(6, "object 'o': material 'lamp' emits, and an object's shapes may not (a "
                    "light is placed as it is, not through instances)"));
    EXPECT_EQ(bad(ball + "instance o scale 0"), at(8, "scale by 0 squashes the object flat"));
    EXPECT_EQ(bad(ball + "instance o scale 1 0 1"), at(8, "scale by 0 squashes the object flat"));
    EXPECT_EQ(bad(ball + "instance o scale 1e-10 translate 1 1 1"),
              at(8, "the placement squashes the object flat or blows it up (the determinant "
                    "of its matrix is 1e-30)"));
    EXPECT_EQ(bad(ball + "instance o scale 1 2"),
              at(8, "'scale' needs 1 number (S) or 3 (X Y Z), got 2 numbers"));
    EXPECT_EQ(bad(ball + "instance o rotate 0 0 0 30"),
              at(8, "rotate needs an axis that is not 0 0 0"));
    EXPECT_EQ(bad(ball + "instance o rotate 0 1 0"),
              at(8, "'rotate' needs 4 numbers (axis X Y Z, DEGREES), got 3 numbers"));
    EXPECT_EQ(bad(ball + "instance o translate 1 2"),
              at(8, "'translate' needs 3 numbers (X Y Z), got 2 numbers"));
    EXPECT_EQ(bad(ball + "instance o rotate_y"),
              at(8, "'rotate_y' needs 1 number (DEGREES), got 0 numbers"));
    EXPECT_EQ(bad(ball + "instance o spin 3"),
              at(8, "unexpected 'spin' in 'instance' (expected scale, rotate, rotate_y, "
                    "translate, and moving X Y Z and name NAME once each)"));
    EXPECT_EQ(bad(ball + "instance o moving 1 0 0 moving 1 0 0"),
              at(8, "unexpected 'moving' in 'instance' (expected scale, rotate, rotate_y, "
                    "translate, and moving X Y Z and name NAME once each)"));
    EXPECT_EQ(bad(ball + "instance o translate 1 x 3"),
              at(8, "'translate' needs 3 numbers (X Y Z), got 1 number"));
    EXPECT_EQ(bad("instance"), at(5, "'instance' needs the name of an object, then its "
                                     "placement"));
    EXPECT_EQ(bad("medium m homogeneous sigma_a 1 1 1 sigma_s 0 0 0\nmaterial e boundary\n"
                  "object o begin\nsphere 0 0 0 1 e interior m\nend", [] {
                      SceneSupport support = withMotion();
                      support.media.read = true;
                      return support;
                  }()),
              at(8, "object 'o': an object's shapes hold no medium (interior)"));
    EXPECT_EQ(failure(kCamera.substr(0, kCamera.size() - 1) + " shutter 1 0.5\n" +
                          kValid.substr(kCamera.size()), {}, withMotion()),
              at(1, "the camera's shutter '1' '0.5' must open at 0 or later and close no "
                    "earlier than it opens"));
    EXPECT_EQ(failure(kCamera.substr(0, kCamera.size() - 1) + " shutter 1\n" +
                          kValid.substr(kCamera.size()), {}, withMotion()),
              at(1, "the camera's shutter needs two numbers, OPEN CLOSE (seconds), once"));
    // Programs that draw no instances, or nothing that moves, say so at the first line.
    EXPECT_EQ(bad(ball + "instance o", everything()),
              at(5, "this program draws no objects or instances (object ... end, instance)"));
    EXPECT_EQ(bad(ball + "instance o", [] {
                  SceneSupport support = everything();
                  support.instances.firstReadBy = "chapter 26";
                  return support;
              }()),
              at(5, "this program draws no objects or instances (object ... end, instance); "
                    "instances come in chapter 26"));
    EXPECT_EQ(bad(ball + "instance o moving 1 0 0", withInstances()),
              at(8, "this program renders nothing that moves (moving X Y Z)"));
    EXPECT_EQ(failure(kCamera.substr(0, kCamera.size() - 1) + " shutter 0 1\n" +
                          kValid.substr(kCamera.size()), {}, withInstances()),
              at(1, "the camera has a shutter: this program renders nothing that moves"));
}
