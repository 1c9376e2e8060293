// The injected passes of a slave (docs/effects.md), run at the end of each frame before present in
// this order: snow cover and icicles, shadows, falling snow or rain (particles, then the
// spectral composite). Cover comes before shadows so that shadows fall on the snow. One Pipeline per slave GL context: passes keep GL objects of the
// context they were created in.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "slave/effects/effect_params.h"
#include "slave/effects/frame_view.h"
#include "slave/effects/gl_api.h"

namespace glcast::slave::effects {

// One injected pass. run() is called with the window framebuffer bound for drawing, the
// viewport covering the tile, and a StateGuard around it (a pass may change any state the
// guard lists and needs not restore it; anything else it changes it must restore).
class Pass {
public:
    virtual ~Pass() = default;
    virtual const char* name() const = 0;
    virtual void run(const GlApi& gl, const FrameView& view) = 0;
};

// Per-pass factories and parameter declarations, each in the pass's own file.
std::unique_ptr<Pass> make_shadow_pass(const GlApi& gl, const EffectParams& params);
std::unique_ptr<Pass> make_winter_surfaces_pass(const GlApi& gl, const EffectParams& params, bool cover, bool icicles);
std::unique_ptr<Pass> make_precipitation_pass(const GlApi& gl, const EffectParams& params, bool rain);
std::vector<ParamSpec> shadow_param_specs();
std::vector<ParamSpec> winter_surfaces_param_specs();
std::vector<ParamSpec> precipitation_param_specs();

class Pipeline {
public:
    // Builds the enabled passes in the current context; throws std::runtime_error (a shader
    // that does not compile, a missing GL function) with the pass named.
    Pipeline(const GlApi& gl, const EffectsSettings& settings);
    void run(const FrameView& view);
    // Milliseconds of GPU time per pass in the last frame (GL_TIME_ELAPSED), for benchmarks.
    const std::vector<std::pair<std::string, double>>& last_timings() const { return timings_; }
    void set_timing(bool on) { timing_ = on; }

private:
    const GlApi& gl_;
    std::vector<std::unique_ptr<Pass>> passes_;
    std::vector<std::pair<std::string, double>> timings_;
    bool timing_ = false;
};

}  // namespace glcast::slave::effects
