// The soft-shadow pass (`--effects shadows`, docs/shadows.md): contact-hardening shadows that
// the program never drew, computed by ShadowRenderer and multiplied into the tile.
#include <cstdio>
#include <memory>
#include <set>
#include <string>

#include "slave/effects/pipeline.h"
#include "slave/effects/shadows/shadow_renderer.h"
#include "slave/effects/shadows/shadow_settings.h"

namespace glcast::slave::effects {

namespace {

class ShadowPass : public Pass {
public:
    ShadowPass(const GlApi& gl, const ShadowSettings& settings) : renderer_(gl, settings) {}
    const char* name() const override { return "shadows"; }

    void run(const GlApi&, const FrameView& view) override {
        if (!view.view_known) return;  // (the effects runner says so once)
        std::string why;
        if (!renderer_.render(view, why)) {
            // Once per reason: a program without a perspective frame now and then is normal.
            if (reported_.insert(why).second)
                std::fprintf(stderr, "glcast shadows: frame %llu left unshadowed: %s\n",
                             static_cast<unsigned long long>(view.frame), why.c_str());
            return;
        }
        if (renderer_.used_screen_space() && renderer_.settings().method != ShadowMethod::ScreenSpace &&
            reported_.insert("screen-space").second)
            std::fprintf(stderr, "glcast shadows: frame %llu: the draws cannot be re-rendered from the light; "
                                 "shadows from the depth on the screen (screen-space) instead\n",
                         static_cast<unsigned long long>(view.frame));
        renderer_.composite(view);
    }

private:
    ShadowRenderer renderer_;
    std::set<std::string> reported_;
};

}  // namespace

std::unique_ptr<Pass> make_shadow_pass(const GlApi& gl, const EffectParams& params) {
    return std::make_unique<ShadowPass>(gl, shadow_settings_from(params));
}

}  // namespace glcast::slave::effects
