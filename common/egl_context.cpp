// Headless OpenGL through EGL. Two ways to get a display without a window system:
//   EGL_EXT_platform_device   one display per GPU (how NVIDIA's driver renders
//                             headless); Mesa lists its software renderer here too
//   EGL_MESA_platform_surfaceless  Mesa with no window system at all (llvmpipe here)
// We try every hardware device, then surfaceless, then the software devices, and take
// the first that gives the chapter's OpenGL; --gpu N (or COURSE_GPU=N) takes device N
// and no other. No surface is created: chapters render into buffers, and
// EGL_KHR_surfaceless_context lets a context be current without one (a 1x1 pbuffer is
// the fallback).
#include <EGL/egl.h>
#include <EGL/eglext.h>

#include <cstring>
#include <vector>

#include "course/context_search.h"
#include "course/error.h"
#include "course/gl_context.h"
#include "course/log.h"

// Names from newer eglext.h files, for older ones.
#ifndef EGL_RENDERER_EXT
#define EGL_RENDERER_EXT 0x335F  // EGL_EXT_device_query_name
#endif
#ifndef EGL_DRM_DEVICE_FILE_EXT
#define EGL_DRM_DEVICE_FILE_EXT 0x3233  // EGL_EXT_device_drm
#endif
#ifndef EGL_CONTEXT_OPENGL_DEBUG
#define EGL_CONTEXT_OPENGL_DEBUG 0x31B0  // EGL 1.5
#endif

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

// What a device is called: its renderer's name where EGL_EXT_device_query_name gives
// one, else its DRM file, else whether it is software.
std::string deviceName(EGLDeviceEXT device, PFNEGLQUERYDEVICESTRINGEXTPROC queryString,
                       bool isSoftware) {
    const char* extensions = queryString(device, EGL_EXTENSIONS);
    if (hasExtension(extensions, "EGL_EXT_device_query_name"))
        if (const char* renderer = queryString(device, EGL_RENDERER_EXT)) return renderer;
    if (hasExtension(extensions, "EGL_EXT_device_drm"))
        if (const char* file = queryString(device, EGL_DRM_DEVICE_FILE_EXT)) return file;
    return isSoftware ? "software" : "hardware";
}

// Displays to try, best first; with `gpu` >= 0, device `gpu` alone.
std::vector<Candidate> candidateDisplays(int gpu) {
    const char* clientExtensions = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
    auto getPlatformDisplay = reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(
        eglGetProcAddress("eglGetPlatformDisplayEXT"));
    std::vector<Candidate> hardware, software, surfaceless;
    std::string deviceList;
    EGLint count = 0;

    if (getPlatformDisplay && hasExtension(clientExtensions, "EGL_EXT_platform_device")) {
        auto queryDevices = reinterpret_cast<PFNEGLQUERYDEVICESEXTPROC>(
            eglGetProcAddress("eglQueryDevicesEXT"));
        auto queryDeviceString = reinterpret_cast<PFNEGLQUERYDEVICESTRINGEXTPROC>(
            eglGetProcAddress("eglQueryDeviceStringEXT"));
        EGLDeviceEXT devices[16];
        if (!queryDevices || !queryDeviceString || !queryDevices(16, devices, &count))
            count = 0;
        for (EGLint i = 0; i < count; ++i) {
            const char* extensions = queryDeviceString(devices[i], EGL_EXTENSIONS);
            const bool isSoftware = hasExtension(extensions, "EGL_MESA_device_software");
            const std::string name =
                "egl device " + std::to_string(i) + " (" +
                deviceName(devices[i], queryDeviceString, isSoftware) + ")";
            logInfo("found " + name);
            deviceList += "\n  " + name;
            if (gpu >= 0 && i != gpu) continue;
            EGLDisplay display =
                getPlatformDisplay(EGL_PLATFORM_DEVICE_EXT, devices[i], nullptr);
            if (display == EGL_NO_DISPLAY) continue;
            (isSoftware ? software : hardware).push_back({display, name});
        }
    }
    if (gpu >= 0) {
        if (gpu >= count)
            fail(ExitCode::BadUsage,
                 "--gpu " + std::to_string(gpu) + ": there is no EGL device " +
                     std::to_string(gpu) +
                     (count ? "; this machine's are:" + deviceList
                            : std::string("; this EGL lists no devices (EGL_EXT_platform_device)")));
        hardware.insert(hardware.end(), software.begin(), software.end());
        return hardware;
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
    // A version and a core profile can be asked for with EGL_KHR_create_context or
    // EGL 1.5 (which took the same attributes in, but its own for debug contexts).
    const bool createContextKhr = hasExtension(extensions, "EGL_KHR_create_context");
    if (!createContextKhr && major * 10 + minor < 15) {
        reason = candidate.description + ": EGL " + std::to_string(major) + "." +
                 std::to_string(minor) +
                 " without EGL_KHR_create_context cannot ask for a core OpenGL version";
        terminateDisplay(display);
        return nullptr;
    }
    std::vector<EGLint> contextAttributes = {
        EGL_CONTEXT_MAJOR_VERSION, required.major, EGL_CONTEXT_MINOR_VERSION,
        required.minor, EGL_CONTEXT_OPENGL_PROFILE_MASK, EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT};
    if (createContextKhr)
        contextAttributes.insert(contextAttributes.end(), {EGL_CONTEXT_FLAGS_KHR, flags});
    else if (flags)
        contextAttributes.insert(contextAttributes.end(), {EGL_CONTEXT_OPENGL_DEBUG, EGL_TRUE});
    contextAttributes.push_back(EGL_NONE);
    EGLConfig contextConfig = configCount ? config : EGL_NO_CONFIG_KHR;
    EGLContext context =
        eglCreateContext(display, contextConfig, EGL_NO_CONTEXT, contextAttributes.data());
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

std::unique_ptr<GlContext> createEglContext(GlVersion required, int gpu) {
    std::vector<ContextCandidate> candidates;
    for (const Candidate& display : candidateDisplays(gpu))
        candidates.push_back({display.description, [display, required](std::string& reason) {
                                  return tryDisplay(display, required, reason);
                              }});
    std::string reasons;
    if (auto context = firstWorkingContext(candidates, reasons)) return context;
    fail(ExitCode::GlProblem,
         "EGL: no headless OpenGL display could be opened" +
             (reasons.empty() ? std::string(" (no EGL device or surfaceless platform)")
                              : reasons) +
             "\n  try --backend osmesa, or install Mesa's EGL (apt install libegl-mesa0)");
}

}  // namespace course
