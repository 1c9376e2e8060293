// Saving and restoring the program's GL state around what glcast does inside its frame: the
// injected passes, the redraw of the main view, a tile's projection correction, reading the
// window back. One guard, with the state groups each user asks for; the constructor saves them
// (and sets the defaults some groups promise), the destructor puts them back in an order GL
// accepts (buffers after the framebuffer that owns them).
#pragma once

#include <cstdint>
#include <utility>
#include <vector>

#include "glcast_gl_api.h"

namespace glcast {

enum GlStateGroup : uint32_t {
    // Draw and read framebuffer bindings and their draw and read buffers.
    kGuardFramebuffers = 1u << 0,
    // The window as read framebuffer: binds framebuffer 0 and saves the window's read buffer.
    kGuardWindowRead = 1u << 1,
    kGuardViewport = 1u << 2,         // viewport and scissor box
    // Enables a pass may change, blend/depth/stencil/color masks and functions, polygon mode and
    // offset, point size, line width, clear values; scissor, stencil, culling and the like off.
    kGuardRaster = 1u << 3,
    kGuardProgram = 1u << 4,          // current program
    kGuardVertexArray = 1u << 5,      // vertex-array object and GL_ARRAY_BUFFER
    // Pack and unpack buffers and every pixel-store parameter, set to GL's defaults.
    kGuardPixelStore = 1u << 6,
    // The same for packing only (reading pixels back).
    kGuardPixelPack = 1u << 7,
    // Active texture, 2D texture and sampler of units 0..7; in compatibility contexts the
    // fixed-function state that still acts on a shader's output or sampling is turned off
    // (texture-target enables of units 0..7, alpha test, clip planes, polygon and line stipple).
    kGuardTextures = 1u << 8,
    kGuardMatrixMode = 1u << 9,       // GL_MATRIX_MODE (compatibility contexts)
    // Depth and top of the modelview, projection and texture stacks (compatibility contexts).
    kGuardMatrixStacks = 1u << 10,
    // glPushAttrib(GL_ALL_ATTRIB_BITS) and glPushClientAttrib(GL_CLIENT_ALL_ATTRIB_BITS).
    kGuardAttribStacks = 1u << 11,
    // What an injected pass may change.
    kGuardPass = kGuardFramebuffers | kGuardViewport | kGuardRaster | kGuardProgram | kGuardVertexArray |
                 kGuardPixelStore | kGuardTextures,
};

// The current context has the fixed-function pipeline (a compatibility profile or GL before
// 3.2): matrix stacks, attribute stacks, glBegin.
bool compatibility_profile(const GlApi& gl);

class GlStateGuard {
public:
    GlStateGuard(const GlApi& gl, uint32_t groups);
    ~GlStateGuard();
    GlStateGuard(const GlStateGuard&) = delete;
    GlStateGuard& operator=(const GlStateGuard&) = delete;

private:
    bool has(uint32_t g) const { return (groups_ & g) != 0; }
    // OpenGL ES 2 binds one framebuffer for drawing and reading (GL_FRAMEBUFFER)
    bool one_framebuffer() const { return es_ && es_ < 30; }
    void save_raster();
    void restore_raster();
    void save_textures();
    void restore_textures();

    const GlApi& gl_;
    uint32_t groups_;
    bool compatibility_ = false;
    int es_ = 0;                  // the context's OpenGL ES version times 10, 0 for desktop GL
    bool pixel_buffers_ = false;  // pixel pack and unpack buffer bindings exist
    // A framebuffer object's draw buffers, all of them (GL_DRAW_BUFFERi): restoring the first alone
    // would send the program's later draws into one attachment of several.
    static constexpr int kDrawBuffers = 8;
    GLint draw_fb_ = 0, read_fb_ = 0, draw_buffers_[kDrawBuffers] = {}, read_buffer_ = 0, viewport_[4] = {},
          scissor_[4] = {};
    int draw_buffer_count_ = 1;
    std::vector<std::pair<GLenum, GLboolean>> enables_;
    GLint blend_src_rgb_ = 0, blend_dst_rgb_ = 0, blend_src_a_ = 0, blend_dst_a_ = 0, blend_eq_rgb_ = 0,
          blend_eq_a_ = 0;
    GLfloat blend_color_[4] = {}, clear_color_[4] = {}, clear_depth_ = 1, polygon_offset_[2] = {}, point_size_ = 1,
            line_width_ = 1;
    GLboolean color_mask_[4] = {}, depth_mask_ = GL_TRUE;
    GLint depth_func_ = 0, stencil_mask_ = 0, polygon_mode_[2] = {}, cull_face_ = 0, front_face_ = 0;
    GLint program_ = 0, vao_ = 0, array_buffer_ = 0, pack_buffer_ = 0, unpack_buffer_ = 0, active_texture_ = 0;
    std::vector<std::pair<GLenum, GLint>> pixel_store_;
    GLint textures_[8] = {}, samplers_[8] = {};
    std::vector<std::pair<GLenum, GLboolean>> unit_enables_[8];
    GLint matrix_mode_ = 0;
    struct Stack {
        GLenum mode, depth_query, matrix_query;
        GLint depth = 0;
        GLdouble top[16] = {};
    };
    std::vector<Stack> stacks_;
};

}  // namespace glcast
