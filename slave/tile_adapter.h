// A tile's view of the program (docs/wall.md): window coordinates and pixel sizes mapped into
// the tile's framebuffer (slave/tile_mapping.h), and the projection of rotated or asymmetric
// tiles corrected (slave/view_correction.h). Which calls carry window coordinates, set the
// draw framebuffer or change a matrix comes from semantics.yaml (`window`, `matrix`); adding a
// call there is all a new variant of a known kind needs.
//
// It always follows the program's viewports, scissor boxes and draw framebuffer, wall or not:
// the injected passes read them. Rendering into the program's own framebuffer objects is left
// as the program set it.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <unordered_map>
#include <utility>
#include <vector>

#include <glm/glm.hpp>

#include "slave/program_camera.h"
#include "slave/replay_observer.h"
#include "slave/shader_patch.h"

namespace glcast::slave {

class Replayer;
struct ShareGroup;

class TileAdapter : public ReplayObserver {
public:
    // GL_MAX_VIEWPORTS is at least 16 wherever GL_ARB_viewport_array exists.
    static constexpr int kViewports = 16;

    explicit TileAdapter(Replayer& core);
    ~TileAdapter() override;

    bool wants(uint32_t opcode, const CommandInfo* info) const override;
    bool adapts_redraws() const override { return true; }
    void before_call(const Call& c, const uint8_t* tuple, size_t bytes) override;
    bool replace_call(const Call& c) override;
    void after_call(const Call& c) override;
    void made_current(SlaveContext& ctx, bool first) override;
    void end_frame(SlaveContext& ctx) override;
    void reset() override;
    void context_removed(uint32_t id) override;
    // Contexts and share groups whose state is kept (tests: the totals follow the live ones).
    size_t states_kept() const { return states_.size() + shared_.size(); }

    // The program's viewport 0 as it set it (master window coordinates).
    void program_viewport(int32_t out[4]);
    // The program's own projection now: GL_PROJECTION without the correction a rotated tile
    // (or a redraw) premultiplied into it.
    glm::dmat4 program_projection_now();
    // The camera of a draw by shader program `program` (the slave's name), one mechanism for the
    // tile's correction and the injected passes: the first of its matrices that splits as a
    // perspective product (program_camera.h); for a program whose shaders read the
    // fixed-function matrices through GLSL's built-ins, GL_PROJECTION as the program set it and
    // GL_MODELVIEW. False: none.
    // The slave's name of the program the program's last glUseProgram made current (the core
    // follows it): no driver query at each draw.
    GLuint program_in_use();
    bool shader_camera(uint32_t program, ProgramCamera& out);
    // A shader program that draws flat now: an orthographic matrix among its own, or in
    // GL_PROJECTION when its shaders read the built-ins.
    bool shader_flat(uint32_t program);
    // The light of a shader program whose camera is `camera` (ProgramCameras::light).
    bool shader_light(uint32_t program, const ProgramCamera& camera, effects::SceneLight& out);
    // The view whose screen an orthographic draw lies on (a HUD): to the window, the window's own
    // perspective view this frame, or the scene target's once the window's first flat draw,
    // which shows that scene, went by; into the scene target, after its view this frame and
    // before the window is drawn (VTK's text actors), that view. Null: the draw is shown as drawn
    // (a backdrop, the quad that shows the scene). Called once for each orthographic draw.
    const glm::dmat4* screen_of_flat_draw(const SlaveContext& ctx);
    // This frame's scene, drawn in part of the program's window, was shown over the whole tile (a
    // rotated tile: shown_scene.h): the mask of the tile's pixels that show it (the rest is the
    // program's interface); 0 where it was not.
    GLuint scene_over_tile();
    // How the shader of master name `shader` is patched (slave/shader_patch.h): vertex shaders get
    // the clip-space correction where tiles turn or passes redraw; fragment shaders that read
    // gl_FragCoord the master window's coordinates wherever the slave may draw them elsewhere.
    ShaderPatch shader_patch(uint64_t shader);

    // The tile's camera moved (a tracked head, the eye separation): projections it corrected are
    // corrected again at their next draw.
    void view_changed();
    // Redraw by the injected passes: draws get `correction` premultiplied into the program's
    // projection, or as glcast_clip when `programs` (the redraw binds the program's shader
    // programs); end_redraw puts the projection tracking back as it was, and each program's
    // glcast_clip: a redraw may run just before a draw whose clip is already set (passes that
    // decorate a scene under its overlays run at the first overlay's draw).
    void begin_redraw(const glm::dmat4& correction, bool programs);
    void end_redraw();

private:
    struct State;
    struct Shared;
    State& state();
    Shared& shared();
    void apply_window_rects();
    void track_matrix(const Call& c);
    void correct_projection();
    bool draws_scene_target(SlaveContext& ctx);
    // What the draw framebuffer holds (asked of the driver once): kHoldsColour | kHoldsDepth.
    static constexpr uint8_t kHoldsColour = 1, kHoldsDepth = 2;
    uint8_t attachments();
    bool holds_colour_and_depth() { return attachments() == (kHoldsColour | kHoldsDepth); }
    void saw_view(SlaveContext& ctx, const glm::dmat4& projection);
    // A scene drawn into a target not of the window's shape and shown in part of the window
    // (shown_scene.h; tile_shown_scene.cpp).
    bool part_candidate(SlaveContext& ctx);
    static bool drew_window_this_frame(const State& s);
    void note_part_view();
    bool awaits_shown_scene(const SlaveContext& ctx);
    // This frame's such scene, turned: the context's own, or one another context of its share
    // group lends it (a toolkit's GL widget, which draws only when its view changes and never
    // presents). Null: none.
    const State* scene_in_part(const SlaveContext& ctx);
    State* lender_of(const State& s);
    void find_lender(const SlaveContext& ctx);  // a flat draw to the window may show a lender's scene
    bool shows_scene_in_part(const SlaveContext& ctx, const State& scene);  // the draw about to run; if so, redirected
    bool samples_texture_of_size(const int32_t size[2], GLuint& texture);
    void finish_shown_scene(const Call& c);               // after it: the scene over the tile
    // A glBlitFramebuffer into the window that shows it: shown over the tile instead (true).
    bool shows_scene_by_blit(const int32_t source[4], const int32_t destination[4], GLbitfield mask);
    void show_over_tile(const int32_t rect[4], const std::function<GLuint()>& picture);
    bool correct_shader_program(uint32_t program);  // false: not patched
    // Before a draw by `program` (the slave's name): glcast_fragcoord for the viewport the driver
    // draws with now against the one the program set.
    void correct_fragcoord(uint32_t program);
    bool maps_fragments() const;  // fragment shaders get glcast_fragcoord
    // Vertex shaders get glcast_clip: for rotated tiles, and for passes that redraw the scene.
    bool patching() const;
    bool mapping();
    double pixel_scale();

    Replayer& core_;
    std::unordered_map<uint32_t, std::unique_ptr<State>> states_;       // by context id
    std::unordered_map<const ShareGroup*, std::unique_ptr<Shared>> shared_;
    bool redrawing_ = false, redraw_programs_ = false, redraw_refused_ = false;
    bool warned_no_camera_ = false;
    bool opening_begin_ = false;  // the draw being opened is glBegin's
    glm::dmat4 redraw_correction_{1.0};
    std::unique_ptr<State> saved_;  // the tracking state a redraw started from
    bool saved_opening_begin_ = false;  // ... and whether the draw it interrupted opened with glBegin
    std::vector<std::pair<uint32_t, glm::mat4>> clips_before_redraw_;  // program, its glcast_clip
};

}  // namespace glcast::slave
