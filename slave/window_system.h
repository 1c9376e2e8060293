// The window system on a slave: the master's contexts become the backend's, its drawables the
// backend's window framebuffers at the master's size (or the tile's), and its swaps the
// slave's frames. It follows the window-system calls semantics.yaml `contexts` names and the
// glcast.context and glcast.drawable_size tuples; everything else of GLX and EGL is the
// master's own business (queries, configurations).
#pragma once

#include <cstdint>
#include <map>
#include <utility>

#include "slave/backend.h"
#include "slave/replay_observer.h"

namespace glcast::slave {

class Replayer;

class WindowSystem : public ReplayObserver {
public:
    explicit WindowSystem(Replayer& core) : core_(core) {}

    bool wants(uint32_t opcode, const CommandInfo* info) const override;
    bool replace_call(const Call& c) override;
    void reset() override;

    // Makes `ctx` current again with its drawable (a call of another thread's context).
    void switch_to(SlaveContext& ctx);

private:
    void make_current(uint32_t id, uint64_t drawable);
    void window_size(uint64_t drawable, int& width, int& height) const;
    void end_frame();

    Replayer& core_;
    std::map<uint64_t, ContextRequest> pending_;  // creation requests by master handle
    bool said_passes_keep_depth_ = false;
    std::map<uint64_t, uint32_t> ids_by_handle_;
    void keep_drawable_size(uint64_t drawable, int width, int height);
    std::map<uint64_t, std::pair<int, int>> drawable_sizes_;
};

}  // namespace glcast::slave
