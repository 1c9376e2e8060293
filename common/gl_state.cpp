#include "common/gl_state.h"

#include "common/gles.h"

#include <algorithm>

namespace glcast {
namespace {

const GLenum kGuardedEnables[] = {GL_DEPTH_TEST, GL_BLEND, GL_CULL_FACE, GL_SCISSOR_TEST, GL_STENCIL_TEST,
                                  GL_POLYGON_OFFSET_FILL, GL_FRAMEBUFFER_SRGB, GL_PROGRAM_POINT_SIZE,
                                  GL_DEPTH_CLAMP, GL_SAMPLE_ALPHA_TO_COVERAGE, GL_COLOR_LOGIC_OP,
                                  GL_RASTERIZER_DISCARD, GL_PRIMITIVE_RESTART, GL_LINE_SMOOTH, GL_POLYGON_SMOOTH,
                                  GL_MULTISAMPLE, GL_CLIP_DISTANCE0, GL_DITHER};
const GLenum kPixelStore[] = {GL_PACK_ALIGNMENT, GL_PACK_ROW_LENGTH, GL_PACK_SKIP_ROWS, GL_PACK_SKIP_PIXELS,
                              GL_PACK_SWAP_BYTES, GL_PACK_LSB_FIRST, GL_PACK_IMAGE_HEIGHT, GL_PACK_SKIP_IMAGES,
                              GL_UNPACK_ALIGNMENT, GL_UNPACK_ROW_LENGTH, GL_UNPACK_SKIP_ROWS,
                              GL_UNPACK_SKIP_PIXELS, GL_UNPACK_SWAP_BYTES, GL_UNPACK_LSB_FIRST,
                              GL_UNPACK_IMAGE_HEIGHT, GL_UNPACK_SKIP_IMAGES};
const GLenum kCompatEnables[] = {GL_ALPHA_TEST, GL_POLYGON_STIPPLE, GL_LINE_STIPPLE, GL_CLIP_PLANE0, GL_CLIP_PLANE1,
                                 GL_CLIP_PLANE2, GL_CLIP_PLANE3, GL_CLIP_PLANE4, GL_CLIP_PLANE5};
const GLenum kTextureTargetEnables[] = {GL_TEXTURE_1D, GL_TEXTURE_2D, GL_TEXTURE_3D, GL_TEXTURE_CUBE_MAP,
                                        GL_TEXTURE_RECTANGLE};

bool is_pack(GLenum p) {
    return p == GL_PACK_ALIGNMENT || p == GL_PACK_ROW_LENGTH || p == GL_PACK_SKIP_ROWS || p == GL_PACK_SKIP_PIXELS ||
           p == GL_PACK_SWAP_BYTES || p == GL_PACK_LSB_FIRST || p == GL_PACK_IMAGE_HEIGHT || p == GL_PACK_SKIP_IMAGES;
}

}  // namespace

bool compatibility_profile(const GlApi& gl) {
    GLint profile = 0;
    gl.glGetIntegerv(GL_CONTEXT_PROFILE_MASK, &profile);
    return gl.has(OP_glPushAttrib) && !(profile & GL_CONTEXT_CORE_PROFILE_BIT);
}

GlStateGuard::GlStateGuard(const GlApi& gl, uint32_t groups) : gl_(gl), groups_(groups) {
    if (has(kGuardMatrixMode)) gl.glGetIntegerv(GL_MATRIX_MODE, &matrix_mode_);
    if (has(kGuardFramebuffers)) {
        gl.glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &draw_fb_);
        gl.glGetIntegerv(GL_READ_FRAMEBUFFER_BINDING, &read_fb_);
        GLint most = 1;
        if (draw_fb_ && gl.has(OP_glDrawBuffers)) gl.glGetIntegerv(GL_MAX_DRAW_BUFFERS, &most);
        draw_buffer_count_ = std::clamp(int(most), 1, kDrawBuffers);
        for (int i = 0; i < draw_buffer_count_; ++i) gl.glGetIntegerv(GLenum(GL_DRAW_BUFFER0 + i), &draw_buffers_[i]);
        gl.glGetIntegerv(GL_READ_BUFFER, &read_buffer_);
    }
    // An OpenGL ES context is asked only what its version has (common/gles.h).
    if (has(kGuardWindowRead | kGuardPixelStore | kGuardPixelPack) && gl.has(OP_glGetString))
        es_ = gles_version(reinterpret_cast<const char*>(gl.glGetString(GL_VERSION)));
    if (has(kGuardWindowRead)) {  // GL 1.x has no framebuffer objects: the window is all there is
        if (gl.has(OP_glBindFramebuffer)) {
            gl.glGetIntegerv(one_framebuffer() ? GL_FRAMEBUFFER_BINDING : GL_READ_FRAMEBUFFER_BINDING, &read_fb_);
            gl.glBindFramebuffer(one_framebuffer() ? GL_FRAMEBUFFER : GL_READ_FRAMEBUFFER, 0);
        }
        if (!gles_lacks(GL_READ_BUFFER, es_)) gl.glGetIntegerv(GL_READ_BUFFER, &read_buffer_);  // the window's own
    }
    if (has(kGuardViewport)) {
        gl.glGetIntegerv(GL_VIEWPORT, viewport_);
        gl.glGetIntegerv(GL_SCISSOR_BOX, scissor_);
    }
    if (has(kGuardRaster | kGuardTextures)) compatibility_ = compatibility_profile(gl);
    if (has(kGuardRaster)) save_raster();
    if (has(kGuardProgram)) gl.glGetIntegerv(GL_CURRENT_PROGRAM, &program_);
    if (has(kGuardVertexArray)) {
        gl.glGetIntegerv(GL_VERTEX_ARRAY_BINDING, &vao_);
        gl.glGetIntegerv(GL_ARRAY_BUFFER_BINDING, &array_buffer_);
    }
    if (has(kGuardPixelStore | kGuardPixelPack)) {
        const bool unpack = has(kGuardPixelStore);
        pixel_buffers_ = gl.has(OP_glBindBuffer) && !gles_lacks(GL_PIXEL_PACK_BUFFER_BINDING, es_);
        const bool buffers = pixel_buffers_;
        if (buffers) gl.glGetIntegerv(GL_PIXEL_PACK_BUFFER_BINDING, &pack_buffer_);
        if (buffers && unpack) gl.glGetIntegerv(GL_PIXEL_UNPACK_BUFFER_BINDING, &unpack_buffer_);
        for (GLenum p : kPixelStore) {
            if ((!unpack && !is_pack(p)) || gles_lacks(p, es_)) continue;
            GLint v = 0;
            gl.glGetIntegerv(p, &v);
            pixel_store_.emplace_back(p, v);
        }
        // GL's defaults, which the code inside relies on
        if (buffers && pack_buffer_) gl.glBindBuffer(GL_PIXEL_PACK_BUFFER, 0);
        if (buffers && unpack_buffer_) gl.glBindBuffer(GL_PIXEL_UNPACK_BUFFER, 0);
        for (auto [p, v] : pixel_store_) {
            const bool alignment = p == GL_PACK_ALIGNMENT || p == GL_UNPACK_ALIGNMENT;
            gl.glPixelStorei(p, alignment ? 4 : 0);
        }
    }
    if (has(kGuardTextures)) save_textures();
    if (has(kGuardMatrixStacks)) {
        stacks_ = {{GL_MODELVIEW, GL_MODELVIEW_STACK_DEPTH, GL_MODELVIEW_MATRIX},
                   {GL_PROJECTION, GL_PROJECTION_STACK_DEPTH, GL_PROJECTION_MATRIX},
                   {GL_TEXTURE, GL_TEXTURE_STACK_DEPTH, GL_TEXTURE_MATRIX}};
        for (Stack& s : stacks_) {
            gl.glGetIntegerv(s.depth_query, &s.depth);
            gl.glGetDoublev(s.matrix_query, s.top);
        }
    }
    if (has(kGuardAttribStacks)) {
        gl.glPushAttrib(GL_ALL_ATTRIB_BITS);
        gl.glPushClientAttrib(GL_CLIENT_ALL_ATTRIB_BITS);
    }
}

void GlStateGuard::save_raster() {
    const GlApi& gl = gl_;
    for (GLenum e : kGuardedEnables) enables_.emplace_back(e, gl.glIsEnabled(e));
    gl.glGetIntegerv(GL_BLEND_SRC_RGB, &blend_src_rgb_);
    gl.glGetIntegerv(GL_BLEND_DST_RGB, &blend_dst_rgb_);
    gl.glGetIntegerv(GL_BLEND_SRC_ALPHA, &blend_src_a_);
    gl.glGetIntegerv(GL_BLEND_DST_ALPHA, &blend_dst_a_);
    gl.glGetIntegerv(GL_BLEND_EQUATION_RGB, &blend_eq_rgb_);
    gl.glGetIntegerv(GL_BLEND_EQUATION_ALPHA, &blend_eq_a_);
    gl.glGetFloatv(GL_BLEND_COLOR, blend_color_);
    gl.glGetFloatv(GL_COLOR_CLEAR_VALUE, clear_color_);
    gl.glGetFloatv(GL_DEPTH_CLEAR_VALUE, &clear_depth_);
    gl.glGetFloatv(GL_POLYGON_OFFSET_FACTOR, &polygon_offset_[0]);
    gl.glGetFloatv(GL_POLYGON_OFFSET_UNITS, &polygon_offset_[1]);
    gl.glGetFloatv(GL_POINT_SIZE, &point_size_);
    gl.glGetFloatv(GL_LINE_WIDTH, &line_width_);
    gl.glGetBooleanv(GL_COLOR_WRITEMASK, color_mask_);
    gl.glGetBooleanv(GL_DEPTH_WRITEMASK, &depth_mask_);
    gl.glGetIntegerv(GL_DEPTH_FUNC, &depth_func_);
    gl.glGetIntegerv(GL_STENCIL_WRITEMASK, &stencil_mask_);
    gl.glGetIntegerv(GL_POLYGON_MODE, polygon_mode_);
    gl.glGetIntegerv(GL_CULL_FACE_MODE, &cull_face_);
    gl.glGetIntegerv(GL_FRONT_FACE, &front_face_);
    if (compatibility_)
        for (GLenum e : kCompatEnables) enables_.emplace_back(e, gl.glIsEnabled(e)), gl.glDisable(e);
    gl.glPolygonMode(GL_FRONT_AND_BACK, GL_FILL);
    gl.glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    for (GLenum e : {GL_SCISSOR_TEST, GL_STENCIL_TEST, GL_CULL_FACE, GL_COLOR_LOGIC_OP, GL_RASTERIZER_DISCARD,
                     GL_FRAMEBUFFER_SRGB, GL_SAMPLE_ALPHA_TO_COVERAGE, GL_POLYGON_OFFSET_FILL, GL_CLIP_DISTANCE0,
                     GL_DEPTH_CLAMP})
        gl.glDisable(e);
}

void GlStateGuard::save_textures() {
    const GlApi& gl = gl_;
    gl.glGetIntegerv(GL_ACTIVE_TEXTURE, &active_texture_);
    for (int i = 0; i < 8; ++i) {
        gl.glActiveTexture(GLenum(GL_TEXTURE0 + i));
        gl.glGetIntegerv(GL_TEXTURE_BINDING_2D, &textures_[i]);
        gl.glGetIntegerv(GL_SAMPLER_BINDING, &samplers_[i]);
        if (!compatibility_) continue;
        for (GLenum e : kTextureTargetEnables) {
            unit_enables_[i].emplace_back(e, gl.glIsEnabled(e));
            gl.glDisable(e);
        }
    }
    gl.glActiveTexture(GLenum(active_texture_));
    for (int i = 0; i < 8; ++i)
        if (samplers_[i]) gl.glBindSampler(GLuint(i), 0);
}

void GlStateGuard::restore_textures() {
    const GlApi& gl = gl_;
    for (int i = 0; i < 8; ++i) {
        gl.glActiveTexture(GLenum(GL_TEXTURE0 + i));
        gl.glBindTexture(GL_TEXTURE_2D, GLuint(textures_[i]));
        gl.glBindSampler(GLuint(i), GLuint(samplers_[i]));
        for (auto [e, on] : unit_enables_[i]) on ? gl.glEnable(e) : gl.glDisable(e);
    }
    gl.glActiveTexture(GLenum(active_texture_));
}

void GlStateGuard::restore_raster() {
    const GlApi& gl = gl_;
    if (compatibility_) {
        gl.glPolygonMode(GL_FRONT, GLenum(polygon_mode_[0]));
        gl.glPolygonMode(GL_BACK, GLenum(polygon_mode_[1]));
    } else {
        gl.glPolygonMode(GL_FRONT_AND_BACK, GLenum(polygon_mode_[0]));  // core has no separate faces
    }
    gl.glCullFace(GLenum(cull_face_));
    gl.glFrontFace(GLenum(front_face_));
    gl.glStencilMask(GLuint(stencil_mask_));
    gl.glDepthFunc(GLenum(depth_func_));
    gl.glDepthMask(depth_mask_);
    gl.glColorMask(color_mask_[0], color_mask_[1], color_mask_[2], color_mask_[3]);
    gl.glLineWidth(line_width_);
    gl.glPointSize(point_size_);
    gl.glPolygonOffset(polygon_offset_[0], polygon_offset_[1]);
    gl.glClearDepth(clear_depth_);
    gl.glClearColor(clear_color_[0], clear_color_[1], clear_color_[2], clear_color_[3]);
    gl.glBlendColor(blend_color_[0], blend_color_[1], blend_color_[2], blend_color_[3]);
    gl.glBlendEquationSeparate(GLenum(blend_eq_rgb_), GLenum(blend_eq_a_));
    gl.glBlendFuncSeparate(GLenum(blend_src_rgb_), GLenum(blend_dst_rgb_), GLenum(blend_src_a_), GLenum(blend_dst_a_));
    for (auto [e, on] : enables_) on ? gl.glEnable(e) : gl.glDisable(e);
}

GlStateGuard::~GlStateGuard() {
    const GlApi& gl = gl_;
    if (has(kGuardAttribStacks)) {
        gl.glPopClientAttrib();
        gl.glPopAttrib();
    }
    if (has(kGuardTextures)) restore_textures();
    if (has(kGuardPixelStore | kGuardPixelPack)) {
        for (auto [p, v] : pixel_store_) gl.glPixelStorei(p, v);
        if (pixel_buffers_) {
            gl.glBindBuffer(GL_PIXEL_PACK_BUFFER, GLuint(pack_buffer_));
            if (has(kGuardPixelStore)) gl.glBindBuffer(GL_PIXEL_UNPACK_BUFFER, GLuint(unpack_buffer_));
        }
    }
    if (has(kGuardVertexArray)) {
        if (!has(kGuardAttribStacks)) gl.glBindBuffer(GL_ARRAY_BUFFER, GLuint(array_buffer_));
        gl.glBindVertexArray(GLuint(vao_));
    }
    if (has(kGuardProgram)) gl.glUseProgram(GLuint(program_));
    if (has(kGuardRaster)) restore_raster();
    if (has(kGuardViewport)) {
        gl.glScissor(scissor_[0], scissor_[1], scissor_[2], scissor_[3]);
        gl.glViewport(viewport_[0], viewport_[1], viewport_[2], viewport_[3]);
    }
    if (has(kGuardFramebuffers)) {
        gl.glBindFramebuffer(GL_DRAW_FRAMEBUFFER, GLuint(draw_fb_));
        gl.glBindFramebuffer(GL_READ_FRAMEBUFFER, GLuint(read_fb_));
        if (draw_buffer_count_ > 1) {  // (a framebuffer object's; the window's buffer is one: GL_BACK)
            GLenum buffers[kDrawBuffers];
            for (int i = 0; i < draw_buffer_count_; ++i) buffers[i] = GLenum(draw_buffers_[i]);
            gl.glDrawBuffers(draw_buffer_count_, buffers);
        } else {
            gl.glDrawBuffer(GLenum(draw_buffers_[0]));
        }
        gl.glReadBuffer(GLenum(read_buffer_));
    }
    if (has(kGuardWindowRead)) {  // the window's read buffer while it is bound, then the program's
        if (!gles_lacks(GL_READ_BUFFER, es_)) gl.glReadBuffer(GLenum(read_buffer_));
        if (gl.has(OP_glBindFramebuffer))
            gl.glBindFramebuffer(one_framebuffer() ? GL_FRAMEBUFFER : GL_READ_FRAMEBUFFER, GLuint(read_fb_));
    }
    for (const Stack& s : stacks_) {
        gl.glMatrixMode(s.mode);
        GLint depth = 0;
        gl.glGetIntegerv(s.depth_query, &depth);
        for (; depth > s.depth; --depth) gl.glPopMatrix();
        for (; depth < s.depth; ++depth) gl.glPushMatrix();
        gl.glLoadMatrixd(s.top);
    }
    if (has(kGuardMatrixMode)) gl.glMatrixMode(GLenum(matrix_mode_));
}

}  // namespace glcast
