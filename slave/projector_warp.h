// A projector tile's last step before present (docs/projectors.md): the frame, passes and all,
// is copied from the window into a texture and drawn back warped and blended: the warp's nodes
// are the vertices of a mesh over the output (two triangles a cell, as warping engines draw
// them: a texture lookup per pixel of float nodes costs llvmpipe four times the frame), each
// carrying its source position; each output pixel samples the tile's rendered image there with
// filtering, times the blend (alpha), lifted by the black level (beta). The maps come from the display config
// (display_configs/projector_maps.h, display_configs/mpcdi.h).
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <unordered_map>
#include <vector>

#include "common/gl_headers.h"
#include "slave/replay_observer.h"

namespace glcast::slave {

// The warp: a grid of nodes over the output (node (i, j) at i/(width-1), j/(height-1) across it,
// bilinear between), each the normalized source position in the tile's rendered image (u right,
// v down, (0,0) its top-left), NaN where the output is black.
struct WarpMap {
    int width = 0, height = 0;
    std::vector<float> uv;  // 2 per node, rows top to bottom
};
// A blend (alpha) or black-level (beta) map: RGB in 0..1, stretched over the output.
struct BlendMap {
    int width = 0, height = 0;
    std::vector<float> rgb;  // 3 per pixel, rows top to bottom
};

struct ProjectorMaps {
    bool has_warp = false, has_alpha = false, has_beta = false;
    WarpMap warp;
    BlendMap alpha, beta;
    std::string source;  // for messages: the files they came from
    bool any() const { return has_warp || has_alpha || has_beta; }
};


class Replayer;

class ProjectorWarp : public ReplayObserver {
public:
    ProjectorWarp(Replayer& core, std::shared_ptr<const ProjectorMaps> maps);
    ~ProjectorWarp() override;
    bool wants(uint32_t opcode, const CommandInfo* info) const override;
    void before_call(const Call& c, const uint8_t* tuple, size_t bytes) override;
    void end_frame(SlaveContext& ctx) override;
    void presented(SlaveContext& ctx) override;
    void reset() override;
    void context_removed(uint32_t id) override;

private:
    struct ContextMaps;  // the textures and program of one slave context
    Replayer& core_;
    std::shared_ptr<const ProjectorMaps> maps_;
    std::unordered_map<uint32_t, std::unique_ptr<ContextMaps>> contexts_;
};

}  // namespace glcast::slave
