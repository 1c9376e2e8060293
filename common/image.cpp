#include "common/image.h"

#include <fcntl.h>
#include <png.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <csetjmp>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <new>

namespace glcast::slave {
namespace {

// The largest image read_png accepts: 2^28 pixels (1 GiB of RGBA), so that a corrupt header
// claiming a huge size fails cleanly instead of exhausting memory.
constexpr int64_t kMaxPixels = int64_t(1) << 28;

// libpng reports errors through this callback and then longjmps to png_jmpbuf; the message is
// kept outside the jumping frames.
struct PngErrors {
    char message[256] = "unknown libpng error";
};

void on_png_error(png_structp png, png_const_charp message) {
    auto* errors = static_cast<PngErrors*>(png_get_error_ptr(png));
    std::snprintf(errors->message, sizeof errors->message, "%s", message ? message : "libpng error");
    png_longjmp(png, 1);  // returning would make libpng print the message to stderr first
}
void on_png_warning(png_structp, png_const_charp) {}

struct File {
    std::FILE* f = nullptr;
    ~File() {
        if (f) std::fclose(f);
    }
};

bool valid(const Image& image) {
    return image.width > 0 && image.height > 0 &&
           image.rgba.size() == size_t(image.width) * size_t(image.height) * 4;
}

// The libpng calls of read_png. Between setjmp and a possible longjmp this frame creates no
// object with a destructor; `pixels` and `rows` live in the caller, so nothing is skipped.
// `refusal` gets our own (non-libpng) reason for refusing the file.
constexpr char kTooManyPixels[] = "too many pixels";

bool decode(png_structp png, png_infop info, std::FILE* f, int64_t max_pixels, int& width, int& height,
            std::vector<uint8_t>& pixels, std::vector<png_bytep>& rows, const char*& refusal) {
    if (setjmp(png_jmpbuf(png))) return false;
    png_init_io(png, f);
    png_set_sig_bytes(png, 8);
    png_set_user_limits(png, 1 << 20, 1 << 20);
    png_read_info(png, info);

    const png_uint_32 w = png_get_image_width(png, info), h = png_get_image_height(png, info);
    const int depth = png_get_bit_depth(png, info), type = png_get_color_type(png, info);
    if (type == PNG_COLOR_TYPE_PALETTE) {
        refusal = "palette PNGs are not supported (only 8-bit gray, gray+alpha, RGB, RGBA)";
        return false;
    }
    if (depth != 8) {
        refusal = "only 8-bit PNGs are supported (this one has another bit depth)";
        return false;
    }
    if (type != PNG_COLOR_TYPE_GRAY && type != PNG_COLOR_TYPE_GRAY_ALPHA && type != PNG_COLOR_TYPE_RGB &&
        type != PNG_COLOR_TYPE_RGB_ALPHA) {
        refusal = "unknown PNG colour type";
        return false;
    }
    if (int64_t(w) * int64_t(h) > std::min(kMaxPixels, max_pixels)) {  // before a byte of it is held
        width = int(std::min<png_uint_32>(w, 1u << 30)), height = int(std::min<png_uint_32>(h, 1u << 30));
        refusal = kTooManyPixels;
        return false;
    }
    if (png_get_valid(png, info, PNG_INFO_tRNS)) png_set_tRNS_to_alpha(png);
    if (type == PNG_COLOR_TYPE_GRAY || type == PNG_COLOR_TYPE_GRAY_ALPHA) png_set_gray_to_rgb(png);
    if (!(type & PNG_COLOR_MASK_ALPHA) && !png_get_valid(png, info, PNG_INFO_tRNS))
        png_set_filler(png, 0xff, PNG_FILLER_AFTER);
    png_set_interlace_handling(png);
    png_read_update_info(png, info);
    if (png_get_rowbytes(png, info) != size_t(w) * 4) {
        refusal = "unexpected row size after conversion to RGBA";
        return false;
    }
    pixels.resize(size_t(w) * size_t(h) * 4);
    rows.resize(h);
    for (png_uint_32 y = 0; y < h; ++y) rows[y] = pixels.data() + size_t(y) * w * 4;
    png_read_image(png, rows.data());
    png_read_end(png, nullptr);
    width = int(w);
    height = int(h);
    return true;
}

bool encode(png_structp png, png_infop info, std::FILE* f, const Image& image,
            std::vector<png_bytep>& rows) {
    if (setjmp(png_jmpbuf(png))) return false;
    png_init_io(png, f);
    png_set_IHDR(png, info, png_uint_32(image.width), png_uint_32(image.height), 8, PNG_COLOR_TYPE_RGB_ALPHA,
                 PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    png_write_info(png, info);
    png_write_image(png, rows.data());
    png_write_end(png, nullptr);
    return true;
}

}  // namespace

bool write_png(const std::string& path, const Image& image, std::string& error) {
    if (!valid(image)) {
        error = "write_png " + path + ": invalid image (" + std::to_string(image.width) + "x" +
                std::to_string(image.height) + ", " + std::to_string(image.rgba.size()) + " bytes)";
        return false;
    }
    // Written beside and renamed into place: a reader (or a killed writer) never meets half a file.
    const std::string part = path + ".part";
    File file;
    file.f = std::fopen(part.c_str(), "wb");
    if (!file.f) {
        error = "write_png " + path + ": " + std::strerror(errno);
        return false;
    }
    std::vector<png_bytep> rows(size_t(image.height));
    for (int y = 0; y < image.height; ++y)
        rows[size_t(y)] = const_cast<png_bytep>(image.rgba.data() + size_t(y) * size_t(image.width) * 4);

    PngErrors errors;
    png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, &errors, on_png_error, on_png_warning);
    png_infop info = png ? png_create_info_struct(png) : nullptr;
    if (!png || !info) {
        png_destroy_write_struct(&png, &info);
        error = "write_png " + path + ": out of memory";
        return false;
    }
    const bool ok = encode(png, info, file.f, image, rows);
    png_destroy_write_struct(&png, &info);
    const bool closed = std::fclose(file.f) == 0;
    file.f = nullptr;
    if (!ok) {
        std::remove(part.c_str());
        error = "write_png " + path + ": libpng: " + errors.message;
        return false;
    }
    if (!closed || std::rename(part.c_str(), path.c_str()) != 0) {
        error = "write_png " + path + ": " + std::strerror(errno);
        std::remove(part.c_str());
        return false;
    }
    return true;
}

namespace {

// read_png's work on an open file (a file, or bytes in memory); `path` names it in messages.
bool read_png_from(std::FILE* f, const std::string& path, int64_t max_pixels, Image& image, std::string& error) {
    File file;
    file.f = f;
    unsigned char signature[8];
    if (std::fread(signature, 1, 8, file.f) != 8 || png_sig_cmp(signature, 0, 8) != 0) {
        error = "read_png " + path + ": not a PNG file";
        return false;
    }
    PngErrors errors;
    png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, &errors, on_png_error, on_png_warning);
    png_infop info = png ? png_create_info_struct(png) : nullptr;
    if (!png || !info) {
        png_destroy_read_struct(&png, &info, nullptr);
        error = "read_png " + path + ": out of memory";
        return false;
    }
    int width = 0, height = 0;
    std::vector<uint8_t> pixels;
    std::vector<png_bytep> rows;
    const char* refusal = nullptr;
    bool ok = false;
    try {
        ok = decode(png, info, file.f, max_pixels, width, height, pixels, rows, refusal);
    } catch (const std::bad_alloc&) {
        refusal = "out of memory";
    }
    png_destroy_read_struct(&png, &info, nullptr);
    if (!ok && refusal == kTooManyPixels) {
        const int64_t most = std::min(kMaxPixels, max_pixels);
        error = "read_png " + path + ": an image of " + std::to_string(width) + "x" + std::to_string(height) +
                " pixels, more than the " + std::to_string(most) + " it may have here (" +
                std::to_string(most * 4 >> 20) + " MiB as RGBA)";
        return false;
    }
    if (!ok) {
        error = "read_png " + path + ": " + (refusal ? std::string(refusal) : "libpng: " + std::string(errors.message));
        return false;
    }
    image.width = width;
    image.height = height;
    image.rgba = std::move(pixels);
    return true;
}

}  // namespace

bool read_png(const std::string& path, Image& image, std::string& error, int64_t max_pixels) {
    // Opened without blocking and only as a regular file: a FIFO named as a picture must not hang
    // the reader (as the display config's reader, display_configs/config_check.h).
    const int fd = open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
    struct stat st {};
    if (fd < 0 || fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) {
        error = "read_png " + path + ": " + (fd < 0 ? std::strerror(errno) : "not a regular file");
        if (fd >= 0) close(fd);
        return false;
    }
    fcntl(fd, F_SETFL, fcntl(fd, F_GETFL) & ~O_NONBLOCK);
    std::FILE* f = fdopen(fd, "rb");
    if (!f) {
        error = "read_png " + path + ": " + std::strerror(errno);
        close(fd);
        return false;
    }
    return read_png_from(f, path, max_pixels, image, error);
}

bool read_png_bytes(const std::string& bytes, const std::string& name, Image& image, std::string& error,
                    int64_t max_pixels) {
    std::FILE* f = bytes.empty() ? nullptr : fmemopen(const_cast<char*>(bytes.data()), bytes.size(), "rb");
    if (!f) {
        error = "read_png " + name + ": " + (bytes.empty() ? "empty" : std::strerror(errno));
        return false;
    }
    return read_png_from(f, name, max_pixels, image, error);
}

Image scaled_down(const Image& in, int factor) {
    if (factor <= 1) return in;
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
            for (int c = 0; c < 4; c++) q[c] = uint8_t((sum[c] + n / 2) / std::max(1u, n));
        }
    return out;
}

ImageDiff compare(const Image& a, const Image& b) {
    ImageDiff diff;
    if (a.width != b.width || a.height != b.height || a.rgba.size() != b.rgba.size() ||
        a.rgba.size() != size_t(std::max(a.width, 0)) * size_t(std::max(a.height, 0)) * 4) {
        diff.size_mismatch = true;
        diff.differing_pixels = std::max(int64_t(a.width) * a.height, int64_t(b.width) * b.height);
        diff.max_channel_diff = 255;
        return diff;
    }
    const uint8_t* p = a.rgba.data();
    const uint8_t* q = b.rgba.data();
    for (size_t i = 0, n = a.rgba.size(); i < n; i += 4) {
        int pixel_max = 0;
        for (size_t k = 0; k < 4; ++k) pixel_max = std::max(pixel_max, std::abs(int(p[i + k]) - int(q[i + k])));
        if (pixel_max) {
            ++diff.differing_pixels;
            diff.max_channel_diff = std::max(diff.max_channel_diff, pixel_max);
        }
    }
    return diff;
}

Image mosaic(const std::vector<std::vector<const Image*>>& rows) {
    std::vector<int> column_width, row_height(rows.size(), 0);
    for (size_t r = 0; r < rows.size(); ++r)
        for (size_t c = 0; c < rows[r].size(); ++c) {
            if (column_width.size() <= c) column_width.resize(c + 1, 0);
            if (const Image* tile = rows[r][c]; tile && valid(*tile)) {
                column_width[c] = std::max(column_width[c], tile->width);
                row_height[r] = std::max(row_height[r], tile->height);
            }
        }
    Image out;
    for (int w : column_width) out.width += w;
    for (int h : row_height) out.height += h;
    if (out.width == 0 || out.height == 0) return Image{};
    out.rgba.assign(size_t(out.width) * size_t(out.height) * 4, 0);
    for (size_t i = 3; i < out.rgba.size(); i += 4) out.rgba[i] = 255;

    int y0 = 0;
    for (size_t r = 0; r < rows.size(); ++r) {
        int x0 = 0;
        for (size_t c = 0; c < rows[r].size(); ++c) {
            if (const Image* tile = rows[r][c]; tile && valid(*tile))
                for (int y = 0; y < tile->height; ++y)
                    std::memcpy(&out.rgba[(size_t(y0 + y) * out.width + x0) * 4],
                                &tile->rgba[size_t(y) * tile->width * 4], size_t(tile->width) * 4);
            x0 += column_width[c];
        }
        y0 += row_height[r];
    }
    return out;
}

Image flip_rows(const Image& image) {
    Image out;
    out.width = image.width;
    out.height = image.height;
    out.rgba.resize(image.rgba.size());
    const size_t stride = size_t(std::max(image.width, 0)) * 4;
    if (stride == 0) return out;
    const size_t height = image.rgba.size() / stride;
    for (size_t y = 0; y < height; ++y)
        std::memcpy(&out.rgba[y * stride], &image.rgba[(height - 1 - y) * stride], stride);
    return out;
}

static double grey(const Image& im, int x, int y) {
    const uint8_t* p = &im.rgba[(size_t(y) * im.width + x) * 4];
    return (p[0] + p[1] + p[2]) / 3.0;
}

Shift estimate_shift(const Image& a, const Image& b, int x0, int y0, int w, int h, int radius) {
    double best = 1e300;
    Shift shift;
    for (int dy = -radius; dy <= radius; ++dy)
        for (int dx = -radius; dx <= radius; ++dx) {
            double ssd = 0;
            for (int y = y0; y < y0 + h; ++y)
                for (int x = x0; x < x0 + w; ++x) {
                    const double d = grey(b, x + dx, y + dy) - grey(a, x, y);
                    ssd += d * d;
                }
            if (ssd < best) best = ssd, shift = Shift{dx, dy};
        }
    return shift;
}

Image difference(const Image& a, const Image& a0) {
    Image out{a.width, a.height, a.rgba};
    for (size_t i = 0; i < out.rgba.size(); ++i)
        out.rgba[i] = (i % 4 == 3) ? 255 : uint8_t(std::abs(int(a.rgba[i]) - int(a0.rgba[i])));
    return out;
}

}  // namespace glcast::slave
