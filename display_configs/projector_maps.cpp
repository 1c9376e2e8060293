#include "display_configs/projector_maps.h"

#include <sys/stat.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <sstream>

#include "common/image.h"
#include "display_configs/config_check.h"

namespace glcast::slave {

namespace {

constexpr size_t kMaxPfmHeaderBytes = 256;

// As the display config is read (config_check.h): a regular file only, opened without blocking
// (a FIFO named as a map must not hang the slave), bounded as it is read (it may grow while it
// is), and a read that fails is a message, never an exception.
bool read_file(const std::string& path, uint64_t max_bytes, std::string& out, std::string& error) {
    int error_number = 0;
    std::string kind;
    switch (config_check::read_regular_file(path, size_t(max_bytes), out, error_number, kind)) {
        case config_check::FileProblem::none: return true;
        case config_check::FileProblem::cannot_open: error = path + ": " + std::strerror(error_number); break;
        case config_check::FileProblem::not_regular: error = path + ": is " + kind + ", not a regular file"; break;
        case config_check::FileProblem::too_large:
            error = path + ": more than a map may have (" + std::to_string(max_bytes) + " bytes)";
            break;
        case config_check::FileProblem::cannot_read:
            error = path + ": cannot be read: " + std::strerror(error_number);
            break;
    }
    return false;
}

// The next whitespace-separated word of a PFM header, within its first kMaxPfmHeaderBytes.
bool header_word(const std::string& bytes, size_t& pos, std::string& word) {
    while (pos < bytes.size() && pos < kMaxPfmHeaderBytes && std::isspace(uint8_t(bytes[pos]))) pos++;
    const size_t start = pos;
    while (pos < bytes.size() && pos < kMaxPfmHeaderBytes && !std::isspace(uint8_t(bytes[pos]))) pos++;
    word = bytes.substr(start, pos - start);
    return !word.empty() && pos < bytes.size() && pos < kMaxPfmHeaderBytes;
}

bool parse_side(const std::string& word, int& out) {
    if (word.empty() || word.size() > 9 || word.find_first_not_of("0123456789") != std::string::npos) return false;
    out = std::stoi(word);
    return true;
}

}  // namespace

bool read_pfm_bytes(const std::string& bytes, const std::string& name, FloatImage& out, std::string& error) {
    size_t pos = 0;
    std::string magic, w, h, scale_word;
    if (!header_word(bytes, pos, magic) || (magic != "PF" && magic != "Pf")) {
        error = name + ": not a PFM file (it must begin with PF or Pf)";
        return false;
    }
    int width = 0, height = 0;
    if (!header_word(bytes, pos, w) || !header_word(bytes, pos, h) || !parse_side(w, width) || !parse_side(h, height)) {
        error = name + ": the PFM header's size is not two whole numbers";
        return false;
    }
    if (width < 1 || height < 1 || width > kMaxMapSide || height > kMaxMapSide) {
        error = name + ": a PFM of " + w + "x" + h + ": each side must be 1 to " + std::to_string(kMaxMapSide);
        return false;
    }
    char* end = nullptr;
    if (!header_word(bytes, pos, scale_word)) {
        error = name + ": the PFM header has no scale";
        return false;
    }
    const double scale = std::strtod(scale_word.c_str(), &end);
    if (*end || scale == 0 || !std::isfinite(scale)) {
        error = name + ": the PFM scale \"" + scale_word + "\" is not a non-zero number";
        return false;
    }
    if (scale > 0) {
        error = name + ": a big-endian PFM (positive scale) is not supported; write it little-endian";
        return false;
    }
    pos++;  // the one whitespace character after the scale
    const int channels = magic == "PF" ? 3 : 1;
    const uint64_t count = uint64_t(width) * uint64_t(height) * uint64_t(channels);
    if (count > kMaxMapValues) {
        error = name + ": a PFM of " + w + "x" + h + " holds more than " + std::to_string(kMaxMapValues) + " values";
        return false;
    }
    if (bytes.size() - pos != count * 4) {
        error = name + ": the PFM header says " + w + "x" + h + "x" + std::to_string(channels) + " floats (" +
                std::to_string(count * 4) + " bytes), the file holds " + std::to_string(bytes.size() - pos) + " bytes";
        return false;
    }
    out.width = width, out.height = height, out.channels = channels;
    out.values.resize(count);
    const size_t row = size_t(width) * channels;
    for (int y = 0; y < height; y++)  // stored bottom to top
        std::memcpy(&out.values[size_t(height - 1 - y) * row], bytes.data() + pos + size_t(y) * row * 4, row * 4);
    return true;
}

bool read_pfm(const std::string& path, FloatImage& out, std::string& error) {
    std::string bytes;
    if (!read_file(path, kMaxPfmHeaderBytes + kMaxMapValues * 4, bytes, error)) return false;
    return read_pfm_bytes(bytes, path, out, error);
}

std::string pfm_bytes(const FloatImage& image) {
    std::string bytes = std::string(image.channels == 1 ? "Pf" : "PF") + "\n" + std::to_string(image.width) + " " +
                        std::to_string(image.height) + "\n-1.0\n";
    const size_t row = size_t(image.width) * image.channels;
    for (int y = image.height - 1; y >= 0; y--)
        bytes.append(reinterpret_cast<const char*>(&image.values[size_t(y) * row]), row * 4);
    return bytes;
}

bool write_pfm(const std::string& path, const FloatImage& image, std::string& error) {
    // Written beside and renamed into place, as write_png does: never half a map under its name.
    const std::string part = path + ".part";
    std::ofstream out(part, std::ios::binary);
    const std::string bytes = pfm_bytes(image);
    out.write(bytes.data(), std::streamsize(bytes.size()));
    out.close();  // (a full disk shows at the flush)
    if (!out || std::rename(part.c_str(), path.c_str()) != 0) {
        std::remove(part.c_str());
        error = path + ": cannot be written";
        return false;
    }
    return true;
}

bool warp_from_pfm(const FloatImage& pfm, const std::string& name, WarpMap& out, std::string& error) {
    if (pfm.channels != 3) {
        error = name + ": a warp is a 3-channel PFM (PF: u, v, and a third not used), this one has 1 channel";
        return false;
    }
    if (pfm.width < 2 || pfm.height < 2) {
        error = name + ": a warp needs at least 2x2 nodes, this one has " + std::to_string(pfm.width) + "x" +
                std::to_string(pfm.height);
        return false;
    }
    WarpMap w;
    w.width = pfm.width, w.height = pfm.height;
    w.uv.resize(size_t(w.width) * w.height * 2);
    for (size_t i = 0; i < size_t(w.width) * w.height; i++) {
        for (int c = 0; c < 2; c++) {
            const float v = pfm.values[i * 3 + c];
            if (std::isinf(v) || (!std::isnan(v) && std::fabs(v) > kMaxWarpCoordinate)) {
                char text[160];
                std::snprintf(text, sizeof text, ": warp node (%zu, %zu) has %s = %g: a node is a position in the "
                              "tile's image (0..1), or NaN for black", i % w.width, i / w.width, c ? "v" : "u", v);
                error = name + text;
                return false;
            }
            w.uv[i * 2 + c] = v;
        }
    }
    out = std::move(w);
    return true;
}

bool blend_from_png(const std::string& bytes, const std::string& name, BlendMap& out, std::string& error) {
    Image image;
    // Its cost checked from the PNG's header, before anything is held: 4 bytes a pixel decoded,
    // then 3 floats.
    if (!read_png_bytes(bytes, name, image, error, kMaxBlendPixels)) {
        if (error.find("more than the") != std::string::npos)
            error += "; a blend map holds at most " + std::to_string(kMaxBlendPixels) + " pixels (" +
                     std::to_string(kMaxBlendPixels * 16 >> 20) + " MiB as it is read)";
        return false;
    }
    if (image.width > kMaxMapSide || image.height > kMaxMapSide) {
        error = name + ": a blend map of " + std::to_string(image.width) + "x" + std::to_string(image.height) +
                ": each side must be at most " + std::to_string(kMaxMapSide);
        return false;
    }
    BlendMap b;
    b.width = image.width, b.height = image.height;
    b.rgb.resize(size_t(b.width) * b.height * 3);
    for (size_t i = 0; i < size_t(b.width) * b.height; i++)
        for (int c = 0; c < 3; c++) b.rgb[i * 3 + c] = image.rgba[i * 4 + c] / 255.0f;
    out = std::move(b);
    return true;
}

bool write_blend_png(const std::string& path, const BlendMap& map, std::string& error) {
    Image image;
    image.width = map.width, image.height = map.height;
    image.rgba.resize(size_t(map.width) * map.height * 4);
    for (size_t i = 0; i < size_t(map.width) * map.height; i++) {
        for (int c = 0; c < 3; c++)
            image.rgba[i * 4 + c] = uint8_t(std::lround(std::clamp(map.rgb[i * 3 + c], 0.0f, 1.0f) * 255));
        image.rgba[i * 4 + 3] = 255;
    }
    return write_png(path, image, error);
}

bool load_plain_maps(const std::string& warp_path, const std::string& blend_path, ProjectorMaps& out, std::string& error) {
    ProjectorMaps m;
    if (!warp_path.empty()) {
        FloatImage pfm;
        if (!read_pfm(warp_path, pfm, error) || !warp_from_pfm(pfm, warp_path, m.warp, error)) return false;
        m.has_warp = true;
        m.source = warp_path;
    }
    if (!blend_path.empty()) {
        std::string bytes;
        if (!read_file(blend_path, 256u << 20, bytes, error) || !blend_from_png(bytes, blend_path, m.alpha, error))
            return false;
        m.has_alpha = true;
        m.source += (m.source.empty() ? "" : ", ") + blend_path;
    }
    out = std::move(m);
    return true;
}

}  // namespace glcast::slave
