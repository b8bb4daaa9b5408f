// The chapters' OBJ loader: the same mesh as tinyobjloader on every valid file of the
// corpus and on the generated teapots, the exact error for every bad file, and no
// crash, hang or slowness on garbage. Built twice (obj_loader_tests.cmake): against
// chapter 08's loader, which reads normals, and against chapter 07's, which reads
// positions and faces and only counts `vn` lines (COURSE_OBJ_READS_NORMALS=0), so the
// checks of the normals themselves are left out there.
#include <gtest/gtest.h>
#include <tiny_obj_loader.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <random>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "course/error.h"
#include "obj_loader.h"

#ifndef COURSE_OBJ_READS_NORMALS
#define COURSE_OBJ_READS_NORMALS 1
#endif

namespace fs = std::filesystem;
using course::ExitCode;

namespace {

const fs::path kObjData = fs::path(COURSE_TEST_DATA) / "obj";
const fs::path kMeshes = fs::path(COURSE_GENERATED_ASSET_DIR) / "meshes";

using Row = std::vector<std::string>;

// The rows of a tab-separated file, without its header row.
std::vector<Row> readTsv(const fs::path& path) {
    std::ifstream file(path);
    std::vector<Row> rows;
    std::string line;
    std::getline(file, line);  // the header
    while (std::getline(file, line)) {
        if (line.empty())
            continue;
        Row row;
        std::istringstream fields(line);
        for (std::string field; std::getline(fields, field, '\t');)
            row.push_back(field);
        rows.push_back(row);
    }
    return rows;
}

std::string lowercase(std::string text) {
    std::transform(text.begin(), text.end(), text.begin(),
                   [](unsigned char c) { return char(std::tolower(c)); });
    return text;
}

// The path as loadObj shows it in messages: absolute, without "." or "..".
std::string shownPath(const fs::path& path) {
    return fs::absolute(path).lexically_normal().string();
}

// The message of the course::Failure that loadObj throws; fails the test if the code
// is not BadInput or if the file loads.
std::string loadFailure(const fs::path& path) {
    try {
        const Mesh mesh = loadObj(path.string());
        ADD_FAILURE() << path << " loaded (" << mesh.triangleCount() << " triangles)";
    } catch (const course::Failure& failure) {
        EXPECT_EQ(failure.code(), ExitCode::BadInput) << failure.what();
        return failure.what();
    }
    return "";
}

// ---------------------------------------------------------------------------------------
// tinyobjloader, the independent reader we compare with
// ---------------------------------------------------------------------------------------

// tinyobjloader's view of a file: its attributes and every face's corners, in order.
struct TinyObjFaces {
    tinyobj::attrib_t attrib;
    std::vector<int> faceSizes;             // corners per face
    std::vector<tinyobj::index_t> corners;  // all faces' corners, face after face
};

TinyObjFaces loadWithTinyObj(const fs::path& path, bool triangulate) {
    tinyobj::ObjReaderConfig config;
    config.triangulate = triangulate;
    config.vertex_color = false;
    tinyobj::ObjReader reader;
    EXPECT_TRUE(reader.ParseFromFile(path.string(), config)) << reader.Error();
    TinyObjFaces faces{reader.GetAttrib(), {}, {}};
    for (const tinyobj::shape_t& shape : reader.GetShapes()) {  // one per `g` or `o`
        const tinyobj::mesh_t& mesh = shape.mesh;
        faces.faceSizes.insert(faces.faceSizes.end(), mesh.num_face_vertices.begin(),
                               mesh.num_face_vertices.end());
        faces.corners.insert(faces.corners.end(), mesh.indices.begin(), mesh.indices.end());
    }
    return faces;
}

// Our fan, (0, i, i + 1), applied to tinyobjloader's untriangulated faces.
std::vector<tinyobj::index_t> fanTriangulate(const TinyObjFaces& faces) {
    std::vector<tinyobj::index_t> corners;
    size_t first = 0;
    for (int size : faces.faceSizes) {
        for (int i = 1; i + 1 < size; ++i) {
            corners.push_back(faces.corners[first]);
            corners.push_back(faces.corners[first + i]);
            corners.push_back(faces.corners[first + i + 1]);
        }
        first += size_t(size);
    }
    return corners;
}

glm::vec3 vec3At(const std::vector<tinyobj::real_t>& values, int index) {
    return glm::vec3(values[3 * size_t(index)], values[3 * size_t(index) + 1],
                     values[3 * size_t(index) + 2]);
}

// Equal to float precision. Both readers parse a double and round it to a float, but
// tinyobjloader's own double parser may be a bit off, so allow a few float ulps.
::testing::AssertionResult sameVec3(glm::vec3 ours, glm::vec3 theirs) {
    for (int axis = 0; axis < 3; ++axis) {
        const float tolerance = 1e-6f * std::max(1.0f, std::fabs(theirs[axis]));
        if (std::fabs(ours[axis] - theirs[axis]) > tolerance)
            return ::testing::AssertionFailure()
                   << "(" << ours.x << ", " << ours.y << ", " << ours.z << ") != ("
                   << theirs.x << ", " << theirs.y << ", " << theirs.z << ")";
    }
    return ::testing::AssertionSuccess();
}

double triangleArea(glm::vec3 a, glm::vec3 b, glm::vec3 c) {
    return 0.5 * double(glm::length(glm::cross(b - a, c - a)));
}

void expectSameAsTinyObj(const fs::path& path) {
    SCOPED_TRACE(path.string());
    const Mesh mesh = loadObj(path.string());
    const TinyObjFaces polygons = loadWithTinyObj(path, false);
    const TinyObjFaces triangles = loadWithTinyObj(path, true);
    const tinyobj::attrib_t& attrib = polygons.attrib;

    // 1. The same positions and normals, in file order.
    ASSERT_EQ(mesh.positions.size() * 3, attrib.vertices.size());
    for (size_t i = 0; i < mesh.positions.size(); ++i)
        ASSERT_TRUE(sameVec3(mesh.positions[i], vec3At(attrib.vertices, int(i)))) << "v " << i;
#if COURSE_OBJ_READS_NORMALS
    ASSERT_EQ(mesh.normals.size() * 3, attrib.normals.size());
    for (size_t i = 0; i < mesh.normals.size(); ++i)
        ASSERT_TRUE(sameVec3(mesh.normals[i], vec3At(attrib.normals, int(i)))) << "vn " << i;
#endif

    // 2. As many triangles as tinyobjloader's own triangulation makes.
    ASSERT_EQ(mesh.triangleCount(), triangles.faceSizes.size());

    // 3. Corner by corner, the same vec3s as tinyobjloader's faces fanned like ours.
    const std::vector<tinyobj::index_t> fanned = fanTriangulate(polygons);
    ASSERT_EQ(mesh.positionIndices.size(), fanned.size());
#if COURSE_OBJ_READS_NORMALS
    const bool withNormals = std::all_of(fanned.begin(), fanned.end(), [](tinyobj::index_t c) {
        return c.normal_index >= 0;
    });
    ASSERT_EQ(mesh.normalIndices.size(), withNormals ? fanned.size() : 0);
#endif
    for (size_t k = 0; k < fanned.size(); ++k) {
        ASSERT_EQ(mesh.positionIndices[k], uint32_t(fanned[k].vertex_index)) << "corner " << k;
        ASSERT_TRUE(sameVec3(mesh.positions[mesh.positionIndices[k]],
                             vec3At(attrib.vertices, fanned[k].vertex_index)))
            << "corner " << k;
#if COURSE_OBJ_READS_NORMALS
        if (withNormals) {
            ASSERT_TRUE(sameVec3(mesh.normals[mesh.normalIndices[k]],
                                 vec3At(attrib.normals, fanned[k].normal_index)))
                << "corner " << k;
        }
#endif
    }

    // 4. tinyobjloader's triangulate=true cuts a quad along its shorter diagonal and a
    //    larger polygon by ear clipping, so only triangles come out corner for corner
    //    like our fan. Each polygon must still be covered by the same area.
    size_t triangle = 0;  // the same in both: each polygon gives size - 2 triangles
    for (int size : polygons.faceSizes) {
        double ourArea = 0.0, theirArea = 0.0;
        for (int t = 0; t < size - 2; ++t, ++triangle) {
            const uint32_t* ours = &mesh.positionIndices[3 * triangle];
            const tinyobj::index_t* theirs = &triangles.corners[3 * triangle];
            ourArea += triangleArea(mesh.positions[ours[0]], mesh.positions[ours[1]],
                                    mesh.positions[ours[2]]);
            theirArea += triangleArea(vec3At(attrib.vertices, theirs[0].vertex_index),
                                      vec3At(attrib.vertices, theirs[1].vertex_index),
                                      vec3At(attrib.vertices, theirs[2].vertex_index));
            for (int corner = 0; size == 3 && corner < 3; ++corner)
                ASSERT_EQ(ours[corner], uint32_t(theirs[corner].vertex_index));
        }
        ASSERT_NEAR(ourArea, theirArea, 1e-5 * std::max(1.0, theirArea))
            << "polygon ending at triangle " << triangle;
    }
}

// ---------------------------------------------------------------------------------------
// A scratch folder per test, removed afterwards
// ---------------------------------------------------------------------------------------

class ObjScratch : public ::testing::Test {
protected:
    void SetUp() override {
        const auto* test = ::testing::UnitTest::GetInstance()->current_test_info();
        folder_ = fs::temp_directory_path() /
                  ("course_obj_" + std::to_string(::getpid()) + "_" + test->name());
        fs::remove_all(folder_);
        fs::create_directories(folder_);
    }
    void TearDown() override { fs::remove_all(folder_); }

    fs::path write(const std::string& name, const std::string& text) {
        const fs::path path = folder_ / name;
        std::ofstream(path, std::ios::binary) << text;
        return path;
    }

    fs::path folder_;
};

}  // namespace

// ---------------------------------------------------------------------------------------
// The corpus: valid files
// ---------------------------------------------------------------------------------------

class ValidObjFile : public ::testing::TestWithParam<Row> {};

TEST_P(ValidObjFile, SameAsTinyObjLoader) { expectSameAsTinyObj(kObjData / GetParam()[0]); }

TEST_P(ValidObjFile, CountsOfExpectedValidTsv) {
    const Row& row = GetParam();  // file, positions, normals, triangles
    const Mesh mesh = loadObj((kObjData / row[0]).string());
    EXPECT_EQ(mesh.positions.size(), std::stoul(row[1]));
#if COURSE_OBJ_READS_NORMALS
    EXPECT_EQ(mesh.normals.size(), std::stoul(row[2]));
#endif
    EXPECT_EQ(mesh.triangleCount(), std::stoul(row[3]));
    EXPECT_EQ(mesh.positionIndices.size(), 3 * mesh.triangleCount());
}

std::string testName(const ::testing::TestParamInfo<Row>& info) {
    std::string name = info.param[0];
    std::replace_if(name.begin(), name.end(), [](char c) { return !std::isalnum(c); }, '_');
    return name;
}

INSTANTIATE_TEST_SUITE_P(Corpus, ValidObjFile,
                         ::testing::ValuesIn(readTsv(kObjData / "expected_valid.tsv")),
                         testName);

// ---------------------------------------------------------------------------------------
// The corpus: bad files
// ---------------------------------------------------------------------------------------

class BadObjFile : public ::testing::TestWithParam<Row> {};

TEST_P(BadObjFile, FailsWithFileLineAndWhatIsWrong) {
    const Row& row = GetParam();  // file, line, substring
    const fs::path path = kObjData / "bad" / row[0];
    const std::string message = loadFailure(path);
    const std::string where = shownPath(path) + ":" + row[1] + ": ";
    ASSERT_EQ(message.rfind(where, 0), 0u) << message << "\ndoes not start with " << where;
    // Look only after "file:line: ": binary_garbage.obj has its word in its name.
    EXPECT_NE(lowercase(message.substr(where.size())).find(row[2]), std::string::npos)
        << message << "\ndoes not say '" << row[2] << "'";
}

INSTANTIATE_TEST_SUITE_P(Corpus, BadObjFile,
                         ::testing::ValuesIn(readTsv(kObjData / "bad" / "expected.tsv")),
                         testName);

// ---------------------------------------------------------------------------------------
// Indices, normals, and what real files contain
// ---------------------------------------------------------------------------------------

TEST_F(ObjScratch, NegativeIndicesEqualTheirPositiveEquivalents) {
    const Mesh negative = loadObj((kObjData / "negative_idx.obj").string());
    const Mesh positive = loadObj(write("positive.obj",
                                        "v 0 0 0\nv 1 0 0\nv 1 1 0\nvn 0 0 1\n"
                                        "f 1//1 2//1 3//1\nv 0 1 0\nf 1//1 3//1 4//1\n")
                                      .string());
    EXPECT_EQ(negative.positionIndices, positive.positionIndices);
#if COURSE_OBJ_READS_NORMALS
    EXPECT_EQ(negative.normalIndices, positive.normalIndices);
#endif
    EXPECT_EQ(negative.positionIndices, (std::vector<uint32_t>{0, 1, 2, 0, 2, 3}));
}

#if COURSE_OBJ_READS_NORMALS
TEST_F(ObjScratch, FacesWithoutNormalsGiveEmptyNormalIndices) {
    const Mesh none = loadObj((kObjData / "no_normals.obj").string());
    EXPECT_TRUE(none.normalIndices.empty());
    EXPECT_EQ(none.triangleCount(), 12u);

    // One face with normals, one without: the mesh keeps its `vn`s but no normal indices.
    const Mesh mixed = loadObj(write("mixed.obj",
                                     "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvn 0 0 1\n"
                                     "f 1//1 2//1 3//1\nf 1 3 4\n")
                                   .string());
    EXPECT_EQ(mixed.normals.size(), 1u);
    EXPECT_TRUE(mixed.normalIndices.empty());
    EXPECT_EQ(mixed.positionIndices, (std::vector<uint32_t>{0, 1, 2, 0, 2, 3}));
}
#endif

TEST_F(ObjScratch, AcceptsWhatRealFilesContain) {
    const Mesh mesh = loadObj(write("real.obj",
                                    "\xEF\xBB\xBF# a byte order mark, then a comment\n"
                                    "mtllib a.mtl\r\n"
                                    "v 1 2 3 1.0\n"            // w
                                    "v +1.5 -2e-1 .25 1 0 0\n"  // '+', exponent, colour
                                    "v 0 1e-50 0\n"             // underflows to 0
                                    "vt 0 0\nvt 1 0\nvp 0.5\n"  // vp: an unknown statement
                                    "cstype bezier\ncurv2 1 2\nl 1 2\np 1\n"
                                    "f 1/1 2/2 3/ # a comment after the face\n"
                                    "f\t3\t2\t1\t\n")
                                  .string());
    ASSERT_EQ(mesh.positions.size(), 3u);
    EXPECT_TRUE(sameVec3(mesh.positions[0], glm::vec3(1, 2, 3)));
    EXPECT_TRUE(sameVec3(mesh.positions[1], glm::vec3(1.5f, -0.2f, 0.25f)));
    EXPECT_TRUE(sameVec3(mesh.positions[2], glm::vec3(0, 0, 0)));
    EXPECT_EQ(mesh.positionIndices, (std::vector<uint32_t>{0, 1, 2, 2, 1, 0}));
}

TEST_F(ObjScratch, RejectsWhatNoObjFileContains) {
    const std::string vertices = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";
    struct Case {
        std::string text;
        int line;
        std::string says;
    };
    const std::vector<Case> cases = {
        {vertices + "@@ 1 2 3\n", 4, "'@@' is not an obj statement"},
        {vertices + "f 1 2 3.5\n", 4, "'3.5' is not a whole number"},
        {vertices + "f 1 2 99999999999999999999\n", 4, "index '9999999999"},
        {vertices + "f 1 2 -2147483649\n", 4, "index -2147483649 is out of range"},
        {vertices + "f 1/1 2/1 3/1\n", 4, "texture coordinate index 1 is out of range"},
        {vertices + "f 1// 2// 3//\n", 4, "empty normal index"},
        {vertices + "f /1 2 3\n", 4, "no vertex index"},
        {"v 1e999 0 0\n", 1, "'1e999' is out of range"},
        {"v 1e39 0 0\n", 1, "'1e39' is too large for a float"},
        {"v 1 2 3abc\n", 1, "'3abc' is not a number"},
        {"v 1 2 -inf\n", 1, "'-inf' is not a finite number"},
#if COURSE_OBJ_READS_NORMALS
        {"vn 0 0 1 0\n", 1, "'vn' needs 3 numbers, got 4"},
#endif
        {"v 0 0 0\n\x7f\n", 2, "binary"},
        {" \t\r\n\n# only blanks\n", 0, "no faces"},
        {vertices, 0, "no faces"},
    };
    for (const Case& test : cases) {
        const fs::path path = write("bad.obj", test.text);
        const std::string message = loadFailure(path);
        const std::string where = shownPath(path) + ":" + std::to_string(test.line) + ": ";
        EXPECT_EQ(message.rfind(where, 0), 0u) << message;
        EXPECT_NE(lowercase(message).find(test.says, where.size()), std::string::npos)
            << message << "\ndoes not contain: " << test.says;
    }
}

TEST_F(ObjScratch, EmptyFileIsLineZero) {
    const fs::path path = write("empty.obj", "");
    EXPECT_EQ(loadFailure(path), shownPath(path) + ":0: empty file");
}

// ---------------------------------------------------------------------------------------
// Files that cannot be read
// ---------------------------------------------------------------------------------------

TEST(ObjLoaderFile, MissingFileNamesTheAbsolutePath) {
    const std::string message = loadFailure("no_such_folder/missing.obj");
    const std::string expected = shownPath(fs::current_path() / "no_such_folder/missing.obj");
    EXPECT_EQ(message.rfind(expected + ": cannot open", 0), 0u) << message;
    EXPECT_NE(message.find("No such file"), std::string::npos) << message;
}

TEST(ObjLoaderFile, DirectoryIsNotAFile) {
    const std::string message = loadFailure(kObjData);
    EXPECT_EQ(message, shownPath(kObjData) + ": cannot open: it is a directory");
}

TEST(ObjLoaderFile, DeviceIsNotAFile) {
    // /dev/zero would never end; a pipe could block forever.
    const std::string message = loadFailure("/dev/zero");
    EXPECT_EQ(message, "/dev/zero: cannot open: not a regular file");
}

TEST_F(ObjScratch, UnreadableFile) {
    const fs::path path = write("locked.obj", "v 0 0 0\n");
    fs::permissions(path, fs::perms::none);
    auto check = [&] {
        const std::string message = loadFailure(path);
        return message.find(shownPath(path) + ": cannot open (Permission denied)") !=
               std::string::npos;
    };
    if (::geteuid() != 0) {
        EXPECT_TRUE(check());
        return;
    }
    // Root reads any file, so the check runs in a child that has given up root and
    // become `nobody` (65534), as a learner's account would be.
    const pid_t child = ::fork();
    ASSERT_GE(child, 0);
    if (child == 0) {
        bool dropped = ::setgid(65534) == 0 && ::setuid(65534) == 0;
        ::_exit(dropped && check() ? 0 : 1);
    }
    int status = 0;
    ::waitpid(child, &status, 0);
    EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0)
        << "as nobody, loading an unreadable file must fail with Permission denied";
}

// ---------------------------------------------------------------------------------------
// Garbage: never a crash, never a hang, never slow
// ---------------------------------------------------------------------------------------

// Loads a file that may be broken: it must either load with every index in range or
// fail with BadInput; anything else (a crash, another exception) fails the test.
void expectLoadsOrFailsCleanly(const fs::path& path) {
    try {
        const Mesh mesh = loadObj(path.string());
        for (uint32_t index : mesh.positionIndices)
            ASSERT_LT(index, mesh.positions.size());
#if COURSE_OBJ_READS_NORMALS
        for (uint32_t index : mesh.normalIndices)
            ASSERT_LT(index, mesh.normals.size());
#endif
    } catch (const course::Failure& failure) {
        ASSERT_EQ(failure.code(), ExitCode::BadInput) << failure.what();
    }
}

TEST_F(ObjScratch, EveryTruncationAndMutationLoadsOrFailsCleanly) {
    std::ifstream source(kObjData / "cube_normals.obj", std::ios::binary);
    const std::string cube((std::istreambuf_iterator<char>(source)),
                           std::istreambuf_iterator<char>());
    for (size_t length = 0; length <= cube.size(); ++length)
        expectLoadsOrFailsCleanly(write("cut.obj", cube.substr(0, length)));

    std::string tricky = "/-+.0123456789eE #\n\r\tvfnx";
    tricky += '\0';  // a NUL too: the loader must not stop at it like a C string
    std::mt19937 random(7);
    for (int trial = 0; trial < 2000; ++trial) {
        std::string mutated = cube;
        for (int change = 0; change < 3; ++change)
            mutated[random() % mutated.size()] = tricky[random() % tricky.size()];
        expectLoadsOrFailsCleanly(write("mutated.obj", mutated));
    }
}

// About `size` bytes of random printable ASCII in lines of random length, like a log
// or a base64 dump handed over by mistake. Fixed seed: the same file every run.
void writePrintableGarbage(const fs::path& path, size_t size) {
    std::ofstream file(path, std::ios::binary);
    std::string block(size_t(1) << 20, ' ');
    uint64_t state = 20251124;
    for (size_t written = 0; written < size; written += block.size()) {
        for (size_t i = 0; i < block.size(); i += 8) {
            // splitmix64: a fast generator, 8 random bytes per step
            uint64_t bits = (state += 0x9E3779B97F4A7C15ull);
            bits = (bits ^ (bits >> 30)) * 0xBF58476D1CE4E5B9ull;
            bits = (bits ^ (bits >> 27)) * 0x94D049BB133111EBull;
            bits ^= bits >> 31;
            for (size_t b = 0; b < 8; ++b, bits >>= 8) {
                const unsigned byte = unsigned(bits & 0xff);
                block[i + b] = byte < 5 ? '\n' : char(' ' + byte % 95);  // ' ' .. '~'
            }
        }
        file.write(block.data(), std::streamsize(block.size()));
    }
}

TEST_F(ObjScratch, TwoHundredMegabytesOfGarbageFailFast) {
    const fs::path path = folder_ / "garbage.obj";
    writePrintableGarbage(path, size_t(200) << 20);
    ASSERT_GE(fs::file_size(path), size_t(200) << 20);

    const auto started = std::chrono::steady_clock::now();
    const std::string message = loadFailure(path);
    const std::chrono::duration<double> took = std::chrono::steady_clock::now() - started;
    std::cout << "200 MB of garbage rejected in " << took.count() << " s: " << message << "\n";
    EXPECT_LT(took.count(), 5.0);

    // It stops at the first bad line, near the top, not at the end of the file.
    const std::string prefix = shownPath(path) + ":";
    ASSERT_EQ(message.rfind(prefix, 0), 0u) << message;
    EXPECT_LE(std::stoul(message.substr(prefix.size())), 10u) << message;
}

// ---------------------------------------------------------------------------------------
// Generated teapots (cmake/Assets.cmake, built before this test)
// ---------------------------------------------------------------------------------------

TEST(ObjLoaderTeapot, SameAsTinyObjLoader) {
    for (const char* name : {"teapot_552.obj", "teapot_552_no_normals.obj", "teapot_6320.obj"})
        expectSameAsTinyObj(kMeshes / name);
}

TEST(ObjLoaderTeapot, CountsAndNormals) {
    const Mesh smooth = loadObj((kMeshes / "teapot_552.obj").string());
    const Mesh plain = loadObj((kMeshes / "teapot_552_no_normals.obj").string());
    EXPECT_EQ(smooth.triangleCount(), 552u);
    EXPECT_EQ(plain.positionIndices, smooth.positionIndices);
#if COURSE_OBJ_READS_NORMALS
    EXPECT_EQ(smooth.normals.size(), smooth.positions.size());  // one normal per vertex
    EXPECT_EQ(smooth.normalIndices, smooth.positionIndices);    // written as f a//a ...
    EXPECT_TRUE(plain.normals.empty());
    EXPECT_TRUE(plain.normalIndices.empty());
#endif
    EXPECT_EQ(loadObj((kMeshes / "teapot_6320.obj").string()).triangleCount(), 6320u);
}

// How long a million triangles take to load is measured by ./course bench, not here:
// timed tests fail on a busy machine and prove nothing on a fast one.
