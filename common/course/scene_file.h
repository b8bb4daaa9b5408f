// Scenes as small text files (assets/scenes/*.scene), read by a strict line parser.
// The scene-file reader of the chapters that read scene files; no chapter teaches it,
// so it lives here once. No GL: a chapter turns a SceneFile into what its shaders read,
// and loads the meshes it names with its own OBJ loader (the lesson of the OBJ chapter).
//
// The format, one statement per line; `#` starts a comment; numbers are decimal (1,
// -0.25, 1e-3); lengths in metres, angles in degrees; every shape names a material:
//
//   camera eye X Y Z look X Y Z up X Y Z focal F sensor S [lens RADIUS focus DISTANCE]
//          [medium MEDIUM] [shutter OPEN CLOSE]
//       a pinhole camera (python_prototypes/camera_rays.py): the eye, a viewing direction
//       (not a point), roughly-up, the focal length and the sensor's *width*; exactly
//       one per file. Its horizontal field of view is 2 atan(S / 2F). With `lens`, a
//       thin lens (python_prototypes/thin_lens.py): an aperture of RADIUS >= 0 metres
//       centred on the eye, sharp on the plane DISTANCE > 0 metres in front of it
//       (Mitsuba 3's `thinlens`, aperture_radius and focus_distance); RADIUS 0 is the
//       pinhole again. With `medium`, the camera stands in MEDIUM, which fills all
//       space outside the shapes that have an interior (fog filling the scene).
//   texture NAME image PATH [linear]
//       a PNG or JPEG image, found as a mesh's PATH is; its 8-bit values are sRGB-encoded
//       and decoded to linear at load, unless `linear` says they are linear already.
//       Looked up bilinearly between texel centres and repeated beyond [0, 1]:
//       Mitsuba's `bitmap` (filter_type bilinear, wrap_mode repeat, raw for linear).
//   texture NAME checker R G B R G B [scale S]
//       squares of two colours (each channel in [0, 1]), S > 0 squares of each colour
//       per unit of texture coordinate (default 1): Mitsuba's `checkerboard`.
//       A texture must be defined before the material that uses it.
//   material NAME albedo R G B [emission R G B]
//   material NAME albedo texture TEXTURE [emission R G B]
//       a Lambertian surface reflecting a fraction R G B in [0, 1] of the light, or the
//       fraction a texture gives where the surface is hit; with `emission`, also a light
//       giving out that radiance (W / m^2 / sr, per channel). A textured material is for
//       quads (u along the first edge, v along the second) and meshes (their OBJ `vt`).
//       NAME: letters, digits, '_' and '-'; each name once. A material may be used
//       before the line that defines it.
//   material NAME mirror [reflectance R G B]
//       ideal specular reflection of a fraction R G B in [0, 1] (default 1 1 1):
//       Mitsuba 3's `conductor` with `material none` and `specular_reflectance`
//   material NAME conductor eta R G B k R G B [roughness A]
//       a metal: the Fresnel equations with the complex index eta + i k per channel
//       (eta > 0, k >= 0); A, the GGX alpha (0 or absent: smooth). Mitsuba's
//       `conductor`, or `roughconductor` with `distribution ggx`, `sample_visible`.
//   material NAME dielectric ior N [roughness A]
//       a glass-like boundary, index N > 0 inside and 1 outside: Mitsuba's `dielectric`
//       (int_ior N, ext_ior 1), or `roughdielectric` with GGX alpha A.
//   material NAME boundary
//       an invisible surface: light passes through unchanged. It is only the border of a
//       participating medium (below): Mitsuba 3's `null` BSDF.
//   Only an `albedo` material may have an emission. A program that renders only some
//   kinds of material says which it met (loadSceneFile's `accepted`).
//   medium NAME homogeneous sigma_a R G B sigma_s R G B [g G]
//       a participating medium of constant density: per metre and per channel, the
//       absorption coefficient sigma_a >= 0 and the scattering coefficient sigma_s >= 0
//       (their sum, sigma_t, is the extinction: a ray keeps exp(-sigma_t d) of its
//       light over d metres); its scattering follows the Henyey-Greenstein phase
//       function with mean cosine G in (-1, 1), default 0 (the same in every direction).
//       Mitsuba 3's `homogeneous` medium with sigma_t = sigma_a + sigma_s and albedo
//       sigma_s / sigma_t, and its `hg` phase function.
//   medium NAME grid PATH albedo R G B [scale S] [g G]
//       a medium whose density varies: the densities of a Mitsuba `.vol` grid (one
//       channel of float32, spanning the file's bounding box in world units), times
//       S > 0 per metre (default 1), is sigma_t; the albedo R G B in [0, 1] is
//       sigma_s / sigma_t. Mitsuba 3's `heterogeneous` medium with a `gridvolume`.
//   A medium fills the inside of the closed shapes that name it (`interior`, below) or,
//   named by the camera, the space around the camera. Media may be named before the
//   line that defines them.
//   sphere CX CY CZ RADIUS MATERIAL [interior MEDIUM] [name NAME]
//   quad OX OY OZ EX EY EZ FX FY FZ MATERIAL [name NAME]
//       the parallelogram with corners O, O + E, O + E + F, O + F (two edges from a
//       corner, so a rectangle needs no fourth corner to agree)
//   triangle AX AY AZ BX BY BZ CX CY CZ MATERIAL [name NAME]
//   mesh PATH MATERIAL [scale S] [rotate_y DEGREES] [translate X Y Z] [interior MEDIUM]
//        [name NAME]
//       an OBJ file, placed in the scene by scaling it by S, turning it about the y axis
//       by DEGREES (counter-clockwise seen from above), then moving it by X Y Z, in that
//       order whatever order the options are written in. PATH (no spaces) is relative
//       to the scene file's folder or, if not found there, to each mesh folder the
//       program passes in (the build's generated assets); the first that exists wins.
//   `interior MEDIUM`: the medium inside the shape. Only a sphere or a closed mesh has
//   an inside (the program that loads a mesh checks that every edge joins two faces),
//   and only a `boundary` or `dielectric` material lets light in (coloured glass, a
//   tinted liquid: a dielectric around an absorbing medium).
//   environment PATH [scale S] [rotate_y DEGREES]
//       a latitude-longitude radiance map (PFM or OpenEXR), infinitely far: the
//       background and a light. A direction d has u = atan2(d.x, -d.z) / 2 pi, v =
//       acos(d.y) / pi (python_prototypes/sky.py), the map's top row at v = 0; S > 0
//       scales its radiance (default 1); the map is turned by DEGREES about y,
//       counter-clockwise seen from above. Mitsuba 3's `envmap`. At most one; a scene
//       with one needs no emitting shape. PATH is found as a mesh's is.
//   A shape's optional name (same rule as a material's) labels a region of the image
//   for comparisons: several shapes may share one name (the six faces of a box).
//   object NAME begin ... end
//       the sphere, quad, triangle and mesh statements between the two lines form an
//       object, drawn only where instances place it (nothing of it by itself). Its
//       shapes may not emit, nor hold a medium; objects do not nest, and hold no
//       instances (two levels: objects, and instances of them).
//   instance OBJECT [scale S | scale X Y Z] [rotate X Y Z DEGREES] [rotate_y DEGREES]
//            [translate X Y Z] [moving X Y Z] [name NAME]
//       OBJECT placed in the world by the steps written, applied in the order written
//       (Mitsuba's to_world chain, each step multiplying from the left): scale by S, or
//       by X Y Z along the axes (none 0; a negative one mirrors), turn by DEGREES about
//       the axis X Y Z (any length but 0; counter-clockwise seen from its tip), turn
//       about y, move. Steps may repeat. `moving`, once, after them: the instance moves
//       by X Y Z in the world while the camera's shutter is open, from where the steps
//       put it (motion blur). OBJECT may be defined before or after the instance.
//   The camera's optional `shutter OPEN CLOSE` (seconds, 0 <= OPEN <= CLOSE) is the
//   interval over which a picture is exposed: Mitsuba's shutter_open, shutter_close.
//
// The front of a quad is the side cross(E, F) points to; of a triangle, the side
// cross(B - A, C - A) points to (corners counter-clockwise seen from the front); of a
// sphere, the outside. An emitting surface emits from its front only. A scene needs at
// least one emitter: a shape whose material has an emission above zero, or an
// environment.
//
// Any problem throws course::Failure(ExitCode::BadInput, "file:line: what is wrong"),
// the file as an absolute path; line 0 means the file as a whole (empty, no camera).
#pragma once
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include <glm/glm.hpp>

namespace course {

// --8<-- [start:types]
struct SceneCamera {
    glm::vec3 eye{0.0f}, look{0.0f, 0.0f, -1.0f}, up{0.0f, 1.0f, 0.0f};
    float focalLength = 0.035f;  // metres
    float sensorWidth = 0.036f;  // metres
    float lensRadius = 0.0f;     // metres; 0: a pinhole
    float focusDistance = 1.0f;  // metres along the view direction, where a lens is sharp
    int32_t medium = -1;         // the medium around the camera (SceneFile::media), or -1
    float shutterOpen = 0.0f;    // seconds: the exposure's interval (instances that move
    float shutterClose = 0.0f;   // blur over it); both 0 when not written
};

enum class MediumKind { Homogeneous, Grid };

struct SceneMedium {
    std::string name;
    MediumKind kind = MediumKind::Homogeneous;
    glm::vec3 sigmaA{0.0f}, sigmaS{0.0f};  // homogeneous: per metre, per channel
    std::string path;                      // grid: absolute, where the .vol file was found
    std::string writtenPath;               // grid: as written in the scene file
    glm::vec3 albedo{0.0f};                // grid: sigma_s / sigma_t, per channel
    float scale = 1.0f;                    // grid: sigma_t per metre at density 1
    float g = 0.0f;                        // Henyey-Greenstein mean cosine, in (-1, 1)
    size_t line = 0;
};

enum class TextureKind { Image, Checker };

struct SceneTexture {
    std::string name;
    TextureKind kind = TextureKind::Image;
    std::string path;         // image: absolute, where the file was found
    std::string writtenPath;  // image: as written in the scene file
    bool linear = false;      // image: its values are linear, not sRGB-encoded
    glm::vec3 color0{0.0f}, color1{1.0f};  // checker: the two colours
    float scale = 1.0f;                    // checker: squares per unit of u and of v
    size_t line = 0;
};

enum class MaterialKind { Diffuse, Mirror, Conductor, Dielectric, Boundary };

struct SceneMaterial {
    std::string name;
    MaterialKind kind = MaterialKind::Diffuse;
    glm::vec3 albedo{0.0f};       // diffuse: reflected fraction per channel, in [0, 1]
    int32_t texture = -1;         // diffuse: the index in SceneFile::textures, or -1: albedo
    glm::vec3 emission{0.0f};     // diffuse: emitted radiance; zero for one that only reflects
    glm::vec3 reflectance{1.0f};  // mirror: reflected fraction per channel, in [0, 1]
    glm::vec3 eta{1.0f}, k{0.0f};  // conductor: the complex index of refraction per channel
    float ior = 1.5f;             // dielectric: the index inside (outside: 1)
    float roughness = 0.0f;       // conductor, dielectric: GGX alpha; 0 is smooth
    size_t line = 0;              // where it is defined, for messages

    bool emits() const { return emission.r > 0.0f || emission.g > 0.0f || emission.b > 0.0f; }
};

// Shapes refer to their material by its index in SceneFile::materials.
struct SceneSphere {
    glm::vec3 center{0.0f};
    float radius = 1.0f;
    uint32_t material = 0;
    int32_t interior = -1;  // the medium inside (SceneFile::media), or -1: none
    std::string name;  // optional
};

struct SceneQuad {
    glm::vec3 origin{0.0f}, edge1{0.0f}, edge2{0.0f};  // corners O, O+E, O+E+F, O+F
    uint32_t material = 0;
    std::string name;  // optional
};

struct SceneTriangle {
    glm::vec3 p0{0.0f}, p1{0.0f}, p2{0.0f};
    uint32_t material = 0;
    std::string name;  // optional
};

struct SceneMesh {
    std::string path;         // absolute: where the file was found
    std::string writtenPath;  // as written in the scene file
    uint32_t material = 0;
    float scale = 1.0f;
    float rotationYDegrees = 0.0f;
    glm::vec3 translation{0.0f};
    int32_t interior = -1;  // the medium inside (SceneFile::media), or -1: none
    std::string name;  // optional
    size_t line = 0;   // the `mesh` line, for messages about the OBJ file

    // Scale, then turn about y, then move: the matrix taking mesh points to the world.
    glm::mat4 worldFromMesh() const;
};

struct SceneEnvironment {
    std::string path;         // absolute, where the file was found
    std::string writtenPath;  // as written in the scene file
    float scale = 1.0f;
    float rotationYDegrees = 0.0f;
    size_t line = 0;  // the `environment` line; 0: the scene has no environment
};

// --8<-- [start:instances]
// One step of an instance's placement, as written (so that a scene writes back as read).
enum class PlacementStepKind { Scale, Rotate, RotateY, Translate };
struct PlacementStep {
    PlacementStepKind kind = PlacementStepKind::Translate;
    // scale: the factors along x, y, z; rotate: the axis and the degrees (w);
    // rotate_y: the degrees (w); translate: the offset.
    glm::vec4 values{0.0f};
};

// `object NAME begin` ... `end`: shapes drawn only where instances place them, in the
// object's own coordinates.
struct SceneObject {
    std::string name;
    std::vector<SceneSphere> spheres;
    std::vector<SceneQuad> quads;
    std::vector<SceneTriangle> triangles;
    std::vector<SceneMesh> meshes;
    size_t line = 0;  // the `object` line
};

// `instance OBJECT ...`: an object placed in the world.
struct SceneInstance {
    uint32_t object = 0;               // index into SceneFile::objects
    std::vector<PlacementStep> steps;  // in the order written: the first applies first
    glm::vec3 motion{0.0f};            // moving X Y Z: how far it goes while the shutter is open
    std::string name;                  // optional
    size_t line = 0;

    // The steps as one matrix, object points to world points, where the instance is when
    // the shutter opens: the last step's matrix on the left.
    glm::mat4 worldFromObject() const;
};
// --8<-- [end:instances]

struct SceneFile {
    std::string path;  // absolute
    SceneCamera camera;
    SceneEnvironment environment;
    std::vector<SceneTexture> textures;
    std::vector<SceneMaterial> materials;
    std::vector<SceneMedium> media;
    std::vector<SceneSphere> spheres;
    std::vector<SceneQuad> quads;
    std::vector<SceneTriangle> triangles;
    std::vector<SceneMesh> meshes;
    std::vector<SceneObject> objects;      // what instances place; not drawn by themselves
    std::vector<SceneInstance> instances;

    // Shapes whose material emits: spheres, quads, triangles and meshes.
    size_t emitterCount() const;
    bool hasEnvironment() const { return environment.line != 0; }
};
// --8<-- [end:types]

// What a program's scene reader accepts besides diffuse materials, shapes and a pinhole
// camera. A scene using anything else is exit code 3 at its line, rather than a picture
// that silently shows it as something else; the message names where the course first
// reads it. A chapter's manifest says both (manifests/NN_name.ini, scene_reads): the
// build writes them into the chapter's scene_support.h, kSceneSupport.
struct SceneFeature {
    bool read = false;
    std::string firstReadBy;  // e.g. "chapter NN"; empty when no chapter at hand reads it
};
struct SceneSupport {
    SceneFeature metals;       // mirror and conductor materials
    SceneFeature glass;        // dielectric materials
    SceneFeature lens;         // a camera with a lens (lens RADIUS focus DISTANCE)
    SceneFeature textures;     // texture statements and textured materials
    SceneFeature environment;  // an environment light
    SceneFeature media;        // medium statements, boundary materials, interior, camera medium
    SceneFeature instances;    // object ... end, instance statements
    SceneFeature motion;       // instances that move (moving X Y Z), the camera's shutter
};

// Reads a scene file; meshFolders are the folders searched for a mesh's PATH after the
// scene file's own folder.
SceneFile loadSceneFile(const std::string& path,
                        const std::vector<std::string>& meshFolders = {},
                        const SceneSupport& support = {});

// The same, from text already in memory: shownPath names it in messages and its folder
// is where mesh paths are looked up first.
SceneFile parseSceneText(std::string_view text, const std::string& shownPath,
                         const std::vector<std::string>& meshFolders = {},
                         const SceneSupport& support = {});

// "albedo", "mirror", "conductor", "dielectric" or "boundary": the word the format uses.
const char* materialKindWord(MaterialKind kind);

// The scene as text in the format above, with every number written so that it reads
// back as the same float: parseSceneText(formatSceneFile(s)) gives s again.
std::string formatSceneFile(const SceneFile& scene);

}  // namespace course
