// Falling snow and rain (docs/snow.md): the spectral-particle hybrid. A sparse
// set of 3D particles around the viewer, depth-tested against the program's depth buffer, and
// the spectral opacity texture composited over the frame for the dense far snow. Rain is the
// same pass with vertical motion, a high C and thin streaks.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <stdexcept>
#include <vector>

#include <glm/gtc/type_ptr.hpp>

#include "slave/effects/gl_util.h"
#include "slave/effects/pipeline.h"
#include "slave/effects/snow/snow_motion.h"
#include "slave/effects/snow/snow_synthesis_worker.h"

namespace glcast::slave::effects {

namespace {

// The parameters of one kind ("snow" or "rain"); lengths in units of the program's near-plane
// distance, so that one setting suits programs of any scale.
struct Kind {
    const char* prefix;
    double particles, fall_speed, box, flake_size, particle_opacity, spectral_opacity, speed_c, size, regions,
        scale, sway, streak, sharpness;
};
const Kind kSnow{"snow", 2000, 1.0, 12, 0.04, 0.9, 0.9, 0, 256, 3, 2.5, 0.15, 0.5, 2.5};
const Kind kRain{"rain", 3000, 12.0, 12, 0.008, 0.5, 0.30, 900, 256, 1, 2.0, 0.0, 1.0, 1.0};

std::vector<ParamSpec> kind_specs(const Kind& k) {
    const std::string p = std::string(k.prefix) + ".";
    return {
        {p + "particles", k.particles, 0, 1e6, "number of 3D particles around the viewer (0: none)"},
        {p + "spectral", 1, 0, 1, "composite the spectral opacity texture (0: particles only)"},
        {p + "fall_speed", k.fall_speed, 0, 1000, "fall speed, near-plane distances per second"},
        {p + "wind_x", 0, -1000, 1000, "wind along world x, near-plane distances per second"},
        {p + "wind_z", 0, -1000, 1000, "wind along world z, near-plane distances per second"},
        {p + "box", k.box, 0.5, 1e4, "half size of the particle volume around the camera, near-plane distances"},
        {p + "flake_size", k.flake_size, 1e-5, 100, "particle radius, near-plane distances"},
        {p + "sway", k.sway, 0, 100, "sideways sway amplitude of particles, near-plane distances"},
        {p + "streak", k.streak, 0, 1, "motion blur: particles stretch over this fraction of a frame's motion (1: a whole frame)"},
        {p + "particle_opacity", k.particle_opacity, 0, 1, "opacity of a particle's centre"},
        {p + "spectral_opacity", k.spectral_opacity, 0, 1, "opacity scale of the spectral layer"},
        {p + "brightness", 0.95, 0, 1, "grey level of the snow (or rain) colour"},
        {p + "sharpness", k.sharpness, 0.25, 8, "spectral opacity is raised to this power before compositing (1: the method's mapping as is)"},
        {p + "size", k.size, 8, 2048, "spectral texture size M (even), texels"},
        {p + "regions", k.regions, 1, 8, "regions per canvas side, each with its own C and theta (docs/snow.md, The pass)"},
        {p + "scale", k.scale, 0.25, 16, "canvas pixels per spectral texel"},
        {p + "speed_c", k.speed_c, 0, 1e4, "Eq. 6's C in rad/s; 0: from the particles' speed at the spectral depth"},
        {p + "spectral_depth", k.box, 0.5, 1e4, "depth of the spectral layer, near-plane distances (its speeds follow)"},
        {p + "camera_motion", 1, 0, 1, "follow the program's camera (view transform from frame to frame)"},
        {p + "camera_velocity_x", 0, -1e4, 1e4, "camera velocity in eye space (with camera_motion 0), near-plane distances/s"},
        {p + "camera_velocity_y", 0, -1e4, 1e4, "see camera_velocity_x"},
        {p + "camera_velocity_z", 0, -1e4, 1e4, "see camera_velocity_x (negative: forward)"},
        {p + "seed", 1, 0, 4294967295.0, "seed of every random choice"},
        {p + "frame_time", 1.0 / 60, 1e-3, 1, "seconds per frame of the stream (time = frame number x this)"},
        {p + "without_view", 0, 0, 1, "1: also on frames without a perspective view (2D programs, menus, a camera glcast cannot find), over their interfaces too; 0: such frames are left as they are"},
    };
}

class PrecipitationPass : public Pass {
public:
    PrecipitationPass(const GlApi& gl, const EffectParams& params, bool rain)
        : gl_(gl), kind_(rain ? kRain : kSnow) {
        auto number = [&](const char* name) { return params.number(std::string(kind_.prefix) + "." + name); };
        particles_ = int(number("particles"));
        spectral_ = number("spectral") != 0;
        fall_speed_ = number("fall_speed");
        wind_ = glm::dvec2(number("wind_x"), number("wind_z"));
        box_ = number("box");
        flake_size_ = number("flake_size");
        sway_ = number("sway");
        streak_ = number("streak");
        particle_opacity_ = number("particle_opacity");
        spectral_opacity_ = number("spectral_opacity");
        sharpness_ = number("sharpness");
        brightness_ = number("brightness");
        scale_ = number("scale");
        speed_c_ = number("speed_c");
        spectral_depth_ = number("spectral_depth");
        camera_motion_ = number("camera_motion") != 0;
        camera_velocity_ = glm::dvec3(number("camera_velocity_x"), number("camera_velocity_y"), number("camera_velocity_z"));
        seed_ = uint32_t(number("seed"));
        frame_time_ = number("frame_time");
        without_view_ = number("without_view") != 0;
        regions_ = int(number("regions"));
        const int size = int(number("size"));
        if (size % 2) throw std::runtime_error(std::string(kind_.prefix) + ".size must be even");
        if (spectral_) {
            SpectralSnowParams sp;
            sp.size = size;
            sp.seed = seed_;
            sp.frame_time = frame_time_;
            worker_ = std::make_unique<SnowSynthesisWorker>(sp, regions_, sharpness_, brightness_, spectral_opacity_);
            min_frequency_fraction_ = sp.min_frequency_fraction;
            composite_ = build_program(gl, "fullscreen.vert", "snow_composite.frag");
            composite_single_ = build_program(gl, "snow_composite_single.vert", "snow_composite_single.frag");
            const GLenum targets[] = {GL_TEXTURE_2D_ARRAY, GL_TEXTURE_2D};
            gl.glGenTextures(2, textures_);
            for (int t = 0; t < 2; ++t) {
                gl.glBindTexture(targets[t], textures_[t]);
                if (t == 0)
                    gl.glTexImage3D(GL_TEXTURE_2D_ARRAY, 0, GL_RGBA8, size, size, regions_ * regions_, 0, GL_RGBA,
                                    GL_UNSIGNED_BYTE, nullptr);
                else
                    gl.glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, size, size, 0, GL_RGBA, GL_UNSIGNED_BYTE, nullptr);
                gl.glTexParameteri(targets[t], GL_TEXTURE_MIN_FILTER, GL_LINEAR);
                gl.glTexParameteri(targets[t], GL_TEXTURE_MAG_FILTER, GL_LINEAR);
                gl.glTexParameteri(targets[t], GL_TEXTURE_WRAP_S, GL_REPEAT);
                gl.glTexParameteri(targets[t], GL_TEXTURE_WRAP_T, GL_REPEAT);
            }
        }
        if (particles_) particle_program_ = build_program(gl, "snow_particles.vert", "snow_particles.frag");
        gl.glGenVertexArrays(1, &vao_);
    }

    ~PrecipitationPass() override {
        gl_.glDeleteVertexArrays(1, &vao_);
        if (textures_[0]) gl_.glDeleteTextures(2, textures_);
        if (composite_) gl_.glDeleteProgram(composite_);
        if (composite_single_) gl_.glDeleteProgram(composite_single_);
        if (particle_program_) gl_.glDeleteProgram(particle_program_);
    }

    const char* name() const override { return kind_.prefix; }

    void run(const GlApi& gl, const FrameView& view) override {
        if (!view.view_known && !without_view_) {
            // Its interface cannot be told from its scene, nor its depth from a view (docs/snow.md;
            // the effects runner says so once).
            has_previous_ = false;
            return;
        }
        const glm::dmat4 world_to_eye = view.view_known ? view.modelview : glm::dmat4(1.0);
        const double unit = near_distance(view);
        // Eye-space velocities: the particles' (world wind and fall) and the camera's.
        const glm::dvec3 fall_world(wind_.x * unit, -fall_speed_ * unit, wind_.y * unit);
        glm::dvec3 camera = camera_velocity_ * unit;
        if (camera_motion_ && view.view_known && has_previous_ && view.frame == previous_frame_ + 1)
            camera = camera_velocity_eye(previous_view_, world_to_eye, frame_time_);
        has_previous_ = view.view_known;
        previous_view_ = world_to_eye;
        previous_frame_ = view.frame;
        const glm::dvec3 relative = glm::dmat3(world_to_eye) * fall_world - camera;

        if (particles_) draw_particles(gl, view, world_to_eye, fall_world, relative, unit);
        if (spectral_) composite_spectral(gl, view, relative, unit);
    }

private:
    // The program's near-plane distance: the unit of the pass's lengths.
    static double near_distance(const FrameView& view) {
        const glm::dmat4& p = view.projection;
        if (!view.view_known || p[2][3] == 0) return 1.0;
        const double n = p[3][2] / (p[2][2] - 1);
        return std::isfinite(n) && n > 0 ? n : 1.0;
    }

    void draw_particles(const GlApi& gl, const FrameView& view, const glm::dmat4& world_to_eye,
                        const glm::dvec3& fall_world, const glm::dvec3& relative_eye, double unit) {
        // (the lazy copy binds framebuffers of its own: taken before the draw's state is set)
        const GLuint scene_depth = view.window_depth_matches || !view.depth_texture ? 0 : view.depth_texture();
        if (scene_depth) {
            gl.glBindFramebuffer(GL_FRAMEBUFFER, 0);
            gl.glViewport(0, 0, view.width, view.height);
        }
        const double t = double(view.frame) * frame_time_;
        const double box = 2 * box_ * unit;
        const glm::dvec3 camera_world(glm::inverse(world_to_eye)[3]);
        // Where every particle drifted by now, folded into the box: exact in double, so the
        // shader's floats stay small however long the stream runs.
        const glm::dvec3 drift = glm::mod(fall_world * t, glm::dvec3(box));
        const glm::dvec3 box_min = camera_world - glm::dvec3(box_ * unit);
        const glm::dvec3 origin = glm::mod(box_min - drift, glm::dvec3(box));  // particle p sits at box_min + mod(p - origin, box)
        const glm::mat4 eye_from_world(world_to_eye), clip_from_eye(view.tile_clip_from_eye);
        gl.glUseProgram(particle_program_);
        gl.glUniformMatrix4fv(uniform(gl, particle_program_, "eye_from_world"), 1, GL_FALSE, glm::value_ptr(eye_from_world));
        gl.glUniformMatrix4fv(uniform(gl, particle_program_, "clip_from_eye"), 1, GL_FALSE, glm::value_ptr(clip_from_eye));
        gl.glUniform3f(uniform(gl, particle_program_, "box_min"), float(box_min.x), float(box_min.y), float(box_min.z));
        gl.glUniform3f(uniform(gl, particle_program_, "origin"), float(origin.x), float(origin.y), float(origin.z));
        gl.glUniform1f(uniform(gl, particle_program_, "box_size"), float(box));
        gl.glUniform1f(uniform(gl, particle_program_, "time"), float(std::fmod(t, 3600.0)));
        gl.glUniform1f(uniform(gl, particle_program_, "radius"), float(flake_size_ * unit));
        gl.glUniform1f(uniform(gl, particle_program_, "sway"), float(sway_ * unit));
        const glm::dvec3 blur = relative_eye * (frame_time_ * streak_);
        gl.glUniform3f(uniform(gl, particle_program_, "blur_eye"), float(blur.x), float(blur.y), float(blur.z));
        gl.glUniform2f(uniform(gl, particle_program_, "viewport_size"), float(view.width), float(view.height));
        gl.glUniform1ui(uniform(gl, particle_program_, "seed"), seed_);
        gl.glUniform1f(uniform(gl, particle_program_, "opacity"), float(particle_opacity_));
        gl.glUniform1f(uniform(gl, particle_program_, "brightness"), float(brightness_));
        (void)fall_world;
        // Tested against the program's depth, written nowhere: snow passes behind objects. A
        // depth in the program's own convention is tested in the shader against its conversion.
        gl.glUniform1i(uniform(gl, particle_program_, "test_scene_depth"), scene_depth ? 1 : 0);
        if (scene_depth) {
            gl.glActiveTexture(GL_TEXTURE0);
            gl.glBindTexture(GL_TEXTURE_2D, scene_depth);
            gl.glUniform1i(uniform(gl, particle_program_, "scene_depth"), 0);
            gl.glDisable(GL_DEPTH_TEST);
        } else {
            gl.glEnable(GL_DEPTH_TEST);
        }
        gl.glDepthFunc(GL_LESS);
        gl.glDepthMask(GL_FALSE);
        gl.glEnable(GL_BLEND);
        gl.glBlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
        gl.glBindVertexArray(vao_);
        gl.glDrawArraysInstanced(GL_TRIANGLE_STRIP, 0, 4, particles_);
    }

    void composite_spectral(const GlApi& gl, const FrameView& view, const glm::dvec3& relative_eye, double unit) {
        const int m = worker_->size();
        const double cw = view.canvas_width, ch = view.canvas_height;
        // This frame's texture was submitted last frame; the first frame computes its own.
        if (!submitted_) submit(view, relative_eye, unit, 0.0);
        const std::vector<uint8_t>& texels = worker_->result();
        // While every region has moved alike their textures are identical: one plain 2D texture
        // with coordinates interpolated from the vertices (llvmpipe's fast textured path).
        const bool single = alike_so_far_;  // of the job just collected, before the next is submitted
        gl.glActiveTexture(GL_TEXTURE0);
        gl.glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
        if (single) {
            gl.glBindTexture(GL_TEXTURE_2D, textures_[1]);
            gl.glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, m, m, GL_RGBA, GL_UNSIGNED_BYTE, texels.data());
        } else {
            gl.glBindTexture(GL_TEXTURE_2D_ARRAY, textures_[0]);
            gl.glTexSubImage3D(GL_TEXTURE_2D_ARRAY, 0, 0, 0, 0, m, m, regions_ * regions_, GL_RGBA, GL_UNSIGNED_BYTE,
                               texels.data());
        }
        submit(view, relative_eye, unit, frame_time_);  // the next frame's, while this one is drawn

        const GLuint program = single ? composite_single_ : composite_;
        gl.glUseProgram(program);
        gl.glUniform1i(uniform(gl, program, "snow"), 0);
        gl.glUniform2f(uniform(gl, program, "canvas_offset"), float(view.canvas_x), float(view.canvas_y));
        gl.glUniform1f(uniform(gl, program, "texels_per_pixel"), float(1.0 / (scale_ * m)));
        if (single) {
            gl.glUniform2f(uniform(gl, program, "tile_size"), float(view.width), float(view.height));
        } else {
            gl.glUniform1i(uniform(gl, program, "regions"), regions_);
            gl.glUniform2f(uniform(gl, program, "canvas_size"), float(cw), float(ch));
        }
        gl.glDisable(GL_DEPTH_TEST);
        gl.glEnable(GL_BLEND);
        gl.glBlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);  // I = I_snow a + (1 - a) I_bg
        draw_fullscreen(gl, vao_);
    }

    // Per-region C and theta from the image velocity at the region's centre (docs/snow.md, "The pass").
    void submit(const FrameView& view, const glm::dvec3& relative_eye, double unit, double dt) {
        std::vector<std::pair<double, double>> c_theta;
        const double cw = view.canvas_width, ch = view.canvas_height;
        const glm::dmat4 p = view.view_known ? view.projection : glm::dmat4(1.0);
        for (int j = 0; j < regions_; ++j)
            for (int i = 0; i < regions_; ++i) {
                const glm::dvec2 centre((i + 0.5) * cw / regions_, (j + 0.5) * ch / regions_);
                const glm::dvec2 v = image_velocity(p, cw, ch, centre, relative_eye, spectral_depth_ * unit) / scale_;
                double c = 0, theta = 0;
                spectral_c_theta(v, min_frequency_fraction_, c, theta);
                if (speed_c_ > 0) c = speed_c_;
                c_theta.emplace_back(c, theta);
            }
        // Regions that move alike hold identical textures (one seed): the composite then reads one.
        bool alike = true;
        for (const auto& ct : c_theta) alike &= ct == c_theta.front();
        alike_so_far_ = alike_so_far_ && alike;  // phases remember every frame
        worker_->submit(dt, std::move(c_theta), alike_so_far_);
        submitted_ = true;
    }

    const GlApi& gl_;
    const Kind& kind_;
    int particles_ = 0, regions_ = 1;
    bool spectral_ = true, camera_motion_ = true, submitted_ = false, has_previous_ = false;
    bool without_view_ = false;
    // Every region had the same C and theta in every frame submitted so far.
    bool alike_so_far_ = true;
    double fall_speed_, box_, flake_size_, sway_, streak_, particle_opacity_, spectral_opacity_, brightness_, sharpness_;
    double scale_, speed_c_, spectral_depth_, frame_time_, min_frequency_fraction_ = 1.0 / 32;
    glm::dvec2 wind_;
    glm::dvec3 camera_velocity_;
    uint32_t seed_ = 1;
    uint64_t previous_frame_ = 0;
    glm::dmat4 previous_view_{1.0};
    std::unique_ptr<SnowSynthesisWorker> worker_;
    GLuint composite_ = 0, composite_single_ = 0, particle_program_ = 0, vao_ = 0;
    GLuint textures_[2] = {0, 0};  // the regions' layers; the one texture while they move alike
};

}  // namespace

std::vector<ParamSpec> precipitation_param_specs() {
    std::vector<ParamSpec> all = kind_specs(kSnow);
    for (const ParamSpec& s : kind_specs(kRain)) all.push_back(s);
    return all;
}

std::unique_ptr<Pass> make_precipitation_pass(const GlApi& gl, const EffectParams& params, bool rain) {
    return std::make_unique<PrecipitationPass>(gl, params, rain);
}

}  // namespace glcast::slave::effects
