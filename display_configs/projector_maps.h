// A projector tile's warp and blend (docs/projectors.md): where each output pixel samples the
// tile's rendered image, and how much of it the projector shows. Read from the plain pair (a
// PFM warp and a PNG blend) or from an MPCDI file (display_configs/mpcdi.h); every file is
// untrusted: sizes, values and dimensions are checked before anything is allocated.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "slave/projector_warp.h"

namespace glcast::slave {

constexpr int kMaxMapSide = 16384;                  // nodes or pixels along one side of a map
constexpr uint64_t kMaxMapValues = 64ull << 20;     // floats in one map (256 MiB)
constexpr int64_t kMaxBlendPixels = 64ll << 20;     // pixels of a blend map (1 GiB as read: RGBA, then 3 floats)
constexpr double kMaxWarpCoordinate = 1e3;          // |u|, |v| of a warp node (outside [0,1]: black)

// A float image as PFM stores it: rows here top to bottom (PFM's are bottom to top).
struct FloatImage {
    int width = 0, height = 0, channels = 0;  // 1 (Pf) or 3 (PF)
    std::vector<float> values;
};

// Reads a PFM; false with `error` naming the file and what is wrong (a header that is not PFM,
// a side over kMaxMapSide, a size the file does not hold). Values are not checked here.
bool read_pfm(const std::string& path, FloatImage& out, std::string& error);
bool read_pfm_bytes(const std::string& bytes, const std::string& name, FloatImage& out, std::string& error);
// Writes 3-channel (or 1-channel) little-endian PFM, rows bottom to top.
bool write_pfm(const std::string& path, const FloatImage& image, std::string& error);
std::string pfm_bytes(const FloatImage& image);

// A warp from a PFM image (3 channels: u, v and one not used; or 2 of 3 when written by others).
// False for a warp of fewer than 2x2 nodes, or a node that is infinite or beyond
// kMaxWarpCoordinate (NaN is allowed: black there).
bool warp_from_pfm(const FloatImage& pfm, const std::string& name, WarpMap& out, std::string& error);
// A blend from PNG bytes (grey or RGB, 8 bit): values 0..1, multiplying the output as stored.
bool blend_from_png(const std::string& bytes, const std::string& name, BlendMap& out, std::string& error);
bool write_blend_png(const std::string& path, const BlendMap& map, std::string& error);

// The plain pair of a display config's tile: "warp" (a PFM) and/or "blend" (a PNG), paths as
// given (the caller resolves them against the config's folder).
bool load_plain_maps(const std::string& warp_path, const std::string& blend_path, ProjectorMaps& out, std::string& error);

}  // namespace glcast::slave
