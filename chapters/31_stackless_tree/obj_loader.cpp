// Chapter 07: reading an OBJ file by hand. The file is read whole and walked line by
// line with string_views: no stream per token, so a million triangles load in about a
// second, and no line, however long or strange, can crash or hang it.
#include "obj_loader.h"

#include <charconv>
#include <string_view>
#include <system_error>
#include <utility>

#include "course/text_file.h"  // the file whole, its lines, words and numbers, messages

namespace {

using course::inQuotes;
using course::isDigit;
using course::isLetter;
using course::nextWord;

// Indices are 32-bit; staying below 2^31 also keeps them valid as GLSL `int`s.
constexpr size_t kMostElements = size_t(1) << 31;
// 4 GiB of text is about 50 million triangles: far more than any scene here needs.
constexpr std::uintmax_t kMostBytes = std::uintmax_t(4) << 30;

// Statement names are words such as v, usemtl, curv2 or trace_obj. A first word made of
// anything else is not an OBJ statement: most likely the file is not an OBJ file.
bool looksLikeKeyword(std::string_view word) {
    if (!isLetter(word[0]))
        return false;
    for (char c : word)
        if (!isLetter(c) && !isDigit(c) && c != '_')
            return false;
    return true;
}

// One face corner as written (v, v/vt, v//vn or v/vt/vn), resolved to 0-based indices.
struct Corner {
    uint32_t position = 0;
    uint32_t normal = 0, texcoord = 0;
    bool hasNormal = false, hasTexcoord = false;
};

class ObjParser {
public:
    explicit ObjParser(std::string shownPath) : path_(std::move(shownPath)) {}

    // --8<-- [start:line]
    // One line, its comment already cut off (course::forEachLine).
    void readLine(std::string_view line, size_t lineNumber) {
        lineNumber_ = lineNumber;
        const std::string_view keyword = nextWord(line);
        if (keyword.empty())
            return;  // a blank line, or only a comment
        if (keyword == "v")
            readPosition(line);
        else if (keyword == "vn")
            readNormal(line);
        else if (keyword == "vt")
            readTexcoord(line);
        else if (keyword == "f")
            readFace(line);
        else if (!looksLikeKeyword(keyword))
            fail(inQuotes(keyword) + " is not an OBJ statement");
        // Anything else (g, o, s, usemtl, mtllib, l, vp, ...) does not change the triangles.
    }
    // --8<-- [end:line]

    Mesh finish() {
        if (mesh_.positionIndices.empty())
            course::failAtLine(path_, 0, "no faces: the file has no 'f' line");
        // Normals are all or nothing. If some corner has none, the whole mesh goes
        // without file normals (chapter 08 then computes its own) rather than
        // mixing two kinds of shading in one picture.
        if (!everyCornerHasNormal_)
            mesh_.normalIndices.clear();
        // Texture coordinates likewise: a textured material then says the mesh has none.
        if (!everyCornerHasTexcoord_)
            mesh_.texcoordIndices.clear();
        return std::move(mesh_);
    }

private:
    [[noreturn]] void fail(const std::string& what) const {
        course::failAtLine(path_, lineNumber_, what);
    }

    // --8<-- [start:vector]
    // The numbers after `v` or `vn`: the first three go into xyz; returns how many.
    size_t readVector(std::string_view rest, glm::vec3& xyz) const {
        size_t count = 0;
        for (std::string_view word = nextWord(rest); !word.empty(); word = nextWord(rest)) {
            const float value = course::readNumber(word, path_, lineNumber_);
            if (count < 3)
                xyz[int(count)] = value;
            ++count;
        }
        return count;
    }
    // --8<-- [end:vector]

    // `v x y z`: a 4th number (w) or an r g b colour after x y z is read and ignored.
    void readPosition(std::string_view rest) {
        glm::vec3 position(0.0f);
        const size_t count = readVector(rest, position);
        if (count < 3)
            fail("'v' needs 3 numbers, got " + std::to_string(count));
        if (mesh_.positions.size() >= kMostElements)
            fail("too many vertices (more than 2^31)");
        mesh_.positions.push_back(position);
    }

    // `vn x y z`: exactly three numbers.
    void readNormal(std::string_view rest) {
        glm::vec3 normal(0.0f);
        const size_t count = readVector(rest, normal);
        if (count != 3)
            fail("'vn' needs 3 numbers, got " + std::to_string(count));
        if (mesh_.normals.size() >= kMostElements)
            fail("too many normals (more than 2^31)");
        mesh_.normals.push_back(normal);
    }

    // `vt u [v [w]]`: v defaults to 0 and w (for 3D textures) is ignored.
    void readTexcoord(std::string_view rest) {
        glm::vec3 uvw(0.0f);
        const size_t count = readVector(rest, uvw);
        if (count < 1 || count > 3)
            fail("'vt' needs 1 to 3 numbers, got " + std::to_string(count));
        if (mesh_.texcoords.size() >= kMostElements)
            fail("too many texture coordinates (more than 2^31)");
        mesh_.texcoords.push_back(glm::vec2(uvw));
    }

    // --8<-- [start:index]
    // OBJ indices start at 1; negative ones count back from the elements read so far
    // (-1 is the latest). Returns the 0-based index, or fails naming what is wrong.
    uint32_t resolveIndex(std::string_view word, size_t count, const std::string& kind,
                          const std::string& kindPlural) const {
        long long index = 0;
        const char* end = word.data() + word.size();
        const auto [stop, error] = std::from_chars(word.data(), end, index);
        if (error == std::errc::result_out_of_range)
            fail(kind + " index " + inQuotes(word) + " is out of range");
        if (error != std::errc() || stop != end)
            fail("bad face vertex: " + kind + " index " + inQuotes(word) +
                 " is not a whole number");
        if (index == 0)
            fail(kind + " index 0 is invalid: OBJ indices start at 1");
        const long long resolved = index > 0 ? index - 1 : (long long)count + index;
        if (resolved < 0 || resolved >= (long long)count)
            fail(kind + " index " + std::to_string(index) + " is out of range (" +
                 std::to_string(count) + " " + kindPlural + " so far)");
        return uint32_t(resolved);
    }
    // --8<-- [end:index]

    Corner readCorner(std::string_view word) const {
        // Split at '/': "7" -> {7}, "7/3" -> {7, 3}, "7//2" -> {7, "", 2}.
        std::string_view parts[3];
        size_t partCount = 0;
        for (std::string_view rest = word;;) {
            if (partCount == 3)
                fail("bad face vertex " + inQuotes(word) + ": at most 3 parts, v/vt/vn");
            const size_t slash = rest.find('/');
            parts[partCount++] = rest.substr(0, slash);
            if (slash == std::string_view::npos)
                break;
            rest.remove_prefix(slash + 1);
        }
        if (parts[0].empty())
            fail("bad face vertex " + inQuotes(word) + ": no vertex index");

        Corner corner;
        corner.position = resolveIndex(parts[0], mesh_.positions.size(), "vertex", "vertices");
        if (!parts[1].empty()) {
            corner.texcoord = resolveIndex(parts[1], mesh_.texcoords.size(),
                                           "texture coordinate", "texture coordinates");
            corner.hasTexcoord = true;
        }
        if (partCount == 3) {
            if (parts[2].empty())
                fail("bad face vertex " + inQuotes(word) + ": empty normal index");
            corner.normal = resolveIndex(parts[2], mesh_.normals.size(), "normal", "normals");
            corner.hasNormal = true;
        }
        return corner;
    }

    // --8<-- [start:face]
    void readFace(std::string_view rest) {
        corners_.clear();
        for (std::string_view word = nextWord(rest); !word.empty(); word = nextWord(rest))
            corners_.push_back(readCorner(word));
        if (corners_.size() < 3)
            fail("a face needs at least 3 vertices, got " + std::to_string(corners_.size()));
        if (mesh_.positionIndices.size() + 3 * (corners_.size() - 2) > kMostElements)
            fail("too many triangles (more than 2^31 corner indices)");

        // Fan triangulation: (0, 1, 2), (0, 2, 3), ... exact for convex polygons.
        for (size_t i = 1; i + 1 < corners_.size(); ++i) {
            addCorner(corners_[0]);
            addCorner(corners_[i]);
            addCorner(corners_[i + 1]);
        }
    }

    void addCorner(const Corner& corner) {
        mesh_.positionIndices.push_back(corner.position);
        everyCornerHasNormal_ = everyCornerHasNormal_ && corner.hasNormal;
        if (everyCornerHasNormal_)  // once one is missing, normals are dropped (finish)
            mesh_.normalIndices.push_back(corner.normal);
        everyCornerHasTexcoord_ = everyCornerHasTexcoord_ && corner.hasTexcoord;
        if (everyCornerHasTexcoord_)
            mesh_.texcoordIndices.push_back(corner.texcoord);
    }
    // --8<-- [end:face]

    std::string path_;
    size_t lineNumber_ = 0;
    bool everyCornerHasNormal_ = true;
    bool everyCornerHasTexcoord_ = true;
    std::vector<Corner> corners_;  // the face being read; reused to avoid allocations
    Mesh mesh_;
};

}  // namespace

// --8<-- [start:load]
Mesh loadObj(const std::string& path) {
    const std::string shownPath = course::absolutePath(path);  // messages name it
    const std::string text = course::readWholeFile(path, kMostBytes, "an OBJ file");
    ObjParser parser(shownPath);
    course::forEachLine(text, shownPath, [&parser](std::string_view line, size_t lineNumber) {
        parser.readLine(line, lineNumber);
    });
    return parser.finish();
}
// --8<-- [end:load]
