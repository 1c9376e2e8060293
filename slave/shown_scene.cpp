// A scene shown in part of the window, on a rotated tile (shown_scene.h).
#include "slave/shown_scene.h"

#include <cmath>

#include "common/gl_state.h"
#include "slave/effects/gl_util.h"

namespace glcast::slave {

void ShownScene::begin(const GlApi& gl, int master_w, int master_h, const int32_t viewport[4]) {
    gl.glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &draw_framebuffer_);
    gl.glGetIntegerv(GL_READ_FRAMEBUFFER_BINDING, &read_framebuffer_);
    gl.glGetIntegerv(GL_VIEWPORT, viewport_);
    gl.glGetIntegerv(GL_DEPTH_FUNC, &depth_func_);
    depth_test_ = gl.glIsEnabled(GL_DEPTH_TEST);
    scissor_test_ = gl.glIsEnabled(GL_SCISSOR_TEST);
    gl.glGetBooleanv(GL_DEPTH_WRITEMASK, &depth_mask_);
    gl.glGetBooleanv(GL_COLOR_WRITEMASK, colour_mask_);
    gl.glGetDoublev(GL_DEPTH_RANGE, depth_range_);
    gl.glGetFloatv(GL_DEPTH_CLEAR_VALUE, &clear_depth_);
    redirected_ = true;
    GLint texture = 0;  // (making the footprint binds its texture)
    gl.glGetIntegerv(GL_TEXTURE_BINDING_2D, &texture);
    footprint_.begin(gl, master_w, master_h, viewport);
    gl.glBindTexture(GL_TEXTURE_2D, GLuint(texture));
}

bool ShownScene::end(const GlApi& gl, int32_t rect[4]) {
    if (!redirected_) return false;
    redirected_ = false;
    bool drawn = false;
    {
        GlStateGuard pack(gl, kGuardPixelPack);
        drawn = footprint_.measure(gl, rect);
    }
    gl.glBindFramebuffer(GL_DRAW_FRAMEBUFFER, GLuint(draw_framebuffer_));
    gl.glBindFramebuffer(GL_READ_FRAMEBUFFER, GLuint(read_framebuffer_));
    gl.glViewport(viewport_[0], viewport_[1], viewport_[2], viewport_[3]);
    if (depth_test_) gl.glEnable(GL_DEPTH_TEST);
    else gl.glDisable(GL_DEPTH_TEST);
    if (scissor_test_) gl.glEnable(GL_SCISSOR_TEST);
    gl.glDepthFunc(GLenum(depth_func_));
    gl.glDepthMask(depth_mask_);
    gl.glColorMask(colour_mask_[0], colour_mask_[1], colour_mask_[2], colour_mask_[3]);
    gl.glDepthRange(depth_range_[0], depth_range_[1]);
    gl.glClearDepth(clear_depth_);
    return drawn;
}

bool ShownScene::cover(const GlApi& gl, int master_w, int master_h, const int32_t rect[4], int32_t out[4]) {
    const int32_t window[4] = {0, 0, master_w, master_h};
    begin(gl, master_w, master_h, window);
    footprint_.cover(gl, rect);
    return end(gl, out);
}

void ShownScene::TileTarget::fit(const GlApi& gl, GLenum format, int width, int height) {
    if (size[0] == width && size[1] == height) return;
    if (framebuffer) gl.glDeleteFramebuffers(1, &framebuffer), gl.glDeleteTextures(1, &texture);
    framebuffer = texture = 0;
    size[0] = size[1] = 0;
    texture = effects::make_texture(gl, format, width, height);
    framebuffer = effects::make_framebuffer(gl, texture, 0);
    size[0] = width, size[1] = height;
}

GLuint ShownScene::draw_stretched(const GlApi& gl, const int32_t rect[4], const int32_t viewport[4], int tile_w,
                                  int tile_h, const std::function<void()>& draw) {
    // (saved before the target is made: making it binds it, and its texture)
    GLint draw_framebuffer = 0, read_framebuffer = 0, saved_viewport[4] = {}, texture = 0;
    GLfloat clear[4] = {};
    gl.glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &draw_framebuffer);
    gl.glGetIntegerv(GL_READ_FRAMEBUFFER_BINDING, &read_framebuffer);
    gl.glGetIntegerv(GL_TEXTURE_BINDING_2D, &texture);
    gl.glGetIntegerv(GL_VIEWPORT, saved_viewport);
    gl.glGetFloatv(GL_COLOR_CLEAR_VALUE, clear);
    const GLboolean scissor = gl.glIsEnabled(GL_SCISSOR_TEST);
    auto restore = [&] {
        gl.glBindFramebuffer(GL_DRAW_FRAMEBUFFER, GLuint(draw_framebuffer));
        gl.glBindFramebuffer(GL_READ_FRAMEBUFFER, GLuint(read_framebuffer));
        gl.glViewport(saved_viewport[0], saved_viewport[1], saved_viewport[2], saved_viewport[3]);
        gl.glClearColor(clear[0], clear[1], clear[2], clear[3]);
        if (scissor) gl.glEnable(GL_SCISSOR_TEST);
        gl.glBindTexture(GL_TEXTURE_2D, GLuint(texture));
    };
    try {
        stretched_.fit(gl, GL_RGBA8, tile_w, tile_h);
    } catch (...) {
        restore();
        throw;
    }
    gl.glBindTexture(GL_TEXTURE_2D, GLuint(texture));  // the program's draw samples it
    gl.glBindFramebuffer(GL_READ_FRAMEBUFFER, GLuint(read_framebuffer));  // (and a blit reads its own)
    gl.glBindFramebuffer(GL_DRAW_FRAMEBUFFER, stretched_.framebuffer);
    gl.glDisable(GL_SCISSOR_TEST);
    gl.glClearColor(0, 0, 0, 0);
    gl.glClear(GL_COLOR_BUFFER_BIT);
    const double sx = double(tile_w) / (rect[2] - rect[0]), sy = double(tile_h) / (rect[3] - rect[1]);
    gl.glViewport(GLint(std::lround((viewport[0] - rect[0]) * sx)), GLint(std::lround((viewport[1] - rect[1]) * sy)),
                  GLsizei(std::lround(viewport[2] * sx)), GLsizei(std::lround(viewport[3] * sy)));
    draw();
    restore();
    return stretched_.texture;
}

void ShownScene::composite(const GlApi& gl, GLuint scene, const glm::dmat3& tile_to_screen, const int32_t viewport[4],
                           int tile_w, int tile_h) {
    effects::StateGuard guard(gl);
    auto build = [&gl](Program& p, const char* defines) {
        p.name = effects::build_program(gl, "fullscreen.vert", "shown_scene.frag", defines);
        p.scene = effects::uniform(gl, p.name, "scene");
        p.footprint = effects::uniform(gl, p.name, "footprint");
        p.tile_to_screen = effects::uniform(gl, p.name, "tile_to_screen");
    };
    if (!picture_.name) {
        build(picture_, "");
        build(marks_, "#define MASK\n");
        gl.glGenVertexArrays(1, &vao_);
    }
    mask_.fit(gl, GL_R8, tile_w, tile_h);
    gl.glDisable(GL_DEPTH_TEST);
    gl.glDisable(GL_BLEND);
    gl.glDepthMask(GL_FALSE);
    gl.glActiveTexture(GL_TEXTURE0);
    gl.glBindTexture(GL_TEXTURE_2D, scene);
    gl.glActiveTexture(GL_TEXTURE1);
    gl.glBindTexture(GL_TEXTURE_2D, footprint_.depth_texture());
    if (gl.has(OP_glBindSampler)) gl.glBindSampler(0, 0), gl.glBindSampler(1, 0);  // (the guard puts the program's back)
    const glm::mat3 m(tile_to_screen);
    gl.glBindFramebuffer(GL_DRAW_FRAMEBUFFER, mask_.framebuffer);
    gl.glViewport(0, 0, tile_w, tile_h);
    gl.glClearColor(0, 0, 0, 0);
    gl.glClear(GL_COLOR_BUFFER_BIT);
    for (const Program* p : {&marks_, &picture_}) {
        if (p == &picture_) gl.glBindFramebuffer(GL_DRAW_FRAMEBUFFER, 0);
        gl.glViewport(viewport[0], viewport[1], viewport[2], viewport[3]);
        gl.glUseProgram(p->name);
        gl.glUniform1i(p->scene, 0);
        gl.glUniform1i(p->footprint, 1);
        gl.glUniformMatrix3fv(p->tile_to_screen, 1, GL_FALSE, &m[0][0]);
        effects::draw_fullscreen(gl, vao_);
    }
}

}  // namespace glcast::slave
