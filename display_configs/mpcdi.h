// VESA MPCDI files (docs/projectors.md, "MPCDI"): a zip (libzip) of an XML description
// (tinyxml2) with a PFM warp and PNG alpha and beta maps per region. glcast reads the 2D media
// profile: a region's warp gives, per node, the position in the buffer (the wall's canvas,
// normalized, (0,0) its top left) that the projector shows there; glcast shows a region as the
// tile of the canvas rectangle the display config gives it. And the 3D simulation profile: a
// region's warp gives, per node, the point of the screen (relative to the viewer's eye) that the
// projector lights there, and the region's frustum is what the image generator renders: glcast
// shows it as a view tile whose view is that frustum, and projects each point through it. Every archive is untrusted: entry
// count, names, sizes and compression ratios, XML depth, map sizes and values are checked first.
#pragma once

#include <string>
#include <vector>

#include "display_configs/display_config.h"
#include "slave/projector_warp.h"

namespace glcast::slave {

constexpr size_t kMaxMpcdiEntries = 256;
constexpr uint64_t kMaxMpcdiEntryBytes = 512ull << 20;  // one entry, uncompressed
constexpr uint64_t kMaxMpcdiRatio = 1000;               // uncompressed / compressed of one entry

// Where a tile's rendered image lies in the buffer, normalized (the tile's canvas rectangle).
struct BufferRect {
    double x = 0, y = 0, width = 1, height = 1;
};

// The maps of region `region` of an MPCDI file, its warp moved into the tile's image: from buffer
// coordinates (2D profile, `tile` its rectangle), or 3D points projected through `view` (3D
// profile: the tile's view must be the region's frustum). False with `error` naming the file,
// the entry or element, and what is wrong.
bool load_mpcdi_region(const std::string& path, const std::string& region, const BufferRect& tile, ProjectorMaps& out,
                       std::string& error, const TileView* view = nullptr);

// What glcast calibrate writes: one buffer, a region per projector with its warp and alpha map;
// the 2D profile (warps of buffer coordinates), or the 3D profile when the regions have their
// frustum (warps of screen points). `files` are (entry name, bytes); the XML is made here.
struct MpcdiRegionOut {
    std::string id;
    int width = 0, height = 0;  // the projector's resolution
    BufferRect rect;            // where its tile lies in the buffer
    std::string warp_entry, alpha_entry;
    bool has_frustum = false;   // 3D profile: the view the image generator renders for it
    TileView frustum;
};
bool write_mpcdi(const std::string& path, int buffer_width, int buffer_height, const std::vector<MpcdiRegionOut>& regions,
                 const std::vector<std::pair<std::string, std::string>>& files, std::string& error);

}  // namespace glcast::slave
