#include "slave/effects/pipeline.h"

#include <stdexcept>

#include "slave/effects/gl_util.h"

namespace glcast::slave::effects {

Pipeline::Pipeline(const GlApi& gl, const EffectsSettings& settings) : gl_(gl) {
    StateGuard guard(gl);  // passes create their objects with default pixel-store state, and bind them
    const EffectParams& p = settings.params;
    // Cover before shadows (docs/effects.md says why this order): the cover repaints the
    // surfaces it covers, which would erase shadows cast on them; shadows after it darken snow
    // and icicles like the rest of the scene. Falling snow stays unshadowed, in front of it all.
    if (settings.cover || settings.icicles)
        passes_.push_back(make_winter_surfaces_pass(gl, p, settings.cover, settings.icicles));
    if (settings.shadows) passes_.push_back(make_shadow_pass(gl, p));
    if (settings.snow || settings.rain) passes_.push_back(make_precipitation_pass(gl, p, settings.rain));
}

void Pipeline::run(const FrameView& view) {
    timings_.clear();
    for (auto& pass : passes_) {
        StateGuard guard(gl_);
        gl_.glBindFramebuffer(GL_DRAW_FRAMEBUFFER, 0);
        gl_.glViewport(0, 0, view.width, view.height);
        GLuint query = 0;
        if (timing_) {
            gl_.glGenQueries(1, &query);
            gl_.glBeginQuery(GL_TIME_ELAPSED, query);
        }
        pass->run(gl_, view);
        if (timing_) {
            gl_.glEndQuery(GL_TIME_ELAPSED);
            GLuint64 ns = 0;
            gl_.glGetQueryObjectui64v(query, GL_QUERY_RESULT, &ns);
            gl_.glDeleteQueries(1, &query);
            timings_.emplace_back(pass->name(), ns / 1e6);
        }
    }
}

}  // namespace glcast::slave::effects
