// EGL surfaceless backend: headless contexts on EGL_MESA_platform_surfaceless. Each context's
// window framebuffer is a pbuffer of an XRGB8888 config, the format of an X11 TrueColor window,
// so the driver rasterizes exactly as it did for the program's window (Mesa's fast paths and
// rounding depend on the colour format and on the window-system orientation). On a machine
// with a GPU render node Mesa picks the GPU; without one, llvmpipe.
//
// libEGL.so.1 is opened at run time (dynlib.h); every EGL call goes through the pointers below.
// EGL keeps the bound API and the current context per thread, so make_current binds the
// context's API (EGL_OPENGL_API, or EGL_OPENGL_ES_API for a program's OpenGL ES context) on the
// calling thread each time instead of once at start. A thread may hold one current context per
// API, and GL calls go to the one made current last: binding a context of the other API first
// releases the one current there, so that the replay's calls never reach a context it left.
#define EGL_NO_X11
#define MESA_EGL_NO_X11_HEADERS
#include <EGL/egl.h>
#include <EGL/eglext.h>

#include <array>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <mutex>
#include <vector>

#include "common/environment.h"
#include "slave/backends/backends_internal.h"
#include "slave/backends/context_backend.h"
#include "slave/backends/dynlib.h"

namespace glcast::slave {
namespace {

const char* egl_error_name(EGLint e) {
    switch (e) {
        case EGL_SUCCESS: return "EGL_SUCCESS";
        case EGL_NOT_INITIALIZED: return "EGL_NOT_INITIALIZED";
        case EGL_BAD_ACCESS: return "EGL_BAD_ACCESS";
        case EGL_BAD_ALLOC: return "EGL_BAD_ALLOC";
        case EGL_BAD_ATTRIBUTE: return "EGL_BAD_ATTRIBUTE";
        case EGL_BAD_CONFIG: return "EGL_BAD_CONFIG";
        case EGL_BAD_CONTEXT: return "EGL_BAD_CONTEXT";
        case EGL_BAD_CURRENT_SURFACE: return "EGL_BAD_CURRENT_SURFACE";
        case EGL_BAD_DISPLAY: return "EGL_BAD_DISPLAY";
        case EGL_BAD_MATCH: return "EGL_BAD_MATCH";
        case EGL_BAD_NATIVE_PIXMAP: return "EGL_BAD_NATIVE_PIXMAP";
        case EGL_BAD_NATIVE_WINDOW: return "EGL_BAD_NATIVE_WINDOW";
        case EGL_BAD_PARAMETER: return "EGL_BAD_PARAMETER";
        case EGL_BAD_SURFACE: return "EGL_BAD_SURFACE";
        case EGL_CONTEXT_LOST: return "EGL_CONTEXT_LOST";
        default: return "unknown EGL error";
    }
}

bool has_extension(const char* list, const char* name) {
    if (!list) return false;
    const std::string s = std::string(" ") + list + " ";
    return s.find(std::string(" ") + name + " ") != std::string::npos;
}

struct EglApi {
    bool load(void* lib, std::string& error) {
        return load_symbols("egl", lib, error,
                            "eglGetProcAddress", GetProcAddress, "eglGetError", GetError,
                            "eglQueryString", QueryString, "eglInitialize", Initialize,
                            "eglTerminate", Terminate, "eglBindAPI", BindAPI,
                            "eglChooseConfig", ChooseConfig, "eglCreateContext", CreateContext,
                            "eglDestroyContext", DestroyContext, "eglMakeCurrent", MakeCurrent,
                            "eglGetCurrentContext", GetCurrentContext, "eglCreatePbufferSurface", CreatePbufferSurface,
                            "eglGetConfigAttrib", GetConfigAttrib, "eglDestroySurface", DestroySurface);
    }

    decltype(&::eglGetProcAddress) GetProcAddress = nullptr;
    decltype(&::eglGetError) GetError = nullptr;
    decltype(&::eglQueryString) QueryString = nullptr;
    decltype(&::eglInitialize) Initialize = nullptr;
    decltype(&::eglTerminate) Terminate = nullptr;
    decltype(&::eglBindAPI) BindAPI = nullptr;
    decltype(&::eglChooseConfig) ChooseConfig = nullptr;
    decltype(&::eglCreateContext) CreateContext = nullptr;
    decltype(&::eglDestroyContext) DestroyContext = nullptr;
    decltype(&::eglMakeCurrent) MakeCurrent = nullptr;
    decltype(&::eglGetCurrentContext) GetCurrentContext = nullptr;
    decltype(&::eglCreatePbufferSurface) CreatePbufferSurface = nullptr;
    decltype(&::eglGetConfigAttrib) GetConfigAttrib = nullptr;
    decltype(&::eglDestroySurface) DestroySurface = nullptr;
    PFNEGLGETPLATFORMDISPLAYEXTPROC GetPlatformDisplayEXT = nullptr;
    decltype(&::eglGetPlatformDisplay) GetPlatformDisplay = nullptr;  // EGL 1.5, may be absent
};

// The surfaceless display is one per process, shared by every EGL backend: count the users so
// that destroying one backend does not terminate the display under another.
std::mutex g_display_mutex;
int g_display_users = 0;

class EglDriver : public DriverDefaults {
public:
    struct Context {
        EGLContext context = EGL_NO_CONTEXT;
        EGLConfig config = EGL_NO_CONFIG_KHR;  // single-sampled, or as many samples as the program's
        EGLSurface surface = EGL_NO_SURFACE;  // the pbuffer
        int width = 0, height = 0;
        bool es = false;  // an OpenGL ES context
    };
    static constexpr const char* name = "egl";

    ~EglDriver() {
        if (!display_counted_) return;
        std::lock_guard<std::mutex> lock(g_display_mutex);
        if (--g_display_users == 0) api_.Terminate(display_);
    }

    bool init(std::string& error) {
        void* lib = open_library("egl", {"libEGL.so.1", "libEGL.so"}, error);
        if (!lib || !api_.load(lib, error)) return false;
        api_.GetPlatformDisplay =
            reinterpret_cast<decltype(api_.GetPlatformDisplay)>(dlsym(lib, "eglGetPlatformDisplay"));
        api_.GetPlatformDisplayEXT = reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(
            api_.GetProcAddress("eglGetPlatformDisplayEXT"));

        const char* client_ext = api_.QueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
        if (!has_extension(client_ext, "EGL_MESA_platform_surfaceless"))
            return fail(error, "EGL_MESA_platform_surfaceless is not supported by this libEGL");
        if (api_.GetPlatformDisplay)
            display_ = api_.GetPlatformDisplay(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
        else if (api_.GetPlatformDisplayEXT)
            display_ = api_.GetPlatformDisplayEXT(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
        else
            return fail(error, "neither eglGetPlatformDisplay nor eglGetPlatformDisplayEXT exists");
        if (display_ == EGL_NO_DISPLAY) return fail_egl(error, "eglGetPlatformDisplay(surfaceless)");

        {
            std::lock_guard<std::mutex> lock(g_display_mutex);
            EGLint major = 0, minor = 0;
            if (!api_.Initialize(display_, &major, &minor)) return fail_egl(error, "eglInitialize");
            ++g_display_users;
            display_counted_ = true;
            version_ = major * 10 + minor;
        }
        const char* ext = api_.QueryString(display_, EGL_EXTENSIONS);
        if (!has_extension(ext, "EGL_KHR_surfaceless_context"))
            return fail(error, "the display lacks EGL_KHR_surfaceless_context");
        if (version_ < 15 && !has_extension(ext, "EGL_KHR_create_context"))
            return fail(error, "the display lacks EGL_KHR_create_context (EGL 1.4)");
        return choose_config(error) && prepare(error);
    }

    bool prepare(std::string& error) { return bind_api(false, error); }

    bool create(const Context* share, const ContextRequest& request, Context& out, std::string& error) {
        if (request.es) return create_es(share, request, out, error);
        std::vector<EGLint> attribs;
        EGLint flags = 0;
        if (request.major > 0) {
            attribs.insert(attribs.end(), {EGL_CONTEXT_MAJOR_VERSION, request.major,
                                           EGL_CONTEXT_MINOR_VERSION, request.minor});
            // A profile exists only from 3.2 on; EGL rejects the mask below it.
            if (request.major > 3 || (request.major == 3 && request.minor >= 2))
                attribs.insert(attribs.end(),
                               {EGL_CONTEXT_OPENGL_PROFILE_MASK,
                                request.core ? EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT
                                             : EGL_CONTEXT_OPENGL_COMPATIBILITY_PROFILE_BIT});
            if (request.forward_compatible && request.major >= 3)
                flags |= EGL_CONTEXT_OPENGL_FORWARD_COMPATIBLE_BIT_KHR;
        }
        // major 0: no version and no profile, which EGL answers with the highest compatibility
        // context the driver has (a "core" flag means nothing without a version, as in GLX).
        if (request.debug) flags |= EGL_CONTEXT_OPENGL_DEBUG_BIT_KHR;
        if (flags) attribs.insert(attribs.end(), {EGL_CONTEXT_FLAGS_KHR, flags});
        if (request.no_error) attribs.insert(attribs.end(), {EGL_CONTEXT_OPENGL_NO_ERROR_KHR, EGL_TRUE});
        attribs.push_back(EGL_NONE);

        out.config = config_for(request);
        out.context = api_.CreateContext(display_, out.config, share ? share->context : EGL_NO_CONTEXT, attribs.data());
        if (out.context == EGL_NO_CONTEXT) return fail_egl(error, "eglCreateContext(" + describe(request) + ")");
        return true;
    }

    // The program asked for an ES version (ES 2.0 may be answered with a later one, as on the
    // master); a context shares only with one of its own API.
    bool create_es(const Context* share, const ContextRequest& request, Context& out, std::string& error) {
        if (share && !share->es)
            return fail(error, "an OpenGL ES context cannot share objects with a desktop OpenGL one");
        out.config = config_for(request);
        EGLint renderable = 0;
        api_.GetConfigAttrib(display_, out.config, EGL_RENDERABLE_TYPE, &renderable);
        const EGLint wanted = request.major >= 3 ? EGL_OPENGL_ES3_BIT : request.major == 2 ? EGL_OPENGL_ES2_BIT
                                                                                            : EGL_OPENGL_ES_BIT;
        if (!(renderable & wanted))
            return fail(error, "the EGL config renders no " + describe(request) + " (EGL_RENDERABLE_TYPE 0x" +
                                   hex(renderable) + ")");
        const EGLint attribs[] = {EGL_CONTEXT_MAJOR_VERSION, request.major ? request.major : 1,
                                  EGL_CONTEXT_MINOR_VERSION, request.minor, EGL_NONE};
        if (!bind_api(true, error)) return false;
        out.context = api_.CreateContext(display_, out.config, share ? share->context : EGL_NO_CONTEXT, attribs);
        out.es = true;
        std::string ignored;
        bind_api(false, ignored);
        if (out.context == EGL_NO_CONTEXT) return fail_egl(error, "eglCreateContext(" + describe(request) + ")");
        return true;
    }

    // The old pbuffer may be current (on this thread or another): destroyed once released.
    bool resize(Context& c, int width, int height, std::string& error) {
        const EGLint attribs[] = {EGL_WIDTH, width, EGL_HEIGHT, height, EGL_NONE};
        EGLSurface fresh = api_.CreatePbufferSurface(display_, c.config, attribs);
        if (fresh == EGL_NO_SURFACE)
            return fail_egl(error, "eglCreatePbufferSurface(" + std::to_string(width) + "x" + std::to_string(height) + ")");
        if (c.surface != EGL_NO_SURFACE) retired_.push_back(c.surface);
        c.surface = fresh;
        return true;
    }

    // Asked for no size (0 x 0), the context is current without a framebuffer (surfaceless).
    bool bind(uint32_t id, Context& c, bool sized, std::string& error) {
        const EGLSurface surface = sized ? c.surface : EGL_NO_SURFACE;
        if (!release_other_api(c.es, error) || !bind_api(c.es, error)) return false;
        if (!api_.MakeCurrent(display_, surface, surface, c.context))
            return fail_egl(error, "eglMakeCurrent(context " + std::to_string(id) + ")");
        destroy_retired();
        return true;
    }

    // Of both APIs: eglMakeCurrent(EGL_NO_CONTEXT) releases the bound API's context only.
    bool release(std::string& error) {
        for (const bool es : {true, false}) {
            if (!bind_api(es, error)) return false;
            if (!api_.MakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT))
                return fail_egl(error, "eglMakeCurrent(release)");
        }
        destroy_retired();
        return true;
    }

    // EGL defers destroying a context current on some thread; release it first on this one.
    void destroy(Context& c) {
        std::string ignored;
        bind_api(c.es, ignored);
        if (api_.GetCurrentContext() == c.context)
            api_.MakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
        bind_api(false, ignored);
        api_.DestroyContext(display_, c.context);
        if (c.surface != EGL_NO_SURFACE) api_.DestroySurface(display_, c.surface);
    }

    void* proc_address(const char* name) { return reinterpret_cast<void*>(api_.GetProcAddress(name)); }

    // A pbuffer is never swapped: without a flush at the end of each frame the driver may keep
    // queueing the frames' work, growing without bound until a readback pays for all of it
    // (docs/performance.md).
    void present() {
        if (!flush_) flush_ = reinterpret_cast<void (*)()>(api_.GetProcAddress("glFlush"));
        if (flush_) flush_();
    }

private:
    void (*flush_)() = nullptr;

    bool bind_api(bool es, std::string& error) {
        if (api_.BindAPI(es ? EGL_OPENGL_ES_API : EGL_OPENGL_API)) return true;
        return fail_egl(error, es ? "eglBindAPI(EGL_OPENGL_ES_API)" : "eglBindAPI(EGL_OPENGL_API)");
    }

    bool release_other_api(bool es, std::string& error) {
        if (!bind_api(!es, error)) return false;
        if (api_.GetCurrentContext() == EGL_NO_CONTEXT) return true;
        if (api_.MakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT)) return true;
        return fail_egl(error, "eglMakeCurrent(release of the other API's context)");
    }

    static std::string hex(EGLint v) {
        char s[16];
        std::snprintf(s, sizeof s, "%x", unsigned(v));
        return s;
    }
    // One config for every context (so that they can share) and its pbuffers: 8-bit RGB without
    // alpha, 24-bit depth, 8-bit stencil, like the program's GLX visual.
    bool choose_config(std::string& error) {
        const EGLint attribs[] = {EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_SURFACE_TYPE, EGL_PBUFFER_BIT,
                                  EGL_RED_SIZE, 8, EGL_GREEN_SIZE, 8, EGL_BLUE_SIZE, 8, EGL_ALPHA_SIZE, 0,
                                  EGL_DEPTH_SIZE, 24, EGL_STENCIL_SIZE, 8, EGL_NONE};
        // Among them exactly 8/8/8/0 bits (the at-least-8 match also returns 10-bit configs),
        // and of those the lowest config id: Mesa lists XRGB8888 (B, G, R, X in memory, the X11
        // window's layout) before XBGR8888, and the surfaceless platform reports no native
        // visual id to tell them apart. The pixel-exact replay tests catch a driver that orders
        // them otherwise; GLCAST_EGL_CONFIG_ID overrides.
        EGLConfig configs[64];
        EGLint count = 0;
        if (!api_.ChooseConfig(display_, attribs, configs, 64, &count) || count < 1)
            return fail_egl(error, "eglChooseConfig(RGB888 pbuffer)");
        const uint32_t forced = environment().egl_config_id;
        EGLint best_id = 0;
        for (EGLint i = 0; i < count; ++i) {
            EGLint id = 0, r = 0, g = 0, b = 0, a = 0;
            api_.GetConfigAttrib(display_, configs[i], EGL_CONFIG_ID, &id);
            api_.GetConfigAttrib(display_, configs[i], EGL_RED_SIZE, &r);
            api_.GetConfigAttrib(display_, configs[i], EGL_GREEN_SIZE, &g);
            api_.GetConfigAttrib(display_, configs[i], EGL_BLUE_SIZE, &b);
            api_.GetConfigAttrib(display_, configs[i], EGL_ALPHA_SIZE, &a);
            const bool wanted = forced ? uint32_t(id) == forced : (r == 8 && g == 8 && b == 8 && a == 0);
            if (wanted && (!best_id || id < best_id)) {
                best_id = id;
                config_ = configs[i];
            }
        }
        if (!best_id) return fail(error, "no EGL config with 8-bit RGB, no alpha, depth 24, stencil 8");
        return true;
    }

    // A program's window framebuffer of other bits (samples, resolved when read back or copied as
    // a window is; alpha, depth, stencil) gets a pbuffer of the same, RGB as config_ (lowest id).
    EGLConfig config_for(const ContextRequest& r) {
        const int samples = r.samples > 1 ? r.samples : 0;
        if (!samples && r.alpha == 0 && r.depth == 24 && r.stencil == 8) return config_;
        const std::array<int, 4> key{samples, r.alpha, r.depth, r.stencil};
        auto known = configs_.find(key);
        if (known != configs_.end()) return known->second;
        const EGLint attribs[] = {EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_SURFACE_TYPE, EGL_PBUFFER_BIT,
                                  EGL_RED_SIZE, 8, EGL_GREEN_SIZE, 8, EGL_BLUE_SIZE, 8, EGL_ALPHA_SIZE, r.alpha,
                                  EGL_DEPTH_SIZE, r.depth, EGL_STENCIL_SIZE, r.stencil,
                                  EGL_SAMPLE_BUFFERS, samples ? 1 : 0, EGL_SAMPLES, samples, EGL_NONE};
        EGLConfig configs[256];
        EGLint count = 0, best_id = 0;
        EGLConfig best = config_;
        if (api_.ChooseConfig(display_, attribs, configs, 256, &count)) {
            for (EGLint i = 0; i < count; ++i) {
                EGLint id = 0, red = 0, alpha = 0, depth = 0, stencil = 0, s = 0;
                api_.GetConfigAttrib(display_, configs[i], EGL_CONFIG_ID, &id);
                api_.GetConfigAttrib(display_, configs[i], EGL_RED_SIZE, &red);
                api_.GetConfigAttrib(display_, configs[i], EGL_ALPHA_SIZE, &alpha);
                api_.GetConfigAttrib(display_, configs[i], EGL_DEPTH_SIZE, &depth);
                api_.GetConfigAttrib(display_, configs[i], EGL_STENCIL_SIZE, &stencil);
                api_.GetConfigAttrib(display_, configs[i], EGL_SAMPLES, &s);
                const bool same = red == 8 && alpha == r.alpha && depth == r.depth && stencil == r.stencil && s == samples;
                if (same && (!best_id || id < best_id)) best_id = id, best = configs[i];
            }
        }
        if (!best_id)
            std::fprintf(stderr, "glcast slave: egl: no pbuffer config with %d samples, %d alpha, %d depth and %d "
                                 "stencil bits; this context renders with the default (1 sample, 0, 24, 8), and what "
                                 "the program reads of the missing bits differs\n",
                         samples, r.alpha, r.depth, r.stencil);
        configs_[key] = best;
        return best;
    }

    void destroy_retired() {
        for (EGLSurface old : retired_) api_.DestroySurface(display_, old);
        retired_.clear();
    }

    static bool fail(std::string& error, const std::string& what) {
        error = "egl: " + what;
        return false;
    }
    bool fail_egl(std::string& error, const std::string& call) {
        error = "egl: " + call + " failed: " + egl_error_name(api_.GetError());
        return false;
    }

    EglApi api_;
    EGLDisplay display_ = EGL_NO_DISPLAY;
    EGLConfig config_ = EGL_NO_CONFIG_KHR;
    std::map<std::array<int, 4>, EGLConfig> configs_;  // by samples, alpha, depth, stencil
    int version_ = 0;
    bool display_counted_ = false;
    std::vector<EGLSurface> retired_;  // replaced pbuffers, until the next make-current
};

}  // namespace

std::unique_ptr<Backend> make_egl_backend(std::string& error) { return make_context_backend<EglDriver>(error); }

}  // namespace glcast::slave
