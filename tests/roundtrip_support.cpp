#include "tests/roundtrip_support.h"

#include <GL/gl.h>

#include "protocol/decoder.h"

namespace glcast::roundtrip {

static constexpr size_t kBufferBytes = 1 << 20;

Harness::Harness() : pattern_(kBufferBytes), zeros_(kBufferBytes) {
    for (size_t i = 0; i < pattern_.size(); ++i) pattern_[i] = uint8_t(i * 7 + 1);
    pointers_[0] = pointers_[1] = pattern_.data();
    attribs_.assign(kBufferBytes / 8, 0);
    attribs_[0] = 0x3038;
    visual_.visualid = 0x21;
    visual_.depth = 24;
}

void Harness::begin(uint32_t opcode) {
    opcode_ = opcode;
    out_.clear();
    values_.clear();
    ret_ = 0;
    encoder_.clear_failure();
    sizes_.clear_failure();
}

uint64_t Harness::pick(const char* name, uint32_t sample_pname) {
    if (sample_pname) return sample_pname;
    const std::string n = name;
    if (n == "format") return GL_RGBA;
    if (n == "type") return GL_UNSIGNED_BYTE;
    if (n == "target") return GL_TEXTURE_2D;
    if (n == "map") return GL_PIXEL_MAP_I_TO_I;
    return 2;  // counts, sizes, names: small enough for every length expression
}

void* Harness::buffer(const char* name) {
    // Arrays whose values are themselves lengths or counts must not send the encoder past
    // the end of these buffers: they get zeros.
    const std::string n = name;
    // Attribute lists: as 32-bit keys/values {0x3038 (EGL_NONE), 0, 0}: GLX's list ends at key 0,
    // EGL's at EGL_NONE; as 64-bit EGLAttribs {0x3038}: EGL_NONE at once.
    if (n.find("attrib") != std::string::npos) return attribs_.data();
    if (n.find("length") != std::string::npos || n.find("count") != std::string::npos || n == "first" ||
        n == "nelements" || n == "num_config")
        return zeros_.data();
    return pattern_.data();
}

void Harness::check() {
    const CommandInfo* info = command_info(opcode_);
    if (!encoder_.failure().empty() || !sizes_.failure().empty()) {
        size_unknown++;
        unknown_sizes.push_back(std::string(info->name) + ": " +
                                (encoder_.failure().empty() ? sizes_.failure() : encoder_.failure()));
        return;
    }
    encoded++;
    auto fail = [&](const std::string& why) { failures.push_back(std::string(info->name) + ": " + why); };
    try {
        ByteReader r(out_.data(), out_.size(), 0);
        Call call;
        decode_tuple(r, call);
        if (r.remaining()) return fail("bytes left after the tuple");
        if (call.opcode != opcode_) return fail("opcode changed");
        for (uint16_t i = 0; i < info->param_count; ++i) {
            const ParamInfo& p = info->params[i];
            const Arg& a = call.args[i];
            if (p.kind == ArgKind::Value) {
                const size_t n = wire_bytes(p.wire);
                uint64_t want = values_[i], got = a.bits;
                if (n < 8) { want &= (uint64_t(1) << (8 * n)) - 1; got &= (uint64_t(1) << (8 * n)) - 1; }
                if (want != got) return fail(std::string("value of ") + p.name + " changed");
            }
            const PtrRecord& rec = p.kind == ArgKind::Out && a.ptr.tag == PtrTag::Reply ? a.reply : a.ptr;
            if (rec.tag == PtrTag::Data && rec.count && p.kind != ArgKind::String && p.kind != ArgKind::OutString &&
                p.kind != ArgKind::VisualInfo) {
                const size_t bytes = rec.count * wire_bytes(p.wire);
                if (std::memcmp(rec.data, pattern_.data(), bytes) != 0 && std::memcmp(rec.data, zeros_.data(), bytes) != 0 &&
                    std::memcmp(rec.data, attribs_.data(), bytes) != 0)
                    return fail(std::string("array ") + p.name + " differs from what was passed");
            }
            if (p.kind == ArgKind::String && (rec.tag != PtrTag::Data || rec.count != 3 || std::memcmp(rec.data, "abc", 3)))
                return fail(std::string("string ") + p.name + " changed");
        }
        if (info->has_ret && info->ret.kind == ArgKind::Value) {
            const size_t n = wire_bytes(info->ret.wire);
            uint64_t want = ret_, got = call.ret.bits;
            if (n < 8) { want &= (uint64_t(1) << (8 * n)) - 1; got &= (uint64_t(1) << (8 * n)) - 1; }
            if (want != got) return fail("return value changed");
        }
    } catch (const DecodeError& e) {
        fail(std::string("decode: ") + e.what());
    }
}

}  // namespace glcast::roundtrip
