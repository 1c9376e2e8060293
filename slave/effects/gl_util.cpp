#include "slave/effects/gl_util.h"

#include <map>
#include <stdexcept>

namespace glcast::slave::effects {

// Generated from slave/effects/**/*.{vert,frag,glsl} (CMake: glcast_embed_shaders).
const std::map<std::string, std::string>& embedded_shaders();

const std::string& shader_source(const std::string& file_name) {
    const auto& all = embedded_shaders();
    auto it = all.find(file_name);
    if (it == all.end()) throw std::runtime_error("no embedded shader " + file_name);
    return it->second;
}

namespace {

GLuint compile(const GlApi& gl, GLenum type, const std::string& file, const std::string& defines) {
    std::string text = shader_source(file);
    std::string version = "#version 330 core\n";
    if (text.rfind("#version", 0) == 0) {
        const size_t eol = text.find('\n');
        version = text.substr(0, eol + 1);
        text = text.substr(eol + 1);
    }
    // Keep line numbers of the driver's log equal to the file's.
    const std::string source = version + defines + "#line 2\n" + text;
    const char* p = source.c_str();
    GLuint shader = gl.glCreateShader(type);
    gl.glShaderSource(shader, 1, &p, nullptr);
    gl.glCompileShader(shader);
    GLint ok = 0;
    gl.glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
    if (!ok) {
        char log[4096] = {};
        gl.glGetShaderInfoLog(shader, sizeof log, nullptr, log);
        gl.glDeleteShader(shader);
        throw std::runtime_error("slave/effects/" + file + ": " + log);
    }
    return shader;
}

}  // namespace

GLuint build_program(const GlApi& gl, const std::string& vertex_file, const std::string& fragment_file,
                     const std::string& defines) {
    GLuint vs = compile(gl, GL_VERTEX_SHADER, vertex_file, defines);
    GLuint fs = 0;
    try {
        fs = compile(gl, GL_FRAGMENT_SHADER, fragment_file, defines);
    } catch (...) {
        gl.glDeleteShader(vs);
        throw;
    }
    GLuint program = gl.glCreateProgram();
    gl.glAttachShader(program, vs);
    gl.glAttachShader(program, fs);
    gl.glBindFragDataLocation(program, 0, "out_color");
    gl.glLinkProgram(program);
    gl.glDeleteShader(vs);
    gl.glDeleteShader(fs);
    GLint ok = 0;
    gl.glGetProgramiv(program, GL_LINK_STATUS, &ok);
    if (!ok) {
        char log[4096] = {};
        gl.glGetProgramInfoLog(program, sizeof log, nullptr, log);
        gl.glDeleteProgram(program);
        throw std::runtime_error("linking " + vertex_file + " + " + fragment_file + ": " + log);
    }
    return program;
}

GLint uniform(const GlApi& gl, GLuint program, const char* name) { return gl.glGetUniformLocation(program, name); }

GLuint make_texture(const GlApi& gl, GLenum internal_format, int width, int height, bool linear, int mip_levels) {
    GLenum format = GL_RGBA, type = GL_UNSIGNED_BYTE;
    switch (internal_format) {
    case GL_DEPTH_COMPONENT24: case GL_DEPTH_COMPONENT32F: case GL_DEPTH_COMPONENT16:
        format = GL_DEPTH_COMPONENT, type = GL_FLOAT; break;
    case GL_DEPTH24_STENCIL8: format = GL_DEPTH_STENCIL, type = GL_UNSIGNED_INT_24_8; break;
    case GL_R32F: case GL_R16F: format = GL_RED, type = GL_FLOAT; break;
    case GL_R8: format = GL_RED; break;
    case GL_RG32F: case GL_RG16F: format = GL_RG, type = GL_FLOAT; break;
    case GL_RGBA32F: case GL_RGBA16F: type = GL_FLOAT; break;
    default: break;
    }
    GLuint t = 0;
    gl.glGenTextures(1, &t);
    gl.glBindTexture(GL_TEXTURE_2D, t);
    int w = width, h = height;
    for (int level = 0; level < mip_levels; ++level) {
        gl.glTexImage2D(GL_TEXTURE_2D, level, GLint(internal_format), w, h, 0, format, type, nullptr);
        w = w > 1 ? w / 2 : 1;
        h = h > 1 ? h / 2 : 1;
    }
    const bool mips = mip_levels > 1;
    gl.glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAX_LEVEL, mip_levels - 1);
    gl.glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER,
                       linear ? (mips ? GL_LINEAR_MIPMAP_NEAREST : GL_LINEAR) : (mips ? GL_NEAREST_MIPMAP_NEAREST : GL_NEAREST));
    gl.glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, linear ? GL_LINEAR : GL_NEAREST);
    gl.glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    gl.glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    return t;
}

GLuint make_framebuffer(const GlApi& gl, GLuint color, GLuint depth, GLenum depth_attachment) {
    GLuint fb = 0;
    gl.glGenFramebuffers(1, &fb);
    gl.glBindFramebuffer(GL_FRAMEBUFFER, fb);
    if (color) gl.glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, color, 0);
    if (depth) gl.glFramebufferTexture2D(GL_FRAMEBUFFER, depth_attachment, GL_TEXTURE_2D, depth, 0);
    const GLenum none = GL_NONE, attachment0 = GL_COLOR_ATTACHMENT0;
    gl.glDrawBuffers(1, color ? &attachment0 : &none);
    gl.glReadBuffer(color ? GL_COLOR_ATTACHMENT0 : GL_NONE);
    const GLenum status = gl.glCheckFramebufferStatus(GL_FRAMEBUFFER);
    if (status != GL_FRAMEBUFFER_COMPLETE)
        throw std::runtime_error("effects framebuffer incomplete (status 0x" + std::to_string(status) + ")");
    return fb;
}

void draw_fullscreen(const GlApi& gl, GLuint empty_vao) {
    gl.glBindVertexArray(empty_vao);
    gl.glDrawArrays(GL_TRIANGLES, 0, 3);
}

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
}  // namespace

StateGuard::StateGuard(const GlApi& gl) : gl_(gl) {
    gl.glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &draw_fb_);
    gl.glGetIntegerv(GL_READ_FRAMEBUFFER_BINDING, &read_fb_);
    gl.glGetIntegerv(GL_DRAW_BUFFER, &draw_buffer_);
    gl.glGetIntegerv(GL_READ_BUFFER, &read_buffer_);
    gl.glGetIntegerv(GL_VIEWPORT, viewport_);
    gl.glGetIntegerv(GL_SCISSOR_BOX, scissor_);
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
    gl.glGetIntegerv(GL_CURRENT_PROGRAM, &program_);
    gl.glGetIntegerv(GL_VERTEX_ARRAY_BINDING, &vao_);
    gl.glGetIntegerv(GL_ARRAY_BUFFER_BINDING, &array_buffer_);
    gl.glGetIntegerv(GL_PIXEL_PACK_BUFFER_BINDING, &pack_buffer_);
    gl.glGetIntegerv(GL_PIXEL_UNPACK_BUFFER_BINDING, &unpack_buffer_);
    for (GLenum p : kPixelStore) {
        GLint v = 0;
        gl.glGetIntegerv(p, &v);
        pixel_store_.emplace_back(p, v);
    }
    GLint profile = 0;
    gl.glGetIntegerv(GL_CONTEXT_PROFILE_MASK, &profile);
    compatibility_ = gl.has(OP_glPushAttrib) && !(profile & GL_CONTEXT_CORE_PROFILE_BIT);
    if (compatibility_)
        for (GLenum e : kCompatEnables) enables_.emplace_back(e, gl.glIsEnabled(e)), gl.glDisable(e);
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
    // Defaults every pass may rely on.
    gl.glBindBuffer(GL_PIXEL_PACK_BUFFER, 0);
    gl.glBindBuffer(GL_PIXEL_UNPACK_BUFFER, 0);
    for (GLenum p : kPixelStore) {
        const bool alignment = p == GL_PACK_ALIGNMENT || p == GL_UNPACK_ALIGNMENT;
        gl.glPixelStorei(p, alignment ? 4 : 0);
    }
    for (int i = 0; i < 8; ++i) {
        if (!samplers_[i]) continue;
        gl.glBindSampler(GLuint(i), 0);
    }
    gl.glPolygonMode(GL_FRONT_AND_BACK, GL_FILL);
    gl.glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    gl.glDisable(GL_SCISSOR_TEST);
    gl.glDisable(GL_STENCIL_TEST);
    gl.glDisable(GL_CULL_FACE);
    gl.glDisable(GL_COLOR_LOGIC_OP);
    gl.glDisable(GL_RASTERIZER_DISCARD);
    gl.glDisable(GL_FRAMEBUFFER_SRGB);
    gl.glDisable(GL_SAMPLE_ALPHA_TO_COVERAGE);
    gl.glDisable(GL_POLYGON_OFFSET_FILL);
    gl.glDisable(GL_CLIP_DISTANCE0);
    gl.glDisable(GL_DEPTH_CLAMP);
}

StateGuard::~StateGuard() {
    const GlApi& gl = gl_;
    for (int i = 0; i < 8; ++i) {
        gl.glActiveTexture(GLenum(GL_TEXTURE0 + i));
        gl.glBindTexture(GL_TEXTURE_2D, GLuint(textures_[i]));
        gl.glBindSampler(GLuint(i), GLuint(samplers_[i]));
        for (auto [e, on] : unit_enables_[i]) on ? gl.glEnable(e) : gl.glDisable(e);
    }
    gl.glActiveTexture(GLenum(active_texture_));
    for (auto [p, v] : pixel_store_) gl.glPixelStorei(p, v);
    gl.glBindBuffer(GL_PIXEL_PACK_BUFFER, GLuint(pack_buffer_));
    gl.glBindBuffer(GL_PIXEL_UNPACK_BUFFER, GLuint(unpack_buffer_));
    gl.glBindBuffer(GL_ARRAY_BUFFER, GLuint(array_buffer_));
    gl.glBindVertexArray(GLuint(vao_));
    gl.glUseProgram(GLuint(program_));
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
    gl.glScissor(scissor_[0], scissor_[1], scissor_[2], scissor_[3]);
    gl.glViewport(viewport_[0], viewport_[1], viewport_[2], viewport_[3]);
    gl.glBindFramebuffer(GL_DRAW_FRAMEBUFFER, GLuint(draw_fb_));
    gl.glBindFramebuffer(GL_READ_FRAMEBUFFER, GLuint(read_fb_));
    gl.glDrawBuffer(GLenum(draw_buffer_));
    gl.glReadBuffer(GLenum(read_buffer_));
}

}  // namespace glcast::slave::effects
