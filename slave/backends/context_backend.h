// What the EGL, OSMesa and window backends share: the stream's contexts by id, the share
// context lookup, a default framebuffer kept while make_current asks for the same size and
// replaced when the size changes, and the teardown of every context before the driver's own
// (its display, its library). A Driver supplies only the calls into its library:
//
//   struct Context;                     // a driver context and its default framebuffer; its
//                                       // `int width, height` start at the driver's first size
//   static constexpr const char* name;  // the backend's name, the prefix of its errors
//   bool init(std::string& error);
//   bool prepare(std::string& error);   // per-thread driver state, before a create or make-current
//   bool create(const Context* share, const ContextRequest&, Context& out, std::string& error);
//   bool resize(Context&, int width, int height, std::string& error);
//   bool bind(uint32_t id, Context&, bool sized, std::string& error);  // sized: not 0 x 0
//   bool release(std::string& error);
//   void destroy(Context&);             // releases it first where it is current on this thread
//   void* proc_address(const char* name);
//   void present();
//   void set_position(int x, int y);
//
// DriverDefaults: those last hooks and prepare as no-ops, for drivers that need nothing there.
// Contexts are held by pointer so that a driver may give its window system the address of one
// (GLFW's user pointer). No lock: a backend is used from one thread at a time (backend.h).
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <unordered_map>

#include "slave/backend.h"

namespace glcast::slave {

struct DriverDefaults {
    bool prepare(std::string&) { return true; }
    void present() {}
    void set_position(int, int) {}
};

template <class Driver>
class ContextBackend final : public Backend {
public:
    using Context = typename Driver::Context;

    // The driver's destructor runs after this one: contexts go before their display or library.
    ~ContextBackend() override {
        for (auto& [id, c] : contexts_) driver_.destroy(*c);
    }

    bool init(std::string& error) { return driver_.init(error); }
    const char* name() const override { return Driver::name; }

    bool create_context(uint32_t id, uint32_t share_id, const ContextRequest& request,
                        std::string& error) override {
        if (id == 0) return fail(error, "context id 0 is reserved");
        if (contexts_.count(id)) return fail(error, "context " + std::to_string(id) + " already exists");
        const Context* share = nullptr;
        if (share_id && !(share = find(share_id)))
            return fail(error, "share context " + std::to_string(share_id) + " does not exist");
        if (!driver_.prepare(error)) return false;
        auto c = std::make_unique<Context>();
        if (!driver_.create(share, request, *c, error)) return false;
        contexts_[id] = std::move(c);
        return true;
    }

    // The default framebuffer is kept while the size stays (programs make their contexts
    // current every frame, and its contents must survive) and replaced when the master's window
    // was resized: the next frame redraws it.
    bool make_current(uint32_t id, int width, int height, std::string& error) override {
        Context* c = nullptr;
        if (id && !(c = find(id))) return fail(error, "make_current: no context " + std::to_string(id));
        if (!driver_.prepare(error)) return false;
        if (!c) return driver_.release(error);
        const bool sized = width > 0 && height > 0;
        if (sized && (width != c->width || height != c->height)) {
            if (!driver_.resize(*c, width, height, error)) return false;
            c->width = width;
            c->height = height;
        }
        return driver_.bind(id, *c, sized, error);
    }

    void destroy_context(uint32_t id) override {
        auto it = contexts_.find(id);
        if (it == contexts_.end()) return;
        const std::unique_ptr<Context> c = std::move(it->second);
        contexts_.erase(it);
        driver_.destroy(*c);
    }

    void* proc_address(const char* name) override { return driver_.proc_address(name); }
    void present() override { driver_.present(); }
    void set_position(int x, int y) override { driver_.set_position(x, y); }

private:
    Context* find(uint32_t id) {
        auto it = contexts_.find(id);
        return it == contexts_.end() ? nullptr : it->second.get();
    }
    static bool fail(std::string& error, const std::string& what) {
        error = std::string(Driver::name) + ": " + what;
        return false;
    }

    Driver driver_;
    std::unordered_map<uint32_t, std::unique_ptr<Context>> contexts_;
};

// The backend of Driver, or nullptr with `error` set when its library or display is unusable.
template <class Driver>
std::unique_ptr<Backend> make_context_backend(std::string& error) {
    auto backend = std::make_unique<ContextBackend<Driver>>();
    if (!backend->init(error)) return nullptr;
    return backend;
}

}  // namespace glcast::slave
