#include "slave/projector_warp.h"

#include "slave/effects/gl_util.h"
#include "slave/replayer.h"

namespace glcast::slave {

struct ProjectorWarp::ContextMaps {
    GLuint program = 0, vao = 0, source = 0, source_fb = 0, warp = 0, alpha = 0, beta = 0;
    bool warped = false;  // this frame: the window holds the projector's output
    int width = 0, height = 0;  // of `source`
};

namespace {

GLuint float_texture(const GlApi& gl, GLenum format, GLenum layout, int width, int height, const float* values) {
    const GLuint t = effects::make_texture(gl, format, width, height, /*linear=*/true);
    gl.glBindTexture(GL_TEXTURE_2D, t);
    gl.glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, width, height, layout, GL_FLOAT, values);
    return t;
}

}  // namespace

ProjectorWarp::ProjectorWarp(Replayer& core, std::shared_ptr<const ProjectorMaps> maps)
    : core_(core), maps_(std::move(maps)) {}

ProjectorWarp::~ProjectorWarp() = default;

void ProjectorWarp::reset() { contexts_.clear(); }

void ProjectorWarp::context_removed(uint32_t id) { contexts_.erase(id); }

void ProjectorWarp::end_frame(SlaveContext& ctx) {
    if (ctx.width <= 0 || ctx.height <= 0) return;
    const GlApi& gl = core_.api();
    effects::StateGuard guard(gl);  // (the textures' creation binds and unpacks too)
    auto& slot = contexts_[ctx.id];
    if (!slot) {
        slot = std::make_unique<ContextMaps>();
        ContextMaps& m = *slot;
        m.program = effects::build_program(gl, "fullscreen.vert", "projector_warp.frag");
        gl.glGenVertexArrays(1, &m.vao);
        const ProjectorMaps& p = *maps_;
        if (p.has_warp) m.warp = float_texture(gl, GL_RG32F, GL_RG, p.warp.width, p.warp.height, p.warp.uv.data());
        if (p.has_alpha) m.alpha = float_texture(gl, GL_RGB32F, GL_RGB, p.alpha.width, p.alpha.height, p.alpha.rgb.data());
        if (p.has_beta) m.beta = float_texture(gl, GL_RGB32F, GL_RGB, p.beta.width, p.beta.height, p.beta.rgb.data());
    }
    ContextMaps& m = *slot;
    if (m.width != ctx.width || m.height != ctx.height) {
        if (m.source) gl.glDeleteTextures(1, &m.source);
        if (m.source_fb) gl.glDeleteFramebuffers(1, &m.source_fb);
        m.source = effects::make_texture(gl, GL_RGBA8, ctx.width, ctx.height, /*linear=*/true);
        m.source_fb = effects::make_framebuffer(gl, m.source, 0);
        m.width = ctx.width, m.height = ctx.height;
    }
    // The frame as it would be shown, from the window's shown buffer into the source texture.
    const GLenum shown = ctx.double_buffered ? GL_BACK : GL_FRONT;
    gl.glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
    gl.glBindFramebuffer(GL_DRAW_FRAMEBUFFER, 0);
    gl.glReadBuffer(shown);
    gl.glDrawBuffer(shown);
    gl.glActiveTexture(GL_TEXTURE0);
    gl.glBindTexture(GL_TEXTURE_2D, m.source);
    gl.glCopyTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, 0, 0, ctx.width, ctx.height);
    gl.glViewport(0, 0, ctx.width, ctx.height);
    gl.glDisable(GL_BLEND);
    gl.glDisable(GL_DEPTH_TEST);
    gl.glDisable(GL_SCISSOR_TEST);
    gl.glDisable(GL_STENCIL_TEST);
    gl.glDisable(GL_CULL_FACE);
    gl.glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    gl.glUseProgram(m.program);
    const GLuint textures[4] = {m.source, m.warp, m.alpha, m.beta};
    const char* names[4] = {"source", "warp", "alpha", "beta"};
    for (int unit = 0; unit < 4; unit++) {
        gl.glActiveTexture(GL_TEXTURE0 + unit);
        gl.glBindTexture(GL_TEXTURE_2D, textures[unit]);
        gl.glUniform1i(effects::uniform(gl, m.program, names[unit]), unit);
    }
    const ProjectorMaps& p = *maps_;
    gl.glUniform2f(effects::uniform(gl, m.program, "warp_nodes"), GLfloat(p.warp.width), GLfloat(p.warp.height));
    gl.glUniform1i(effects::uniform(gl, m.program, "has_warp"), p.has_warp);
    gl.glUniform1i(effects::uniform(gl, m.program, "has_alpha"), p.has_alpha);
    gl.glUniform1i(effects::uniform(gl, m.program, "has_beta"), p.has_beta);
    effects::draw_fullscreen(gl, m.vao);
    m.warped = true;
}

// A program may draw its next frame over what its last one left in the back buffer: that is the
// frame, not the projector's output. (With passes the effects runner puts the program's own image
// back instead, before this.)
void ProjectorWarp::presented(SlaveContext& ctx) {
    auto it = contexts_.find(ctx.id);
    if (it == contexts_.end() || !it->second->warped || core_.options().effects.followed()) return;
    ContextMaps& m = *it->second;
    m.warped = false;
    if (m.width != ctx.width || m.height != ctx.height) return;
    const GlApi& gl = core_.api();
    GlStateGuard guard(gl, kGuardFramebuffers | kGuardRaster);
    gl.glBindFramebuffer(GL_READ_FRAMEBUFFER, m.source_fb);
    gl.glBindFramebuffer(GL_DRAW_FRAMEBUFFER, 0);
    gl.glDrawBuffer(ctx.double_buffered ? GL_BACK : GL_FRONT);
    gl.glDisable(GL_SCISSOR_TEST);
    gl.glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    gl.glBlitFramebuffer(0, 0, m.width, m.height, 0, 0, m.width, m.height, GL_COLOR_BUFFER_BIT, GL_NEAREST);
}

}  // namespace glcast::slave
