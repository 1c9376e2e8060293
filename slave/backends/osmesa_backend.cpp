// OSMesa backend: Mesa's software renderer (llvmpipe) with no window system at all; the
// reference renderer of the tests.
//
// Each context's window framebuffer is its own BGRA buffer of the master's window size (the
// byte order of an X11 TrueColor window, which Mesa rasterizes through the same paths), freed
// with the context. Mesa writes into it on glFlush/glFinish, so it lives as long as the
// context. (Mesa 22 binds a drawable per context; older osmesa.c looked drawables up by format
// and size across contexts, where same-sized per-context buffers would alias.)
//
// libOSMesa.so.8 is opened at run time; its GL entry points come from OSMesaGetProcAddress.
// OSMesa has no attributes for debug or forward-compatible contexts: those request bits are
// ignored (GL_KHR_debug output still works once the program enables GL_DEBUG_OUTPUT).
#include <GL/osmesa.h>

#include <cstdio>
#include <vector>

#include "slave/backends/backends_internal.h"
#include "slave/backends/context_backend.h"
#include "slave/backends/dynlib.h"

namespace glcast::slave {
namespace {

struct OsmesaApi {
    bool load(void* lib, std::string& error) {
        return load_symbols("osmesa", lib, error,
                            "OSMesaCreateContextAttribs", CreateContextAttribs, "OSMesaDestroyContext", DestroyContext,
                            "OSMesaMakeCurrent", MakeCurrent, "OSMesaGetCurrentContext", GetCurrentContext,
                            "OSMesaGetProcAddress", GetProcAddress);
    }

    decltype(&::OSMesaCreateContextAttribs) CreateContextAttribs = nullptr;
    decltype(&::OSMesaDestroyContext) DestroyContext = nullptr;
    decltype(&::OSMesaMakeCurrent) MakeCurrent = nullptr;
    decltype(&::OSMesaGetCurrentContext) GetCurrentContext = nullptr;
    decltype(&::OSMesaGetProcAddress) GetProcAddress = nullptr;
};

class OsmesaDriver : public DriverDefaults {
public:
    struct Context {
        OSMesaContext context = nullptr;
        std::vector<uint32_t> buffer = std::vector<uint32_t>(1);  // the BGRA window framebuffer
        int width = 1, height = 1;  // OSMesa makes nothing current without a buffer
    };
    static constexpr const char* name = "osmesa";

    bool init(std::string& error) {
        void* lib = open_library("osmesa", {"libOSMesa.so.8", "libOSMesa.so.6", "libOSMesa.so"}, error);
        return lib && api_.load(lib, error);
    }

    bool create(const Context* share, const ContextRequest& request, Context& out, std::string& error) {
        std::vector<int> attribs = {OSMESA_FORMAT, OSMESA_BGRA, OSMESA_DEPTH_BITS, request.depth,
                                    OSMESA_STENCIL_BITS, request.stencil};
        if (request.es && !warned_es_) {
            warned_es_ = true;
            std::fprintf(stderr, "glcast slave: osmesa has no OpenGL ES: the program's %s context is replayed in a "
                                 "desktop OpenGL one, whose version strings, extensions and shader rules differ "
                                 "(EGL makes an ES context)\n",
                         describe(request).c_str());
        }
        if (request.depth > 24 && !warned_depth_) {
            warned_depth_ = true;
            std::fprintf(stderr, "glcast slave: osmesa has at most 24 depth bits: the program's %d are 24 here, and "
                                 "what it asks of them differs (EGL matches them)\n",
                         request.depth);
        }
        if (request.major > 0 && !request.es) {
            attribs.insert(attribs.end(),
                           {OSMESA_PROFILE, request.core ? OSMESA_CORE_PROFILE : OSMESA_COMPAT_PROFILE,
                            OSMESA_CONTEXT_MAJOR_VERSION, request.major,
                            OSMESA_CONTEXT_MINOR_VERSION, request.minor});
        } else {
            // No version: OSMesa answers 1.0 compatibility with its highest compatibility version.
            attribs.insert(attribs.end(), {OSMESA_PROFILE, OSMESA_COMPAT_PROFILE});
        }
        attribs.push_back(0);
        if (request.samples > 1 && !warned_samples_) {
            warned_samples_ = true;
            std::fprintf(stderr, "glcast slave: osmesa has no multisampled framebuffer: the program's %d samples are "
                                 "rendered as one, and polygon edges differ from the program's (EGL matches them)\n",
                         request.samples);
        }
        out.context = api_.CreateContextAttribs(attribs.data(), share ? share->context : nullptr);
        if (!out.context) return fail(error, "OSMesaCreateContextAttribs(" + describe(request) + ") failed");
        return true;
    }

    bool resize(Context& c, int width, int height, std::string&) {
        c.buffer.assign(size_t(width) * size_t(height), 0);
        return true;
    }

    bool bind(uint32_t id, Context& c, bool, std::string& error) {
        if (!api_.MakeCurrent(c.context, c.buffer.data(), GL_UNSIGNED_BYTE, c.width, c.height))
            return fail(error, "OSMesaMakeCurrent(context " + std::to_string(id) + ") failed");
        return true;
    }

    bool release(std::string& error) {
        if (!api_.MakeCurrent(nullptr, nullptr, 0, 0, 0)) return fail(error, "OSMesaMakeCurrent(release) failed");
        return true;
    }

    void destroy(Context& c) {
        if (api_.GetCurrentContext() == c.context) api_.MakeCurrent(nullptr, nullptr, 0, 0, 0);
        api_.DestroyContext(c.context);
    }

    void* proc_address(const char* name) { return reinterpret_cast<void*>(api_.GetProcAddress(name)); }

    // Nothing swaps an OSMesa buffer: a flush at the end of each frame keeps the driver from
    // queueing frame after frame (as the EGL backend's pbuffer did).
    void present() {
        if (!flush_) flush_ = reinterpret_cast<void (*)()>(api_.GetProcAddress("glFlush"));
        if (flush_) flush_();
    }

private:
    void (*flush_)() = nullptr;
    bool warned_samples_ = false;
    bool warned_es_ = false;
    bool warned_depth_ = false;
    static bool fail(std::string& error, const std::string& what) {
        error = "osmesa: " + what;
        return false;
    }

    OsmesaApi api_;
};

}  // namespace

std::unique_ptr<Backend> make_osmesa_backend(std::string& error) {
    return make_context_backend<OsmesaDriver>(error);
}

}  // namespace glcast::slave
