// A stream written call by call with the generated encoders, as the shim would publish it, and
// packed into a one-message capture file: the input of the replay tests.
#pragma once

#include <zlib.h>

#include <GL/gl.h>
#include <GL/glx.h>

#include <cstdint>
#include <vector>

#include "glcast_commands.h"
#include "glcast_encode.h"
#include "master/encoder.h"
#include "master/stream.h"
#include "protocol/format.h"
#include "tests/roundtrip_support.h"

namespace glcast::testing_support {

struct StreamBuilder {
    ByteVector payload;
    Encoder e{payload};
    roundtrip::FakeSizes sz;

    void context(uint32_t id) { e.set_context(id); }
    template <class F>
    void synthetic(uint32_t op, F&& body) {
        e.begin(op);
        body(e);
        e.end();
    }
    // A glcast.client_arrays tuple naming a vertex array (3 floats, stride 12) by a cache handle
    // the stream never sent: the draw after it must be refused.
    void client_array_never_sent(uint32_t handle = 42) {
        synthetic(kSynthClientArrays, [handle](Encoder& e) {
            e.value<uint32_t>(1);
            e.value<uint8_t>(uint8_t(ClientSlot::Vertex));
            e.value<uint32_t>(0);
            e.value<int32_t>(3);
            e.value<uint32_t>(GL_FLOAT);
            e.value<int32_t>(12);
            e.value<uint8_t>(0);
            e.value<uint8_t>(0);
            e.value<uint32_t>(handle);
            e.value<uint32_t>(0);
            e.value<uint8_t>(1);
        });
    }
    std::vector<uint8_t> file() const {
        const FileHeader fh = make_file_header();
        std::vector<uint8_t> f(reinterpret_cast<const uint8_t*>(&fh), reinterpret_cast<const uint8_t*>(&fh) + sizeof fh);
        MessageHeader h{};
        h.magic = kMessageMagic;
        h.flags = kMsgFrameEnd;
        h.stored_bytes = h.raw_bytes = uint32_t(payload.size());
        h.crc32 = uint32_t(crc32(0, payload.data(), uInt(payload.size())));
        f.insert(f.end(), reinterpret_cast<const uint8_t*>(&h), reinterpret_cast<const uint8_t*>(&h) + sizeof h);
        f.insert(f.end(), payload.begin(), payload.end());
        return f;
    }
};

// A GLX context `handle` made as stream context `id` (with a glcast.context_format of `samples`
// if non-zero), sharing with `share_id`'s, and current on drawable `drawable` of width x height.
inline void open_window(StreamBuilder& s, GLXContext handle, int32_t samples = 0, int32_t width = 32,
                        int32_t height = 16, uint32_t id = 1, uint64_t drawable = 7, uint32_t share_id = 0) {
    s.context(0);
    encode_glXCreateContext(s.e, s.sz, nullptr, nullptr, nullptr, True, handle);
    if (samples)
        s.synthetic(kSynthContextFormat, [&](Encoder& e) {
            e.address(handle);
            e.value<int32_t>(samples);
        });
    s.synthetic(kSynthContext, [&](Encoder& e) {
        e.value<uint32_t>(id);
        e.address(handle);
        e.value<uint32_t>(share_id);
        e.value<uint8_t>(0);
    });
    s.context(id);
    s.synthetic(kSynthDrawableSize, [&](Encoder& e) {
        e.value<uint64_t>(drawable);
        e.value<int32_t>(width);
        e.value<int32_t>(height);
    });
    encode_glXMakeCurrent(s.e, s.sz, nullptr, drawable, handle, True);
}

}  // namespace glcast::testing_support
