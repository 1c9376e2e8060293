#include "slave/effects/winter/winter_surface_buffers.h"

#include "slave/effects/gl_util.h"

namespace glcast::slave::effects {

SurfaceBuffers::SurfaceBuffers(const GlApi& gl) : gl_(gl) {
    // A core context has no fixed-function attributes to re-render; FrameView::redraw is
    // empty there anyway, and the depth reconstruction serves.
    if (compatibility_profile(gl)) geometry_program_ = build_program(gl, "winter_normals.vert", "winter_normals.frag");
    depth_program_ = build_program(gl, "fullscreen.vert", "winter_depth_normals.frag");
    gl.glGenVertexArrays(1, &empty_vao_);
}

SurfaceBuffers::~SurfaceBuffers() {
    if (geometry_program_) gl_.glDeleteProgram(geometry_program_);
    gl_.glDeleteProgram(depth_program_);
    gl_.glDeleteVertexArrays(1, &empty_vao_);
    resize(0, 0);
}

void SurfaceBuffers::resize(int width, int height) {
    if (width == width_ && height == height_) return;
    if (framebuffer_) {
        gl_.glDeleteFramebuffers(1, &framebuffer_);
        const GLuint textures[] = {normal_texture_, position_texture_, depth_texture_};
        gl_.glDeleteTextures(3, textures);
        framebuffer_ = normal_texture_ = position_texture_ = depth_texture_ = 0;
    }
    width_ = width;
    height_ = height;
    if (width == 0 || height == 0) return;
    normal_texture_ = make_texture(gl_, GL_RGBA16F, width, height);
    position_texture_ = make_texture(gl_, GL_RGBA32F, width, height);
    depth_texture_ = make_texture(gl_, GL_DEPTH_COMPONENT32F, width, height);
    framebuffer_ = make_framebuffer(gl_, normal_texture_, depth_texture_);
    gl_.glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT1, GL_TEXTURE_2D, position_texture_, 0);
}

void SurfaceBuffers::update(const FrameView& view, const WinterFrame& frame, NormalSource requested,
                            GLuint window_depth) {
    const GlApi& gl = gl_;
    resize(frame.buffer_width, frame.buffer_height);
    gl.glBindFramebuffer(GL_FRAMEBUFFER, framebuffer_);
    const GLenum attachments[] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1};
    gl.glDrawBuffers(2, attachments);
    gl.glViewport(0, 0, width_, height_);
    gl.glDisable(GL_BLEND);
    gl.glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    gl.glDepthMask(GL_TRUE);
    gl.glClearColor(0, 0, 0, 0);
    gl.glClearDepth(1.0);
    gl.glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);

    // Our geometry program shades the redraw: only for frames of fixed-function draws.
    const bool rerender = requested != NormalSource::Depth && view.redraw && !view.redraw_binds_programs &&
                          geometry_program_;
    // Normals from the window's depth first; a re-render then replaces them where its surfaces
    // are the visible ones (its depth test against the window's depth, written a little behind):
    // a visible surface the redraw leaves out (neverball's level in its menu frames) keeps the
    // normal its depth gives, and the guard band beyond the tile has the re-rendered surfaces.
    gl.glEnable(GL_DEPTH_TEST);
    gl.glDepthFunc(GL_ALWAYS);
    gl.glUseProgram(depth_program_);
    bind_sampler(gl, depth_program_, "window_depth", 0, window_depth);
    set_uniform(gl, depth_program_, "write_depth", rerender ? 1 : 0);
    set_uniform(gl, depth_program_, "guard", frame.guard);
    set_uniform(gl, depth_program_, "tile_size", glm::dvec2(view.width, view.height));
    set_uniform(gl, depth_program_, "eye_from_tile_clip", view.eye_from_tile_clip);
    draw_fullscreen(gl, empty_vao_);
    source_ = NormalSource::Depth;
    if (rerender) {
        source_ = requested == NormalSource::Auto ? (view.light.known ? NormalSource::Vertex : NormalSource::Faceted)
                                                  : requested;
        gl.glDepthFunc(GL_LEQUAL);
        gl.glUseProgram(geometry_program_);
        set_uniform(gl, geometry_program_, "use_vertex_normals", source_ == NormalSource::Vertex ? 1 : 0);
        view.redraw(view.guard_band(frame.guard));
    }
    gl.glUseProgram(0);
    gl.glDisable(GL_DEPTH_TEST);
}

}  // namespace glcast::slave::effects
