// Copies of the window framebuffer (window_copies.h).
#include "slave/scene/window_copies.h"

#include <algorithm>

#include <glm/glm.hpp>
#include <glm/gtc/type_ptr.hpp>

#include "slave/effects/gl_util.h"
#include "slave/replayer.h"
#include "slave/scene/depth_convention.h"
#include "slave/scene/scene_recorder.h"

namespace glcast::slave {

namespace {

// A full-screen draw of `program` into the depth-only target `fb` (width x height) that writes
// every fragment's gl_FragDepth, reading `source` on texture unit 0.
void begin_depth_draw(const GlApi& gl, GLuint fb, int width, int height, GLuint program, GLuint source) {
    gl.glBindFramebuffer(GL_DRAW_FRAMEBUFFER, fb);
    gl.glViewport(0, 0, width, height);
    gl.glEnable(GL_DEPTH_TEST);
    gl.glDepthFunc(GL_ALWAYS);
    gl.glDepthMask(GL_TRUE);
    gl.glColorMask(GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
    gl.glUseProgram(program);
    gl.glActiveTexture(GL_TEXTURE0);
    gl.glBindTexture(GL_TEXTURE_2D, source);
}

// The size of the target a scene is drawn into offscreen: the program's window, or its viewport
// when the scene is drawn at another size and shown stretched.
void scene_target_size(const SlaveContext& ctx, const ContextScene& scene, int& SW, int& SH) {
    const int W = std::max(1, ctx.master_width), H = std::max(1, ctx.master_height);
    const bool stretched = scene.loan.borrowed_from == 0 && stretched_scene(scene.facts, W, H);
    SW = stretched ? scene.facts.viewport[2] : W, SH = stretched ? scene.facts.viewport[3] : H;
}

}  // namespace

bool clears_whole_colour(const GlApi& gl, GLbitfield mask) {
    if (!(mask & GL_COLOR_BUFFER_BIT)) return false;
    GLboolean write[4] = {GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE};
    gl.glGetBooleanv(GL_COLOR_WRITEMASK, write);
    return !gl.glIsEnabled(GL_SCISSOR_TEST) && write[0] && write[1] && write[2];
}

GLenum depth_format(const GlApi& gl, GLenum target) {
    GLint type = GL_NONE, name = 0, stencil_type = GL_NONE, stencil_name = 0, bits = 0, component = GL_NONE;
    gl.glGetFramebufferAttachmentParameteriv(target, GL_DEPTH_ATTACHMENT, GL_FRAMEBUFFER_ATTACHMENT_OBJECT_TYPE, &type);
    if (type == GL_NONE) return 0;
    gl.glGetFramebufferAttachmentParameteriv(target, GL_DEPTH_ATTACHMENT, GL_FRAMEBUFFER_ATTACHMENT_OBJECT_NAME, &name);
    gl.glGetFramebufferAttachmentParameteriv(target, GL_DEPTH_ATTACHMENT, GL_FRAMEBUFFER_ATTACHMENT_DEPTH_SIZE, &bits);
    gl.glGetFramebufferAttachmentParameteriv(target, GL_DEPTH_ATTACHMENT, GL_FRAMEBUFFER_ATTACHMENT_COMPONENT_TYPE,
                                             &component);
    gl.glGetFramebufferAttachmentParameteriv(target, GL_STENCIL_ATTACHMENT, GL_FRAMEBUFFER_ATTACHMENT_OBJECT_TYPE,
                                             &stencil_type);
    if (stencil_type != GL_NONE)
        gl.glGetFramebufferAttachmentParameteriv(target, GL_STENCIL_ATTACHMENT, GL_FRAMEBUFFER_ATTACHMENT_OBJECT_NAME,
                                                 &stencil_name);
    const bool packed = stencil_type == type && stencil_name == name;  // one depth-stencil image
    if (component == GL_FLOAT) return packed ? GL_DEPTH32F_STENCIL8 : GL_DEPTH_COMPONENT32F;
    if (bits <= 16) return GL_DEPTH_COMPONENT16;
    if (bits <= 24) return packed ? GL_DEPTH24_STENCIL8 : GL_DEPTH_COMPONENT24;
    return GL_DEPTH_COMPONENT32;
}

bool depth_size(const GlApi& gl, GLenum target, int& width, int& height) {
    GLint type = GL_NONE, name = 0, w = 0, h = 0;
    gl.glGetFramebufferAttachmentParameteriv(target, GL_DEPTH_ATTACHMENT, GL_FRAMEBUFFER_ATTACHMENT_OBJECT_TYPE, &type);
    gl.glGetFramebufferAttachmentParameteriv(target, GL_DEPTH_ATTACHMENT, GL_FRAMEBUFFER_ATTACHMENT_OBJECT_NAME, &name);
    GLint bound = 0;
    if (type == GL_RENDERBUFFER) {
        gl.glGetIntegerv(GL_RENDERBUFFER_BINDING, &bound);
        gl.glBindRenderbuffer(GL_RENDERBUFFER, GLuint(name));
        gl.glGetRenderbufferParameteriv(GL_RENDERBUFFER, GL_RENDERBUFFER_WIDTH, &w);
        gl.glGetRenderbufferParameteriv(GL_RENDERBUFFER, GL_RENDERBUFFER_HEIGHT, &h);
        gl.glBindRenderbuffer(GL_RENDERBUFFER, GLuint(bound));
    } else if (type == GL_TEXTURE) {  // a 2D texture's level 0 (what the program's depth attachments are)
        GLint level = 0;
        gl.glGetFramebufferAttachmentParameteriv(target, GL_DEPTH_ATTACHMENT, GL_FRAMEBUFFER_ATTACHMENT_TEXTURE_LEVEL,
                                                 &level);
        gl.glGetIntegerv(GL_TEXTURE_BINDING_2D, &bound);
        gl.glBindTexture(GL_TEXTURE_2D, GLuint(name));
        gl.glGetTexLevelParameteriv(GL_TEXTURE_2D, level, GL_TEXTURE_WIDTH, &w);
        gl.glGetTexLevelParameteriv(GL_TEXTURE_2D, level, GL_TEXTURE_HEIGHT, &h);
        gl.glBindTexture(GL_TEXTURE_2D, GLuint(bound));
    }
    width = int(w), height = int(h);
    return w > 0 && h > 0;
}

bool WindowCopies::sized(const SlaveContext& ctx) const { return width_ == ctx.width && height_ == ctx.height; }

void WindowCopies::size(SlaveContext& ctx) {
    if (sized(ctx)) return;
    const GlApi& gl = core_.api();
    effects::StateGuard guard(gl);  // making them binds textures and framebuffers: the program's
    GLuint textures[4] = {color_texture_, depth_texture_, program_image, scene_image};
    GLuint fbs[4] = {color_fb_, depth_fb_, program_image_fb, scene_image_fb};
    if (color_texture_) gl.glDeleteTextures(4, textures), gl.glDeleteFramebuffers(4, fbs);
    color_texture_ = effects::make_texture(gl, GL_RGBA8, ctx.width, ctx.height);
    depth_texture_ = effects::make_texture(gl, GL_DEPTH24_STENCIL8, ctx.width, ctx.height);
    program_image = effects::make_texture(gl, GL_RGBA8, ctx.width, ctx.height);
    scene_image = effects::make_texture(gl, GL_RGBA8, ctx.width, ctx.height);
    color_fb_ = effects::make_framebuffer(gl, color_texture_, 0);
    depth_fb_ = effects::make_framebuffer(gl, 0, depth_texture_, GL_DEPTH_STENCIL_ATTACHMENT);
    program_image_fb = effects::make_framebuffer(gl, program_image, 0);
    scene_image_fb = effects::make_framebuffer(gl, scene_image, 0);
    width_ = ctx.width, height_ = ctx.height;
}

// Between the window's colour buffer (the one the program draws to) and one of the copies.
void WindowCopies::copy(SlaveContext& ctx, GLuint copy_fb, bool depth, bool back) {
    const GlApi& gl = core_.api();
    effects::StateGuard guard(gl);
    const GLenum window = ctx.double_buffered ? GL_BACK : GL_FRONT;
    gl.glBindFramebuffer(GL_READ_FRAMEBUFFER, back ? copy_fb : 0);
    gl.glBindFramebuffer(GL_DRAW_FRAMEBUFFER, back ? 0 : copy_fb);
    // The window's own draw or read buffer is the program's state: set for the blit, then restored.
    GLint program_buffer = 0;
    gl.glGetIntegerv(back ? GL_DRAW_BUFFER : GL_READ_BUFFER, &program_buffer);
    if (back) gl.glDrawBuffer(window);
    else gl.glReadBuffer(window);
    gl.glBlitFramebuffer(0, 0, ctx.width, ctx.height, 0, 0, ctx.width, ctx.height,
                         depth ? GL_DEPTH_BUFFER_BIT | GL_STENCIL_BUFFER_BIT : GL_COLOR_BUFFER_BIT, GL_NEAREST);
    if (back) gl.glDrawBuffer(GLenum(program_buffer));
    else gl.glReadBuffer(GLenum(program_buffer));
}

void WindowCopies::keep_depth(SlaveContext& ctx) {
    if (depth_kept_) return;  // (the first is the scene's: what came after is over it)
    size(ctx);
    copy(ctx, depth_fb_, true);
    depth_kept_ = true;
}

GLuint WindowCopies::window_copy(SlaveContext& ctx, bool depth, ContextScene& scene, const ContextScene& shown) {
    if (depth && depth_kept_) return depth_texture_;
    if (depth && scene.facts.scene_framebuffer) {
        if (depth_copied_) return scene_depth_;
        const GLuint copy = scene_depth_copy(ctx, scene, shown);
        depth_copied_ = true;
        return copy;
    }
    size(ctx);
    bool& done = depth ? depth_copied_ : color_copied_;
    if (!done) {
        copy(ctx, depth ? depth_fb_ : color_fb_, depth);
        done = true;
    }
    return depth ? depth_texture_ : color_texture_;
}

void WindowCopies::keep_scene_depth(ContextScene& scene) {
    const GlApi& gl = core_.api();
    effects::StateGuard guard(gl);
    gl.glBindFramebuffer(GL_READ_FRAMEBUFFER, scene.facts.scene_framebuffer);
    const GLenum format = depth_format(gl, GL_READ_FRAMEBUFFER);
    if (!format) {
        scene.facts.scene_depth_kept = false;
        scene.facts.overlay_texture = 0;
        return;
    }
    // The depth attachment's own size: all that a copy or a loan may read of it. (Not the window's:
    // the context that draws Blender's viewport presents to a hidden window of a few pixels. A
    // blit that reads beyond its source's edge is no copy on llvmpipe either: it scales, and moves
    // depths by a step.) The program allocated as much already.
    int SW = 1, SH = 1;
    if (!depth_size(gl, GL_READ_FRAMEBUFFER, SW, SH)) {
        scene.facts.scene_depth_kept = false;
        scene.facts.overlay_texture = 0;
        return;
    }
    if (format != kept_scene_depth_format_ || SW != kept_scene_depth_size_[0] || SH != kept_scene_depth_size_[1]) {
        if (kept_scene_depth_) {
            gl.glDeleteTextures(1, &kept_scene_depth_);
            gl.glDeleteFramebuffers(1, &kept_scene_depth_fb_);
        }
        const bool packed = format == GL_DEPTH24_STENCIL8 || format == GL_DEPTH32F_STENCIL8;
        kept_scene_depth_ = effects::make_texture(gl, format, SW, SH);
        kept_scene_depth_fb_ = effects::make_framebuffer(gl, 0, kept_scene_depth_,
                                                         packed ? GL_DEPTH_STENCIL_ATTACHMENT : GL_DEPTH_ATTACHMENT);
        kept_scene_depth_format_ = format;
        kept_scene_depth_size_[0] = SW, kept_scene_depth_size_[1] = SH;
    }
    gl.glBindFramebuffer(GL_READ_FRAMEBUFFER, scene.facts.scene_framebuffer);
    gl.glBindFramebuffer(GL_DRAW_FRAMEBUFFER, kept_scene_depth_fb_);
    gl.glBlitFramebuffer(0, 0, SW, SH, 0, 0, SW, SH, GL_DEPTH_BUFFER_BIT, GL_NEAREST);
    // A context that lends its scene lends this depth (the borrower attaches it as it is).
    scene.loan.scene_depth_type = GL_TEXTURE;
    scene.loan.scene_depth_name = kept_scene_depth_;
}

GLuint WindowCopies::scene_depth_copy(SlaveContext& ctx, ContextScene& scene, const ContextScene& shown) {
    const GlApi& gl = core_.api();
    effects::StateGuard guard(gl);
    // (the scene's own target, or the copy of its depth made before an overlay engine drew into it)
    const GLuint depth_source = scene.facts.scene_depth_kept ? kept_scene_depth_fb_ : scene.facts.scene_framebuffer;
    gl.glBindFramebuffer(GL_READ_FRAMEBUFFER, depth_source);
    const GLenum format = depth_format(gl, GL_READ_FRAMEBUFFER);
    if (!format) {  // its depth went away since: the window's
        scene.facts.scene_framebuffer = 0;
        return window_copy(ctx, true, scene, shown);
    }
    // A scene drawn at another size than the window's and shown stretched over it, or a borrowed
    // one placed in part of the window (on a rotated tile: over all of it), is copied at its own
    // size, and stretched by the interpolating draw below (a nearest blit would make steps of its
    // depth, and surfaces of steps have no normal; a multisampled depth cannot be scaled at all).
    int scene_size[2];
    const glm::dvec4 source = scene_texels_on_tile(ctx, scene, shown, scene_size);
    const int SW = scene_size[0], SH = scene_size[1];
    const int sizes[4] = {SW, SH, ctx.width, ctx.height};
    if (format != scene_depth_format_ || !std::equal(sizes, sizes + 4, scene_depth_sizes_)) {
        if (scene_depth_full_) {
            const GLuint textures[] = {scene_depth_full_, scene_depth_}, fbs[] = {scene_depth_full_fb_, scene_depth_fb_};
            gl.glDeleteTextures(2, textures);
            gl.glDeleteFramebuffers(2, fbs);
        }
        const bool packed = format == GL_DEPTH24_STENCIL8 || format == GL_DEPTH32F_STENCIL8;
        scene_depth_full_ = effects::make_texture(gl, format, SW, SH, /*linear=*/true);
        scene_depth_full_fb_ = effects::make_framebuffer(gl, 0, scene_depth_full_,
                                                         packed ? GL_DEPTH_STENCIL_ATTACHMENT : GL_DEPTH_ATTACHMENT);
        scene_depth_ = effects::make_texture(gl, GL_DEPTH_COMPONENT32F, ctx.width, ctx.height);
        scene_depth_fb_ = effects::make_framebuffer(gl, 0, scene_depth_, GL_DEPTH_ATTACHMENT);
        scene_depth_format_ = format;
        std::copy(sizes, sizes + 4, scene_depth_sizes_);
    }
    // Resolved at the program's size (a multisampled source may not be scaled; a depth blit
    // needs the same format on both sides), then this tile's rectangle of the program's window
    // (the canvas stretches it) drawn over the tile's size.
    gl.glBindFramebuffer(GL_READ_FRAMEBUFFER, depth_source);
    gl.glBindFramebuffer(GL_DRAW_FRAMEBUFFER, scene_depth_full_fb_);
    gl.glBlitFramebuffer(0, 0, SW, SH, 0, 0, SW, SH, GL_DEPTH_BUFFER_BIT, GL_NEAREST);
    if (!scene_depth_program_) {
        scene_depth_program_ = effects::build_program(gl, "fullscreen.vert", "scene_depth.frag");
        gl.glGenVertexArrays(1, &scene_depth_vao_);
    }
    begin_depth_draw(gl, scene_depth_fb_, ctx.width, ctx.height, scene_depth_program_, scene_depth_full_);
    gl.glUniform1i(effects::uniform(gl, scene_depth_program_, "scene_depth"), 0);
    gl.glUniform4f(effects::uniform(gl, scene_depth_program_, "source_rect"), GLfloat(source.x), GLfloat(source.y),
                   GLfloat(source.z), GLfloat(source.w));
    effects::draw_fullscreen(gl, scene_depth_vao_);
    return scene_depth_;
}

glm::dvec4 WindowCopies::tile_source(const SlaveContext& ctx, int SW, int SH) const {
    const int W = std::max(1, ctx.master_width), H = std::max(1, ctx.master_height);
    const TileMapping& t = core_.options().tile;
    glm::dvec4 source(0, 0, W, H);
    if (t.enabled && !core_.options().view.enabled)
        source = {t.x / t.sx(W), t.y / t.sy(H), (t.x + t.width) / t.sx(W), (t.y + t.height) / t.sy(H)};
    return source * glm::dvec4(double(SW) / W, double(SH) / H, double(SW) / W, double(SH) / H);  // in the copy's texels
}

void WindowCopies::keep_scene_target(const SlaveContext& ctx, const ContextScene& scene, bool final) {
    const GlApi& gl = core_.api();
    effects::StateGuard guard(gl);
    int SW = 1, SH = 1;
    scene_target_size(ctx, scene, SW, SH);
    if (SW != scene_target_size_[0] || SH != scene_target_size_[1]) {
        if (scene_target_before) {
            const GLuint textures[] = {scene_target_before, scene_target_final};
            gl.glDeleteTextures(2, textures);
            gl.glDeleteFramebuffers(2, scene_target_fb_);
        }
        scene_target_before = effects::make_texture(gl, GL_RGBA8, SW, SH);
        scene_target_final = effects::make_texture(gl, GL_RGBA8, SW, SH);
        scene_target_fb_[0] = effects::make_framebuffer(gl, scene_target_before, 0);
        scene_target_fb_[1] = effects::make_framebuffer(gl, scene_target_final, 0);
        scene_target_size_[0] = SW, scene_target_size_[1] = SH;
    }
    // (a multisampled target is resolved by the blit, which keeps the size)
    gl.glBindFramebuffer(GL_READ_FRAMEBUFFER, scene.facts.scene_framebuffer);
    gl.glBindFramebuffer(GL_DRAW_FRAMEBUFFER, scene_target_fb_[final ? 1 : 0]);
    gl.glBlitFramebuffer(0, 0, SW, SH, 0, 0, SW, SH, GL_COLOR_BUFFER_BIT, GL_NEAREST);
}

glm::dvec4 WindowCopies::scene_texels_on_tile(const SlaveContext& ctx, const ContextScene& scene,
                                               const ContextScene& shown, int size[2]) const {
    int SW = 1, SH = 1;
    scene_target_size(ctx, scene, SW, SH);
    const bool placed = scene.loan.borrowed_from != 0;
    if (placed) SW = std::max(1, shown.loan.scene_size[0]), SH = std::max(1, shown.loan.scene_size[1]);
    size[0] = SW, size[1] = SH;
    if (!placed) {
        glm::dvec4 texels = tile_source(ctx, SW, SH);
        if (scene.facts.shown_mirrored) texels.y = SH - texels.y, texels.w = SH - texels.w;  // (shown upside down)
        if (scene.facts.shown_mirrored_columns) texels.x = SW - texels.x, texels.z = SW - texels.z;
        return texels;
    }
    // the tile's rectangle of the window, in the scene's texels (beyond them: outside the scene)
    const int W = std::max(1, ctx.master_width), H = std::max(1, ctx.master_height);
    const int32_t* p = scene.loan.placement;
    const glm::dvec4 window = tile_source(ctx, W, H);
    const double sx = SW / std::max(1.0, double(p[2]) - p[0]), sy = SH / std::max(1.0, double(p[3]) - p[1]);
    return {(window.x - p[0]) * sx, (window.y - p[1]) * sy, (window.z - p[0]) * sx, (window.w - p[1]) * sy};
}

GLuint WindowCopies::pass_depth(SlaveContext& ctx, GLuint program_depth, const DepthConvention& c,
                                const glm::dmat4& pass_clip_from_program_clip) {
    if (pass_depth_done_ && pass_depth_size_[0] == ctx.width && pass_depth_size_[1] == ctx.height) return pass_depth_;
    const GlApi& gl = core_.api();
    effects::StateGuard guard(gl);
    if (pass_depth_size_[0] != ctx.width || pass_depth_size_[1] != ctx.height) {
        if (pass_depth_) {
            gl.glDeleteTextures(1, &pass_depth_);
            gl.glDeleteFramebuffers(1, &pass_depth_fb_);
        }
        pass_depth_ = effects::make_texture(gl, GL_DEPTH_COMPONENT32F, ctx.width, ctx.height);
        pass_depth_fb_ = effects::make_framebuffer(gl, 0, pass_depth_, GL_DEPTH_ATTACHMENT);
        pass_depth_size_[0] = ctx.width, pass_depth_size_[1] = ctx.height;
    }
    if (!pass_depth_program_) {
        pass_depth_program_ = effects::build_program(gl, "fullscreen.vert", "depth_convention.frag");
        if (!scene_depth_vao_) gl.glGenVertexArrays(1, &scene_depth_vao_);
    }
    const GLuint p = pass_depth_program_;
    begin_depth_draw(gl, pass_depth_fb_, ctx.width, ctx.height, p, program_depth);
    gl.glUniform1i(effects::uniform(gl, p, "program_depth"), 0);
    const glm::mat4 m(pass_clip_from_program_clip);
    gl.glUniformMatrix4fv(effects::uniform(gl, p, "pass_clip_from_program_clip"), 1, GL_FALSE, glm::value_ptr(m));
    gl.glUniform2f(effects::uniform(gl, p, "tile_size"), GLfloat(ctx.width), GLfloat(ctx.height));
    gl.glUniform2f(effects::uniform(gl, p, "depth_range"), GLfloat(c.program.range_near), GLfloat(c.program.range_far));
    gl.glUniform1i(effects::uniform(gl, p, "zero_to_one"), c.program.zero_to_one ? 1 : 0);
    gl.glUniform1f(effects::uniform(gl, p, "clear_depth"), GLfloat(c.program.clear_depth));
    effects::draw_fullscreen(gl, scene_depth_vao_);
    pass_depth_done_ = true;
    return pass_depth_;
}

}  // namespace glcast::slave
