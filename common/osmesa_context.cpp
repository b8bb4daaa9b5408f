// OSMesa: Mesa's off-screen, pure software OpenGL. It is loaded with dlopen so the
// course builds and runs without it; only --backend osmesa needs libOSMesa.so.8
// (Debian: apt install libosmesa6). It renders into memory we own; chapters render
// into buffers anyway, so a 1x1 colour buffer is enough.
#include <dlfcn.h>

#include <vector>

#include "course/error.h"
#include "course/gl_context.h"

namespace course {
namespace {

// From GL/osmesa.h, which we do not include: it pulls in the system GL/gl.h, which
// would clash with GLAD's declarations.
constexpr int OSMESA_RGBA = 0x1908, OSMESA_FORMAT = 0x22, OSMESA_DEPTH_BITS = 0x30,
              OSMESA_PROFILE = 0x33, OSMESA_CORE_PROFILE = 0x34,
              OSMESA_CONTEXT_MAJOR_VERSION = 0x36, OSMESA_CONTEXT_MINOR_VERSION = 0x37;
constexpr unsigned GL_UNSIGNED_BYTE_ = 0x1401;

using OSMesaContext = void*;
using CreateContextAttribs = OSMesaContext (*)(const int* attributes, OSMesaContext share);
using MakeCurrent = unsigned char (*)(OSMesaContext, void* buffer, unsigned type,
                                      int width, int height);
using DestroyContext = void (*)(OSMesaContext);
using GetProcAddress = void* (*)(const char* name);

GetProcAddress osmesaGetProcAddress = nullptr;
void* loadGlFunction(const char* name) { return osmesaGetProcAddress(name); }

class OsMesaContext : public GlContext {
public:
    OsMesaContext(void* library, OSMesaContext context, DestroyContext destroy)
        : library_(library), context_(context), destroy_(destroy), pixels_(4) {}
    ~OsMesaContext() override {
        destroy_(context_);
        // The library stays loaded: Mesa keeps thread-local state that outlives this.
    }
    std::string backendName() const override { return "osmesa"; }
    std::vector<unsigned char>& pixels() { return pixels_; }

private:
    void* library_;
    OSMesaContext context_;
    DestroyContext destroy_;
    std::vector<unsigned char> pixels_;
};

}  // namespace

bool osmesaBuiltIn() { return true; }

std::unique_ptr<GlContext> createOsMesaContext(GlVersion required) {
    void* library = dlopen("libOSMesa.so.8", RTLD_NOW | RTLD_LOCAL);
    if (!library) library = dlopen("libOSMesa.so", RTLD_NOW | RTLD_LOCAL);
    if (!library)
        fail(ExitCode::GlProblem,
             "OSMesa: libOSMesa.so.8 not found (Debian/Ubuntu: apt install libosmesa6)");
    auto create = reinterpret_cast<CreateContextAttribs>(
        dlsym(library, "OSMesaCreateContextAttribs"));
    auto makeCurrent = reinterpret_cast<MakeCurrent>(dlsym(library, "OSMesaMakeCurrent"));
    auto destroy = reinterpret_cast<DestroyContext>(dlsym(library, "OSMesaDestroyContext"));
    osmesaGetProcAddress =
        reinterpret_cast<GetProcAddress>(dlsym(library, "OSMesaGetProcAddress"));
    if (!create || !makeCurrent || !destroy || !osmesaGetProcAddress)
        fail(ExitCode::GlProblem, "OSMesa: the library lacks OSMesaCreateContextAttribs");

    const int attributes[] = {OSMESA_FORMAT, OSMESA_RGBA, OSMESA_DEPTH_BITS, 0,
                              OSMESA_PROFILE, OSMESA_CORE_PROFILE,
                              OSMESA_CONTEXT_MAJOR_VERSION, required.major,
                              OSMESA_CONTEXT_MINOR_VERSION, required.minor, 0};
    OSMesaContext context = create(attributes, nullptr);
    if (!context) {
        // Mesa refuses a core context above what it supports: find out what it does.
        const int anyCore[] = {OSMESA_FORMAT, OSMESA_RGBA, OSMESA_PROFILE,
                               OSMESA_CORE_PROFILE, 0};
        OSMesaContext probe = create(anyCore, nullptr);
        std::string have = "an older version";
        if (probe) {
            unsigned char pixel[4];
            makeCurrent(probe, pixel, GL_UNSIGNED_BYTE_, 1, 1);
            using GetString = const unsigned char* (*)(unsigned);
            auto getString = reinterpret_cast<GetString>(osmesaGetProcAddress("glGetString"));
            if (getString && getString(0x1F02))
                have = reinterpret_cast<const char*>(getString(0x1F02));
            destroy(probe);
            failTooOld(required, have, "osmesa");
        }
        fail(ExitCode::GlProblem, "OSMesa: could not create a core context");
    }
    auto result = std::make_unique<OsMesaContext>(library, context, destroy);
    if (!makeCurrent(context, result->pixels().data(), GL_UNSIGNED_BYTE_, 1, 1))
        fail(ExitCode::GlProblem, "OSMesa: OSMesaMakeCurrent failed");
    loadGlAndCheckVersion(loadGlFunction, required, "osmesa");
    return result;
}

}  // namespace course
