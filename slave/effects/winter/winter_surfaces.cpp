// The snow cover and icicle pass (docs/winter.md): the snow accumulator of docs/winter.md, snow by
// texture and icicle generator, done in screen space at the end of each frame. Per frame:
//   1. the surfaces under the tile and its guard band (re-rendered normals, or from depth);
//   2. the cover: snow amount per pixel (spread angle, density, seed, mask);
//   3. the snow shaded over the window (--effects cover);
//   4. icicles under the lower edges of the cover (--effects icicles).
// Both effects share steps 1 and 2, so they are one pass with two switches.
#include <cinttypes>
#include <cstdio>
#include <memory>
#include <optional>

#include "slave/effects/gl_util.h"
#include "slave/effects/pipeline.h"
#include "slave/effects/winter/winter_cover.h"
#include "slave/effects/winter/winter_gl.h"
#include "slave/effects/winter/winter_icicles.h"
#include "slave/effects/winter/winter_settings.h"
#include "slave/effects/winter/winter_surface_buffers.h"

namespace glcast::slave::effects {

namespace {

class WinterSurfacesPass final : public Pass {
public:
    WinterSurfacesPass(const GlApi& gl, const EffectParams& params, bool cover, bool icicles)
        : settings_(winter_settings_from(params)), draw_cover_(cover), surfaces_(gl), cover_(gl, settings_.cover) {
        if (icicles) icicles_.emplace(gl, settings_.icicles);
    }

    const char* name() const override {
        return draw_cover_ && icicles_ ? "cover+icicles" : draw_cover_ ? "cover" : "icicles";
    }

    void run(const GlApi& gl, const FrameView& view) override {
        // No perspective view this frame (a 2D program, a loading screen): nothing to tell "up" by,
        // so nothing holds snow (the effects runner says so once).
        if (!view.view_known) return;
        // The lazy window copies bind framebuffers of their own: take them before ours.
        const GLuint window_depth = view.depth_texture();
        if (settings_.cover.up_auto && !auto_up_) {
            auto_up_ = world_up_seen(view.modelview);
            std::fprintf(stderr, "[glcast] cover/icicles: up is the world's %c%c, the axis the view of frame %" PRIu64
                                 " sees as up (cover.up_x/y/z set it)\n",
                         auto_up_->y + auto_up_->z > 0 ? '+' : '-', auto_up_->y != 0 ? 'Y' : 'Z', view.frame);
        }
        const WinterFrame frame = winter_frame(view, settings_, icicles_.has_value(), auto_up_ ? *auto_up_ : settings_.cover.up);
        surfaces_.update(view, frame, settings_.cover.normals, window_depth);
        cover_.classify(view, frame, surfaces_, window_depth);

        gl.glBindFramebuffer(GL_FRAMEBUFFER, 0);
        gl.glViewport(0, 0, view.width, view.height);
        if (draw_cover_) cover_.composite(view, frame, surfaces_);
        if (icicles_) icicles_->run(view, frame, surfaces_, cover_.cover(), window_depth);
    }

private:
    const WinterSettings settings_;  // the stages keep references into it
    const bool draw_cover_;
    SurfaceBuffers surfaces_;
    CoverStage cover_;
    std::optional<IcicleStage> icicles_;
    std::optional<glm::dvec3> auto_up_;  // cover.up_space=auto: chosen at the first frame with a view
};

}  // namespace

std::unique_ptr<Pass> make_winter_surfaces_pass(const GlApi& gl, const EffectParams& params, bool cover,
                                                bool icicles) {
    return std::make_unique<WinterSurfacesPass>(gl, params, cover, icicles);
}

std::vector<ParamSpec> winter_surfaces_param_specs() { return winter_param_specs(); }

}  // namespace glcast::slave::effects
