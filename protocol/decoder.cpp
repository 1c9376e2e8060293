#include "protocol/decoder.h"

#include <cstdio>

namespace glcast {

static std::string at(uint64_t offset, const std::string& what) {
    return "at byte " + std::to_string(offset) + ": " + what;
}

DecodeError::DecodeError(uint64_t offset, const std::string& what) : std::runtime_error(at(offset, what)), offset_(offset) {}

void ByteReader::need(size_t n, const char* what) const {
    if (n > size_ - pos_)
        throw DecodeError(offset(), std::string("truncated ") + what + ": need " + std::to_string(n) +
                                        " bytes, " + std::to_string(size_ - pos_) + " left");
}

static PtrRecord read_pointer(ByteReader& r, Wire elem, bool reply_allowed) {
    PtrRecord p;
    const uint64_t where = r.offset();
    const uint8_t tag = r.get<uint8_t>();
    switch (PtrTag(tag)) {
    case PtrTag::Null: break;
    case PtrTag::Data: {
        p.count = r.get<uint32_t>();
        const uint64_t bytes = uint64_t(p.count) * wire_bytes(elem);
        if (bytes > r.remaining())
            throw DecodeError(r.offset(), "array of " + std::to_string(p.count) + " elements runs past the tuple");
        p.data = r.bytes(size_t(bytes), "array");
        break;
    }
    case PtrTag::Offset:
    case PtrTag::ClientAddress: p.value = r.get<uint64_t>(); break;
    case PtrTag::Reply:
        if (!reply_allowed) throw DecodeError(where, "reply marker on an input");
        break;
    default: throw DecodeError(where, "unknown pointer tag " + std::to_string(tag));
    }
    p.tag = PtrTag(tag);
    return p;
}

static void read_value(ByteReader& r, const ParamInfo& info, Arg& a) {
    if (info.kind == ArgKind::Value) {
        const size_t n = wire_bytes(info.wire);
        std::memcpy(&a.bits, r.bytes(n, "value"), n);
    } else {
        a.bits = r.get<uint64_t>();
    }
}

void decode_tuple(ByteReader& r, Call& call, const DecodeLimits& limits) {
    call.offset = r.offset();
    call.opcode = r.get<uint32_t>();
    call.context = r.get<uint32_t>();
    const uint32_t body = r.get<uint32_t>();
    if (body > r.remaining())
        throw DecodeError(call.offset + 8, "tuple body of " + std::to_string(body) + " bytes runs past the message (" +
                                               std::to_string(r.remaining()) + " left)");
    call.body_bytes = body;
    call.body = r.bytes(body, "tuple body");
    call.args.clear();
    call.ret = Arg{};
    call.info = nullptr;
    if (call.opcode >= kSynthBase) {
        if (!is_synthetic_opcode(call.opcode))
            throw DecodeError(call.offset, "unknown synthetic opcode 0x" + [&] {
                char b[16];
                std::snprintf(b, sizeof b, "%08x", call.opcode);
                return std::string(b);
            }());
        return;
    }
    call.info = command_info(call.opcode);
    if (!call.info) throw DecodeError(call.offset, "unknown opcode " + std::to_string(call.opcode));
    if (!(call.info->flags & kSerializable))
        throw DecodeError(call.offset, std::string("opcode of unserializable command ") + call.info->name);

    ByteReader b(call.body, body, call.offset + kTupleHeaderBytes);
    const CommandInfo& ci = *call.info;
    call.args.resize(ci.param_count);
    for (uint16_t i = 0; i < ci.param_count; ++i) {
        const ParamInfo& p = ci.params[i];
        Arg& a = call.args[i];
        switch (p.kind) {
        case ArgKind::Value:
        case ArgKind::Address: read_value(b, p, a); break;
        case ArgKind::StringArray:
        case ArgKind::IndexArrays: {
            const uint32_t n = b.get<uint32_t>();
            if (n > b.remaining())  // every record takes at least one byte
                throw DecodeError(b.offset(), "array list of " + std::to_string(n) + " entries runs past the tuple");
            if (n > limits.list_entries)
                throw DecodeError(b.offset(), "array list of " + std::to_string(n) + " entries is over the limit of " +
                                                  std::to_string(limits.list_entries));
            a.strings.reserve(n);
            for (uint32_t k = 0; k < n; ++k) a.strings.push_back(read_pointer(b, p.wire, false));
            break;
        }
        case ArgKind::Out:
        case ArgKind::OutString: a.ptr = read_pointer(b, p.wire, true); break;
        default: a.ptr = read_pointer(b, p.wire, false); break;
        }
    }
    if (ci.has_ret) {
        if (ci.ret.kind == ArgKind::Value || ci.ret.kind == ArgKind::Address)
            read_value(b, ci.ret, call.ret);
        else
            call.ret.ptr = read_pointer(b, ci.ret.kind == ArgKind::Out ? Wire::U64 : ci.ret.wire, false);
    }
    for (uint16_t i = 0; i < ci.param_count; ++i) {
        const ParamInfo& p = ci.params[i];
        Arg& a = call.args[i];
        if ((p.kind == ArgKind::Out || p.kind == ArgKind::OutString) && a.ptr.tag == PtrTag::Reply) {
            a.reply.tag = PtrTag::Data;
            a.reply.count = b.get<uint32_t>();
            const uint64_t bytes = uint64_t(a.reply.count) * wire_bytes(p.kind == ArgKind::OutString ? Wire::I8 : p.wire);
            if (bytes > b.remaining())
                throw DecodeError(b.offset(), std::string("reply of ") + p.name + " runs past the tuple");
            a.reply.data = b.bytes(size_t(bytes), "reply");
        }
    }
    if (b.remaining())
        throw DecodeError(b.offset(), std::to_string(b.remaining()) + " unexpected bytes after " + ci.name);
}

}  // namespace glcast
