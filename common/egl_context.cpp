// Headless OpenGL through EGL. Two ways to get a display without a window system:
//   EGL_EXT_platform_device   one display per GPU (how NVIDIA's driver renders
//                             headless); Mesa lists its software renderer here too
//   EGL_MESA_platform_surfaceless  Mesa with no window system at all (llvmpipe here)
// We prefer a hardware device, then surfaceless, then any device. No surface is
// created: chapters render into buffers, and EGL_KHR_surfaceless_context lets a
// context be current without one (a 1x1 pbuffer is the fallback).
#include <EGL/egl.h>
#include <EGL/eglext.h>

#include <cstring>
#include <vector>

#include "course/error.h"
#include "course/gl_context.h"
#include "course/log.h"

namespace course {
namespace {

bool hasExtension(const char* list, const char* name) {
    if (!list) return false;
    size_t length = std::strlen(name);
    for (const char* p = std::strstr(list, name); p; p = std::strstr(p + 1, name))
        if ((p == list || p[-1] == ' ') && (p[length] == ' ' || p[length] == '\0'))
            return true;
    return false;
}

std::string eglErrorName(EGLint error) {
    switch (error) {
        case EGL_NOT_INITIALIZED: return "EGL_NOT_INITIALIZED";
        case EGL_BAD_MATCH: return "EGL_BAD_MATCH";
        case EGL_BAD_ATTRIBUTE: return "EGL_BAD_ATTRIBUTE";
        case EGL_BAD_CONFIG: return "EGL_BAD_CONFIG";
        case EGL_BAD_DISPLAY: return "EGL_BAD_DISPLAY";
        case EGL_BAD_ALLOC: return "EGL_BAD_ALLOC";
        default: return "EGL error 0x" + std::to_string(error);
    }
}

// Sanitizer builds leave displays initialised: eglTerminate unloads Mesa's driver, and
// LeakSanitizer could then no longer tell that the driver's own allocations are the
// driver's (tests/sanitizers/lsan.supp suppresses them by library name).
void terminateDisplay(EGLDisplay display) {
#ifndef COURSE_SANITIZE_BUILD
    eglTerminate(display);
#else
    (void)display;
#endif
}

struct Candidate {
    EGLDisplay display;
    std::string description;
};

// Displays to try, best first.
std::vector<Candidate> candidateDisplays() {
    const char* clientExtensions = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
    auto getPlatformDisplay = reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(
        eglGetProcAddress("eglGetPlatformDisplayEXT"));
    std::vector<Candidate> hardware, software, surfaceless;

    if (getPlatformDisplay && hasExtension(clientExtensions, "EGL_EXT_platform_device")) {
        auto queryDevices = reinterpret_cast<PFNEGLQUERYDEVICESEXTPROC>(
            eglGetProcAddress("eglQueryDevicesEXT"));
        auto queryDeviceString = reinterpret_cast<PFNEGLQUERYDEVICESTRINGEXTPROC>(
            eglGetProcAddress("eglQueryDeviceStringEXT"));
        EGLDeviceEXT devices[16];
        EGLint count = 0;
        if (queryDevices && queryDeviceString && queryDevices(16, devices, &count)) {
            for (EGLint i = 0; i < count; ++i) {
                const char* extensions = queryDeviceString(devices[i], EGL_EXTENSIONS);
                bool isSoftware = hasExtension(extensions, "EGL_MESA_device_software");
                EGLDisplay display =
                    getPlatformDisplay(EGL_PLATFORM_DEVICE_EXT, devices[i], nullptr);
                if (display == EGL_NO_DISPLAY) continue;
                std::string name = "egl (device " + std::to_string(i) +
                                   (isSoftware ? ", software)" : ")");
                (isSoftware ? software : hardware).push_back({display, name});
            }
        }
    }
    if (getPlatformDisplay && hasExtension(clientExtensions, "EGL_MESA_platform_surfaceless")) {
        EGLDisplay display =
            getPlatformDisplay(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
        if (display != EGL_NO_DISPLAY) surfaceless.push_back({display, "egl (surfaceless)"});
    }
    std::vector<Candidate> all = hardware;
    all.insert(all.end(), surfaceless.begin(), surfaceless.end());
    all.insert(all.end(), software.begin(), software.end());
    return all;
}

class EglContext : public GlContext {
public:
    EglContext(EGLDisplay display, EGLContext context, EGLSurface surface,
               std::string description)
        : display_(display), context_(context), surface_(surface),
          description_(std::move(description)) {}
    ~EglContext() override {
        eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
        if (surface_ != EGL_NO_SURFACE) eglDestroySurface(display_, surface_);
        eglDestroyContext(display_, context_);
        terminateDisplay(display_);
    }
    std::string backendName() const override { return description_; }

private:
    EGLDisplay display_;
    EGLContext context_;
    EGLSurface surface_;
    std::string description_;
};

// Makes a core context of at least `required` on `display`, current. Returns false
// with a reason when this display cannot; throws GlTooOld when it can only do older.
std::unique_ptr<GlContext> tryDisplay(const Candidate& candidate, GlVersion required,
                                      std::string& reason) {
    EGLDisplay display = candidate.display;
    EGLint major = 0, minor = 0;
    if (!eglInitialize(display, &major, &minor)) {
        reason = candidate.description + ": eglInitialize failed (" +
                 eglErrorName(eglGetError()) + ")";
        return nullptr;
    }
    if (!eglBindAPI(EGL_OPENGL_API)) {
        reason = candidate.description + ": no desktop OpenGL";
        terminateDisplay(display);
        return nullptr;
    }
    const EGLint configAttributes[] = {EGL_SURFACE_TYPE, EGL_PBUFFER_BIT,
                                       EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_NONE};
    EGLConfig config = nullptr;
    EGLint configCount = 0;
    eglChooseConfig(display, configAttributes, &config, 1, &configCount);
    const char* extensions = eglQueryString(display, EGL_EXTENSIONS);
    if (configCount == 0 && !hasExtension(extensions, "EGL_KHR_no_config_context")) {
        reason = candidate.description + ": no OpenGL config";
        terminateDisplay(display);
        return nullptr;
    }
    EGLint flags = 0;
#ifndef NDEBUG
    flags |= EGL_CONTEXT_OPENGL_DEBUG_BIT_KHR;
#endif
    const EGLint contextAttributes[] = {
        EGL_CONTEXT_MAJOR_VERSION, required.major, EGL_CONTEXT_MINOR_VERSION,
        required.minor, EGL_CONTEXT_OPENGL_PROFILE_MASK,
        EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT, EGL_CONTEXT_FLAGS_KHR, flags, EGL_NONE};
    EGLConfig contextConfig = configCount ? config : EGL_NO_CONFIG_KHR;
    EGLContext context =
        eglCreateContext(display, contextConfig, EGL_NO_CONTEXT, contextAttributes);
    if (context == EGL_NO_CONTEXT) {
        // Ask for any version, only to tell the user which one there is.
        const EGLint anyVersion[] = {EGL_NONE};
        EGLContext probe = eglCreateContext(display, contextConfig, EGL_NO_CONTEXT, anyVersion);
        std::string have = "an older version";
        if (probe != EGL_NO_CONTEXT &&
            eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, probe)) {
            using GetString = const unsigned char* (*)(unsigned);
            auto getString = reinterpret_cast<GetString>(eglGetProcAddress("glGetString"));
            if (getString && getString(0x1F02 /* GL_VERSION */))
                have = reinterpret_cast<const char*>(getString(0x1F02));
            eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
        }
        if (probe != EGL_NO_CONTEXT) eglDestroyContext(display, probe);
        terminateDisplay(display);
        if (probe != EGL_NO_CONTEXT) failTooOld(required, have, candidate.description);
        reason = candidate.description + ": eglCreateContext failed";
        return nullptr;
    }
    EGLSurface surface = EGL_NO_SURFACE;
    if (!hasExtension(extensions, "EGL_KHR_surfaceless_context") && configCount) {
        const EGLint pbufferAttributes[] = {EGL_WIDTH, 1, EGL_HEIGHT, 1, EGL_NONE};
        surface = eglCreatePbufferSurface(display, config, pbufferAttributes);
    }
    if (!eglMakeCurrent(display, surface, surface, context)) {
        reason = candidate.description + ": eglMakeCurrent failed (" +
                 eglErrorName(eglGetError()) + ")";
        eglDestroyContext(display, context);
        terminateDisplay(display);
        return nullptr;
    }
    auto result = std::make_unique<EglContext>(display, context, surface,
                                               candidate.description);
    loadGlAndCheckVersion(reinterpret_cast<GlProcLoader>(eglGetProcAddress), required,
                          candidate.description);
    return result;
}

}  // namespace

bool eglBuiltIn() { return true; }

std::unique_ptr<GlContext> createEglContext(GlVersion required) {
    std::string reasons;
    for (const Candidate& candidate : candidateDisplays()) {
        std::string reason;
        if (auto context = tryDisplay(candidate, required, reason)) return context;
        logInfo(reason);
        reasons += "\n  " + reason;
    }
    fail(ExitCode::GlProblem,
         "EGL: no headless OpenGL display could be opened" +
             (reasons.empty() ? std::string(" (no EGL device or surfaceless platform)")
                              : reasons) +
             "\n  try --backend osmesa, or install Mesa's EGL (apt install libegl-mesa0)");
}

}  // namespace course
