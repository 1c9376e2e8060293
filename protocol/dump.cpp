#include "protocol/dump.h"

#include <cinttypes>
#include <cstring>

namespace glcast {
namespace {

std::string hex(uint64_t v) {
    char b[24];
    std::snprintf(b, sizeof b, "0x%" PRIx64, v);
    return b;
}

std::string number(const uint8_t* p, Wire w, ShowAs d, int group = -1) {
    char b[64];
    switch (w) {
    case Wire::U8: { uint8_t v; std::memcpy(&v, p, 1);
        if (d == ShowAs::Boolean) return v ? "GL_TRUE" : "GL_FALSE";
        std::snprintf(b, sizeof b, "%u", v); break; }
    case Wire::I8: { int8_t v; std::memcpy(&v, p, 1); std::snprintf(b, sizeof b, "%d", v); break; }
    case Wire::U16: { uint16_t v; std::memcpy(&v, p, 2); std::snprintf(b, sizeof b, "%u", v); break; }
    case Wire::I16: { int16_t v; std::memcpy(&v, p, 2); std::snprintf(b, sizeof b, "%d", v); break; }
    case Wire::U32: { uint32_t v; std::memcpy(&v, p, 4);
        if (d == ShowAs::Enum) { if (const char* n = enum_name(v, group)) return n; return hex(v); }
        if (d == ShowAs::Bitfield) return bitfield_names(v, group);
        if (d == ShowAs::Boolean) return v ? "GL_TRUE" : "GL_FALSE";
        std::snprintf(b, sizeof b, "%u", v); break; }
    case Wire::I32: { int32_t v; std::memcpy(&v, p, 4);
        if (d == ShowAs::Boolean) return v ? "True" : "False";
        std::snprintf(b, sizeof b, "%d", v); break; }
    case Wire::U64: { uint64_t v; std::memcpy(&v, p, 8);
        if (d == ShowAs::Handle) return v ? hex(v) : "NULL";
        std::snprintf(b, sizeof b, "%" PRIu64, v); break; }
    case Wire::I64: { int64_t v; std::memcpy(&v, p, 8); std::snprintf(b, sizeof b, "%" PRId64, v); break; }
    case Wire::F32: { float v; std::memcpy(&v, p, 4); std::snprintf(b, sizeof b, "%g", double(v)); break; }
    case Wire::F64: { double v; std::memcpy(&v, p, 8); std::snprintf(b, sizeof b, "%g", v); break; }
    }
    return b;
}

std::string quoted(const uint8_t* p, uint32_t n, size_t limit = 80) {
    std::string s = "\"";
    for (uint32_t i = 0; i < n && s.size() < limit; ++i) {
        const char c = char(p[i]);
        if (c == '"' || c == '\\') { s += '\\'; s += c; }
        else if (c == '\n') s += "\\n";
        else if (c == '\t') s += "\\t";
        else if (uint8_t(c) < 32 || uint8_t(c) >= 127) { char b[8]; std::snprintf(b, sizeof b, "\\x%02x", uint8_t(c)); s += b; }
        else s += c;
    }
    s += n && s.size() >= limit ? "\"..." : "\"";
    return s;
}

std::string elements(const PtrRecord& r, Wire w, ShowAs d, const DumpOptions& opt, int group = -1) {
    if (d == ShowAs::Text || w == Wire::I8) return quoted(r.data, r.count);
    if (w == Wire::U8 && d != ShowAs::Boolean && r.count > opt.max_elements)
        return "blob(" + std::to_string(r.count) + ")";
    std::string s = "{";
    const size_t n = wire_bytes(w);
    for (uint32_t i = 0; i < r.count && i < opt.max_elements; ++i) {
        if (i) s += ", ";
        s += number(r.data + i * n, w, d, group);
    }
    if (r.count > opt.max_elements) s += ", ... (" + std::to_string(r.count) + ")";
    return s + "}";
}

std::string pointer(const PtrRecord& r, const ParamInfo& p, const DumpOptions& opt) {
    switch (r.tag) {
    case PtrTag::Null: return "NULL";
    case PtrTag::Offset: return "buffer+" + hex(r.value);
    case PtrTag::ClientAddress: return "client " + hex(r.value);
    case PtrTag::Reply: return "?";
    case PtrTag::Data: break;
    }
    if (p.kind == ArgKind::VisualInfo && r.count == 72) {
        int64_t f[9];
        std::memcpy(f, r.data, sizeof f);
        return "{visualid = " + hex(uint64_t(f[0])) + ", screen = " + std::to_string(f[1]) + ", depth = " +
               std::to_string(f[2]) + "}";
    }
    if (p.kind == ArgKind::AttribList || p.kind == ArgKind::VisualAttribs) {
        std::string s = "{";
        const size_t n = wire_bytes(p.wire);
        for (uint32_t i = 0; i < r.count; ++i) {
            if (i) s += ", ";
            s += number(r.data + i * n, p.wire, ShowAs::Plain);
        }
        return s + "}";
    }
    return elements(r, p.wire, p.show, opt, p.group);
}

std::string argument(const Arg& a, const ParamInfo& p, const DumpOptions& opt) {
    switch (p.kind) {
    case ArgKind::Value: return number(reinterpret_cast<const uint8_t*>(&a.bits), p.wire, p.show, p.group);
    case ArgKind::Address: return a.bits ? hex(a.bits) : "NULL";
    case ArgKind::IndexArrays: {
        std::string s = "{";
        for (size_t i = 0; i < a.strings.size(); ++i) {
            if (i) s += ", ";
            s += pointer(a.strings[i], p, opt);
        }
        return s + "}";
    }
    case ArgKind::StringArray: {
        std::string s = "{";
        for (size_t i = 0; i < a.strings.size(); ++i) {
            if (i) s += ", ";
            s += a.strings[i].tag == PtrTag::Data ? quoted(a.strings[i].data, a.strings[i].count) : "NULL";
        }
        return s + "}";
    }
    case ArgKind::Out:
    case ArgKind::OutString:
        if (a.ptr.tag == PtrTag::Reply) {
            if (p.kind == ArgKind::OutString) return "&" + quoted(a.reply.data, a.reply.count);
            return "&" + elements(a.reply, p.wire, p.show, opt, p.group);
        }
        return pointer(a.ptr, p, opt);
    default: return pointer(a.ptr, p, opt);
    }
}

// What a frame's summary counts of glcast's own tuples: client arrays sent and found cached,
// mapped-buffer writes, calls the master could not serialize.
void count_synthetic(const Call& call, FrameSummary& sum) {
    switch (call.opcode) {
    case kSynthClientArrays: {
        SynthClientArrays v;
        read_synthetic(call, v);
        for (const auto& a : v.arrays) {
            if (a.cached) {
                sum.cache_hits++;
            } else {
                sum.arrays_sent++;
                sum.array_bytes += a.data_bytes;
            }
        }
        break;
    }
    case kSynthBufferWrite: sum.buffer_writes++; break;
    case kSynthUnserialized: sum.unserialized++; break;
    default: break;
    }
}

}  // namespace

std::string format_call(const Call& call, const DumpOptions& opt) {
    if (!call.info) return format_synthetic(call);
    const CommandInfo& ci = *call.info;
    std::string s = ci.name;
    s += "(";
    for (uint16_t i = 0; i < ci.param_count; ++i) {
        if (i) s += ", ";
        s += ci.params[i].name;
        s += " = ";
        s += argument(call.args[i], ci.params[i], opt);
    }
    s += ")";
    if (ci.has_ret) s += " = " + argument(call.ret, ci.ret, opt);
    return s;
}

void dump_capture(CaptureReader& reader, const DumpOptions& opt, FILE* out) {
    Message m;
    Call call;
    FrameSummary sum;
    uint64_t index = 0;
    uint32_t context = UINT32_MAX;
    while (reader.next(m)) {
        const uint64_t frame = sum.frame;
        if (frame > opt.last_frame) break;
        const bool shown = frame >= opt.first_frame;
        sum.stored_bytes += sizeof(MessageHeader) + m.header.stored_bytes;
        ByteReader r(m.payload.data(), m.payload.size(), 0);
        try {
            while (r.remaining()) {
                decode_tuple(r, call);
                sum.calls++;
                sum.raw_bytes += kTupleHeaderBytes + call.body_bytes;
                std::string line = call.info ? format_call(call, opt) : format_synthetic(call);
                if (!call.info) count_synthetic(call, sum);
                if (shown && opt.calls) {
                    if (call.context != context) std::fprintf(out, "# context %u\n", call.context);
                    std::fprintf(out, "%" PRIu64 " %s\n", index, line.c_str());
                }
                context = call.context;
                index++;
            }
        } catch (const DecodeError& e) {
            throw DecodeError(m.offset, "message " + std::to_string(m.header.sequence) + " (frame " +
                                            std::to_string(frame) + "), payload byte " + std::to_string(e.offset()) +
                                            ": " + std::string(e.what()).substr(std::string(e.what()).find(": ") + 2));
        }
        if (m.header.flags & kMsgFrameEnd) {
            if (shown)
                std::fprintf(out,
                             "# frame %" PRIu64 ": %" PRIu64 " calls, %" PRIu64 " bytes raw, %" PRIu64
                             " stored, client arrays %" PRIu64 " sent (%" PRIu64 " bytes) / %" PRIu64
                             " cache hits, %" PRIu64 " buffer writes, %" PRIu64 " unserialized\n",
                             sum.frame, sum.calls, sum.raw_bytes, sum.stored_bytes, sum.arrays_sent, sum.array_bytes,
                             sum.cache_hits, sum.buffer_writes, sum.unserialized);
            sum = FrameSummary{frame + 1};
        }
    }
    if (sum.calls && sum.frame >= opt.first_frame && sum.frame <= opt.last_frame)
        std::fprintf(out, "# after the last swap: %" PRIu64 " calls, %" PRIu64 " bytes raw\n", sum.calls, sum.raw_bytes);
}

}  // namespace glcast
