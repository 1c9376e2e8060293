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

#include <mutex>
#include <unordered_map>
#include <vector>

#include "slave/backends/backends_internal.h"
#include "slave/backends/dynlib.h"

namespace glcast::slave {
namespace {

struct Context {
    OSMesaContext ctx = nullptr;
    std::vector<uint32_t> buffer = std::vector<uint32_t>(1);  // the BGRA window framebuffer
    int width = 1, height = 1;
};

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

class OsmesaBackend final : public Backend {
public:
    ~OsmesaBackend() override {
        std::lock_guard<std::mutex> lock(mutex_);
        for (auto& [id, c] : contexts_) release_and_destroy(c->ctx);
        contexts_.clear();
    }

    const char* name() const override { return "osmesa"; }

    bool init(std::string& error) {
        void* lib = open_library("osmesa", {"libOSMesa.so.8", "libOSMesa.so.6", "libOSMesa.so"}, error);
        return lib && api_.load(lib, error);
    }

    bool create_context(uint32_t id, uint32_t share_id, const ContextRequest& request,
                        std::string& error) override {
        if (id == 0) return fail(error, "context id 0 is reserved");
        OSMesaContext share = nullptr;
        {
            std::lock_guard<std::mutex> lock(mutex_);
            if (contexts_.count(id)) return fail(error, "context " + std::to_string(id) + " already exists");
            if (share_id) {
                auto it = contexts_.find(share_id);
                if (it == contexts_.end())
                    return fail(error, "share context " + std::to_string(share_id) + " does not exist");
                share = it->second->ctx;
            }
        }
        std::vector<int> attribs = {OSMESA_FORMAT, OSMESA_BGRA, OSMESA_DEPTH_BITS, 24,
                                    OSMESA_STENCIL_BITS, 8};
        if (request.major > 0) {
            attribs.insert(attribs.end(),
                           {OSMESA_PROFILE, request.core ? OSMESA_CORE_PROFILE : OSMESA_COMPAT_PROFILE,
                            OSMESA_CONTEXT_MAJOR_VERSION, request.major,
                            OSMESA_CONTEXT_MINOR_VERSION, request.minor});
        } else {
            // No version: OSMesa answers 1.0 compatibility with its highest compatibility version.
            attribs.insert(attribs.end(), {OSMESA_PROFILE, OSMESA_COMPAT_PROFILE});
        }
        attribs.push_back(0);
        OSMesaContext ctx = api_.CreateContextAttribs(attribs.data(), share);
        if (!ctx) return fail(error, "OSMesaCreateContextAttribs(" + describe(request) + ") failed");
        auto c = std::make_unique<Context>();
        c->ctx = ctx;
        std::lock_guard<std::mutex> lock(mutex_);
        contexts_[id] = std::move(c);
        return true;
    }

    bool make_current(uint32_t id, int width, int height, std::string& error) override {
        if (id == 0) {
            if (!api_.MakeCurrent(nullptr, nullptr, 0, 0, 0))
                return fail(error, "OSMesaMakeCurrent(release) failed");
            return true;
        }
        Context* c;
        {
            std::lock_guard<std::mutex> lock(mutex_);
            auto it = contexts_.find(id);
            if (it == contexts_.end()) return fail(error, "make_current: no context " + std::to_string(id));
            c = it->second.get();
        }
        if (width > 0 && height > 0 && (width != c->width || height != c->height)) {
            c->buffer.assign(size_t(width) * size_t(height), 0);
            c->width = width;
            c->height = height;
        }
        if (!api_.MakeCurrent(c->ctx, c->buffer.data(), GL_UNSIGNED_BYTE, c->width, c->height))
            return fail(error, "OSMesaMakeCurrent(context " + std::to_string(id) + ") failed");
        return true;
    }

    void destroy_context(uint32_t id) override {
        std::unique_ptr<Context> c;
        {
            std::lock_guard<std::mutex> lock(mutex_);
            auto it = contexts_.find(id);
            if (it == contexts_.end()) return;
            c = std::move(it->second);
            contexts_.erase(it);
        }
        release_and_destroy(c->ctx);
    }

    void* proc_address(const char* name) override {
        return reinterpret_cast<void*>(api_.GetProcAddress(name));
    }

    void present() override {}

private:
    void release_and_destroy(OSMesaContext ctx) {
        if (api_.GetCurrentContext() == ctx) api_.MakeCurrent(nullptr, nullptr, 0, 0, 0);
        api_.DestroyContext(ctx);
    }

    static bool fail(std::string& error, const std::string& what) {
        error = "osmesa: " + what;
        return false;
    }

    OsmesaApi api_;
    std::mutex mutex_;
    std::unordered_map<uint32_t, std::unique_ptr<Context>> contexts_;  // buffers stay put
};

}  // namespace

std::unique_ptr<Backend> make_osmesa_backend(std::string& error) {
    auto backend = std::make_unique<OsmesaBackend>();
    if (!backend->init(error)) return nullptr;
    return backend;
}

}  // namespace glcast::slave
