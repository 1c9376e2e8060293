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
    case GL_DEPTH_COMPONENT32: format = GL_DEPTH_COMPONENT, type = GL_UNSIGNED_INT; break;
    case GL_DEPTH24_STENCIL8: format = GL_DEPTH_STENCIL, type = GL_UNSIGNED_INT_24_8; break;
    case GL_DEPTH32F_STENCIL8: format = GL_DEPTH_STENCIL, type = GL_FLOAT_32_UNSIGNED_INT_24_8_REV; break;
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

}  // namespace glcast::slave::effects
