#include "common/jpeg.h"

#include <turbojpeg.h>

#include <algorithm>
#include <memory>

namespace glcast::slave {

namespace {

struct TjCloser {
    void operator()(void* handle) const { tjDestroy(handle); }
};

}  // namespace

bool thumbnail_jpeg(const Image& image, int max_width, int quality, std::string& jpeg, std::string& error) {
    if (image.width <= 0 || image.height <= 0 || image.rgba.size() != size_t(image.width) * image.height * 4) {
        error = "thumbnail: an empty or malformed image";
        return false;
    }
    const int factor = std::max(1, (image.width + max_width - 1) / std::max(1, max_width));
    const Image small = scaled_down(image, factor);  // (averaged: no aliasing of dropped pixels)
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
