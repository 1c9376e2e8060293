#include "common/jpeg.h"

#include <turbojpeg.h>

#include <algorithm>
#include <memory>
#include <vector>

namespace glcast::slave {

namespace {

struct TjCloser {
    void operator()(void* handle) const { tjDestroy(handle); }
};

// Averages each factor x factor block: a thumbnail without the aliasing of dropping pixels.
Image scaled_down(const Image& in, int factor) {
    Image out;
    out.width = std::max(1, in.width / factor), out.height = std::max(1, in.height / factor);
    out.rgba.resize(size_t(out.width) * out.height * 4);
    for (int y = 0; y < out.height; y++)
        for (int x = 0; x < out.width; x++) {
            unsigned sum[4] = {0, 0, 0, 0}, n = 0;
            for (int dy = 0; dy < factor && y * factor + dy < in.height; dy++)
                for (int dx = 0; dx < factor && x * factor + dx < in.width; dx++, n++) {
                    const uint8_t* p = &in.rgba[(size_t(y * factor + dy) * in.width + x * factor + dx) * 4];
                    for (int c = 0; c < 4; c++) sum[c] += p[c];
                }
            uint8_t* q = &out.rgba[(size_t(y) * out.width + x) * 4];
            for (int c = 0; c < 4; c++) q[c] = uint8_t(sum[c] / std::max(1u, n));
        }
    return out;
}

}  // namespace

bool thumbnail_jpeg(const Image& image, int max_width, int quality, std::string& jpeg, std::string& error) {
    if (image.width <= 0 || image.height <= 0 || image.rgba.size() != size_t(image.width) * image.height * 4) {
        error = "thumbnail: an empty or malformed image";
        return false;
    }
    const int factor = std::max(1, (image.width + max_width - 1) / std::max(1, max_width));
    const Image small = factor > 1 ? scaled_down(image, factor) : image;
    std::unique_ptr<void, TjCloser> handle(tjInitCompress());
    if (!handle) {
        error = std::string("thumbnail: libturbojpeg: ") + tjGetErrorStr();
        return false;
    }
    unsigned char* out = nullptr;
    unsigned long size = 0;
    if (tjCompress2(handle.get(), small.rgba.data(), small.width, 0, small.height, TJPF_RGBA, &out, &size, TJSAMP_420,
                    std::clamp(quality, 1, 100), TJFLAG_FASTDCT) != 0) {
        error = std::string("thumbnail: libturbojpeg: ") + tjGetErrorStr2(handle.get());
        if (out) tjFree(out);
        return false;
    }
    jpeg.assign(reinterpret_cast<const char*>(out), size);
    tjFree(out);
    return true;
}

}  // namespace glcast::slave
