#include "master/encoder.h"

#include <cstring>

#include "protocol/format.h"

namespace glcast {

bool Encoder::checked_bytes(int64_t count, size_t elem_bytes, uint32_t& out_count) {
    if (count < 0) count = 0;
    if (count > kMaxArrayBytes / int64_t(elem_bytes ? elem_bytes : 1)) {
        fail("array of " + std::to_string(count) + " elements is larger than the 1 GiB limit");
        return false;
    }
    out_count = uint32_t(count);
    return true;
}

void Encoder::data_checked(const void* p, int64_t count, size_t elem_bytes) {
    uint32_t n = 0;
    if (!p) { tag(PtrTag::Null); return; }
    if (!checked_bytes(count, elem_bytes, n)) { tag(PtrTag::Null); return; }
    tag(PtrTag::Data);
    value<uint32_t>(n);
    put(p, size_t(n) * elem_bytes);
}

void Encoder::offset(const void* p) {
    tag(PtrTag::Offset);
    address(p);
}

void Encoder::deferred(const void* p, bool in_buffer) {
    if (!p && !in_buffer) { tag(PtrTag::Null); return; }
    tag(in_buffer ? PtrTag::Offset : PtrTag::ClientAddress);
    address(p);
}

void Encoder::string(const char* s) {
    if (!s) { tag(PtrTag::Null); return; }
    data(s, int64_t(std::strlen(s)), 1);
}

void Encoder::string_array(int64_t count, const char* const* strings, const int* lengths) {
    if (count < 0 || !strings) count = 0;
    if (count > 1 << 20) { fail("string array of " + std::to_string(count) + " entries"); count = 0; }
    value<uint32_t>(uint32_t(count));
    for (int64_t i = 0; i < count; ++i) {
        const char* s = strings[i];
        if (lengths && lengths[i] >= 0)
            data(s, lengths[i], 1);
        else
            string(s);
    }
}

void Encoder::visual_attribs(const int* list) {
    // glXChooseVisual: GLX_USE_GL, GLX_RGBA, GLX_DOUBLEBUFFER and GLX_STEREO stand alone;
    // every other attribute is followed by a value.
    if (!list) { tag(PtrTag::Null); return; }
    size_t n = 0;
    while (n < 512 && list[n] != 0) {
        const int key = list[n];
        const bool boolean = key == 1 || key == 4 || key == 5 || key == 6;
        n += boolean ? 1 : 2;
    }
    if (n >= 512) { fail("visual attribute list without terminator"); tag(PtrTag::Null); return; }
    data(list, int64_t(n + 1), sizeof(int));
}

void Encoder::visualinfo(const XVisualInfo* vi) {
    if (!vi) { tag(PtrTag::Null); return; }
    const int64_t fields[9] = {int64_t(vi->visualid), vi->screen, vi->depth, vi->c_class,
                               int64_t(vi->red_mask), int64_t(vi->green_mask),
                               int64_t(vi->blue_mask), vi->colormap_size, vi->bits_per_rgb};
    data(fields, sizeof fields, 1);
}

void Encoder::reply_marker(const void* p) { tag(p ? PtrTag::Reply : PtrTag::Null); }

void Encoder::reply_data(const void* p, int64_t count, size_t elem_bytes) {
    uint32_t n = 0;
    if (!checked_bytes(count, elem_bytes, n)) n = 0;
    value<uint32_t>(n);
    put(p, size_t(n) * elem_bytes);
}

void Encoder::reply_string(const char* s, int64_t capacity) {
    const size_t n = capacity > 0 ? strnlen(s, size_t(capacity)) : 0;
    value<uint32_t>(uint32_t(n));
    put(s, n);
}

}  // namespace glcast
