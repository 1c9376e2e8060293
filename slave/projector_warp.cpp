#include "slave/projector_warp.h"

#include <algorithm>
#include <cmath>

#include "slave/effects/gl_util.h"
#include "slave/replayer.h"
#include "slave/scene/window_copies.h"

namespace glcast::slave {

struct ProjectorWarp::ContextMaps {
    GLuint program = 0, vao = 0, vertices = 0, indices = 0, source = 0, source_fb = 0, alpha = 0, beta = 0;
    GLsizei index_count = 0;
    int width = 0, height = 0;  // of `source`
    bool warped = false;   // this frame: the window holds the projector's output
    bool restore = false;  // the program's frame goes back before its next write to the window
};

namespace {

// A blend map as 8-bit RGBA (what it was stored as): the texture unit's fast path.
GLuint blend_texture(const GlApi& gl, const BlendMap& map) {
    std::vector<uint8_t> rgba(size_t(map.width) * map.height * 4, 255);
    for (size_t i = 0; i < size_t(map.width) * map.height; i++)
        for (int c = 0; c < 3; c++)
            rgba[i * 4 + c] = uint8_t(std::lround(std::clamp(map.rgb[i * 3 + c], 0.0f, 1.0f) * 255));
    const GLuint t = effects::make_texture(gl, GL_RGBA8, map.width, map.height, /*linear=*/true);
    gl.glBindTexture(GL_TEXTURE_2D, t);
    gl.glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, map.width, map.height, GL_RGBA, GL_UNSIGNED_BYTE, rgba.data());
    return t;
}

// The warp as a mesh: a vertex per node (its output position, its source position) and two
// triangles per cell whose four nodes are all given; a cell with a NaN node stays black. Without
// a warp, one quad showing the tile's image as it is.
void build_mesh(const GlApi& gl, const ProjectorMaps& p, GLuint& vertices, GLuint& indices, GLsizei& count) {
    std::vector<float> v;
    std::vector<uint32_t> idx;
    const int nx = p.has_warp ? p.warp.width : 2, ny = p.has_warp ? p.warp.height : 2;
    v.reserve(size_t(nx) * ny * 4);
    for (int j = 0; j < ny; j++)
        for (int i = 0; i < nx; i++) {
            const float x = float(i) / float(nx - 1), y = float(j) / float(ny - 1);
            const float* uv = p.has_warp ? &p.warp.uv[(size_t(j) * nx + i) * 2] : nullptr;
            v.insert(v.end(), {x, y, uv ? uv[0] : x, uv ? uv[1] : y});
        }
    auto given = [&](int i, int j) {
        const float* n = &v[(size_t(j) * nx + i) * 4 + 2];
        return std::isfinite(n[0]) && std::isfinite(n[1]);
    };
    for (int j = 0; j + 1 < ny; j++)
        for (int i = 0; i + 1 < nx; i++) {
            if (!given(i, j) || !given(i + 1, j) || !given(i, j + 1) || !given(i + 1, j + 1)) continue;
            const uint32_t a = uint32_t(j * nx + i), b = a + 1, c = a + uint32_t(nx), d = c + 1;
            idx.insert(idx.end(), {a, b, c, b, d, c});
        }
    gl.glGenBuffers(1, &vertices);
    gl.glBindBuffer(GL_ARRAY_BUFFER, vertices);
    gl.glBufferData(GL_ARRAY_BUFFER, GLsizeiptr(v.size() * sizeof(float)), v.data(), GL_STATIC_DRAW);
    gl.glGenBuffers(1, &indices);
    gl.glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, indices);
    gl.glBufferData(GL_ELEMENT_ARRAY_BUFFER, GLsizeiptr(idx.size() * sizeof(uint32_t)), idx.data(), GL_STATIC_DRAW);
    gl.glVertexAttribPointer(0, 2, GL_FLOAT, GL_FALSE, 4 * sizeof(float), nullptr);
    gl.glVertexAttribPointer(1, 2, GL_FLOAT, GL_FALSE, 4 * sizeof(float), reinterpret_cast<void*>(2 * sizeof(float)));
    gl.glEnableVertexAttribArray(0);
    gl.glEnableVertexAttribArray(1);
    count = GLsizei(idx.size());
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
    effects::StateGuard guard(gl);  // (building the mesh binds buffers and unpacks too)
    auto& slot = contexts_[ctx.id];
    const ProjectorMaps& p = *maps_;
    if (!slot) {
        slot = std::make_unique<ContextMaps>();
        ContextMaps& m = *slot;
        m.program = effects::build_program(gl, "projector_warp.vert", "projector_warp.frag",
                                           std::string(p.has_alpha ? "#define HAS_ALPHA\n" : "") +
                                               (p.has_beta ? "#define HAS_BETA\n" : ""));
        gl.glGenVertexArrays(1, &m.vao);
        gl.glBindVertexArray(m.vao);
        build_mesh(gl, p, m.vertices, m.indices, m.index_count);
        if (p.has_alpha) m.alpha = blend_texture(gl, p.alpha);
        if (p.has_beta) m.beta = blend_texture(gl, p.beta);
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
    gl.glClearColor(0, 0, 0, 1);  // where no cell of the mesh lands: no light
    gl.glClear(GL_COLOR_BUFFER_BIT);
    gl.glUseProgram(m.program);
    const GLuint textures[3] = {m.source, m.alpha, m.beta};
    const char* names[3] = {"source", "alpha", "beta"};
    for (int unit = 0; unit < 3; unit++) {
        gl.glActiveTexture(GL_TEXTURE0 + unit);
        gl.glBindTexture(GL_TEXTURE_2D, textures[unit]);
        gl.glUniform1i(effects::uniform(gl, m.program, names[unit]), unit);
    }
    gl.glBindVertexArray(m.vao);
    gl.glDrawElements(GL_TRIANGLES, m.index_count, GL_UNSIGNED_INT, nullptr);
    m.warped = true;
}

// A program may draw its next frame over what its last one left in the back buffer: that is the
// frame, not the projector's output. It gets it back at its first write to the window, unless
// that write is a clear of the whole colour buffer (most programs': then nothing is copied).
// (With passes the effects runner puts the program's own image back instead, before this.)
void ProjectorWarp::presented(SlaveContext& ctx) {
    auto it = contexts_.find(ctx.id);
    if (it == contexts_.end() || !it->second->warped || core_.options().effects.followed()) return;
    it->second->warped = false;
    it->second->restore = true;
}

bool ProjectorWarp::wants(uint32_t, const CommandInfo* info) const {
    if (!info) return false;
    const RedrawKind k = info->sem.redraw;
    return k == RedrawKind::Draw || k == RedrawKind::Begin || k == RedrawKind::Pixels || k == RedrawKind::Copy ||
           k == RedrawKind::Clear;
}

void ProjectorWarp::before_call(const Call& c, const uint8_t*, size_t) {
    SlaveContext* ctx = core_.current_or_null();
    if (!ctx || !ctx->drawing_to_window) return;
    auto it = contexts_.find(ctx->id);
    if (it == contexts_.end() || !it->second->restore) return;
    ContextMaps& m = *it->second;
    m.restore = false;
    const GlApi& gl = core_.api();
    if (c.info->sem.redraw == RedrawKind::Clear && clears_whole_colour(gl, GLbitfield(c.args[0].bits)))
        return;  // all of it cleared
    if (m.width != ctx->width || m.height != ctx->height) return;  // resized: a new picture anyway
    GlStateGuard guard(gl, kGuardFramebuffers | kGuardRaster);
    gl.glBindFramebuffer(GL_READ_FRAMEBUFFER, m.source_fb);
    gl.glBindFramebuffer(GL_DRAW_FRAMEBUFFER, 0);
    gl.glDrawBuffer(ctx->double_buffered ? GL_BACK : GL_FRONT);
    gl.glDisable(GL_SCISSOR_TEST);
    gl.glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    gl.glBlitFramebuffer(0, 0, m.width, m.height, 0, 0, m.width, m.height, GL_COLOR_BUFFER_BIT, GL_NEAREST);
}

}  // namespace glcast::slave
