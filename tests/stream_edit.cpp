// glcast_stream_edit IN OUT EDIT...: a capture with some tuples changed, framed correctly
// (lengths and CRCs recomputed), so that the decoder accepts it and the slave's own checks
// are what is tested (tests/e2e/replay_attack_test.py). Messages are written uncompressed.
//
// EDIT is TARGET.FIELD=VALUE, TARGET is a command or synthetic tuple name with an optional
// #k (the k-th such tuple, from 0):
//   glBufferData.arg1=0x40000000      a Value or Address parameter
//   glGenLists.ret=1                  the return value
//   glDrawElements.arg3:fill=0xff     every byte of a Data record
//   glGetIntegerv.arg1:offset=0x41    the pointer record becomes an Offset
//   glDrawElements.arg3:null=0        the pointer record becomes Null
//   glUniform4fv.arg2:client=0x41     the pointer record becomes a ClientAddress
//   glShaderSource.arg2:nulls=N       a string list becomes N Null records
//   client_arrays.first_byte=V        a field of every array of the tuple
//   drawable_size.width=V, drawable_size.height=V
//   context:repeat=N                  N more context tuples after it, with new ids
//   stream:repeat=N                   every message after the first N more times (a longer
//                                     stream for timing replays)
//   glClear:after=glDeleteLists(1,0x7fffffff)
//                                     a new tuple after it; each argument is a number (a Value),
//                                     o:N (an Offset record), d:HEX (a Data record of those
//                                     bytes), n (Null) or r:N (a reply of N zero elements)
#include <zlib.h>

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <string>
#include <vector>

#include "protocol/decoder.h"
#include "protocol/format.h"

using namespace glcast;

namespace {

struct Edit {
    std::string target;
    int nth = 0;
    std::string field;  // "arg3", "arg3:fill", "ret", "first_byte", ":repeat", ":after"
    uint64_t value = 0;
    std::string text;   // what follows '=
    bool done = false;
};

class Out {
public:
    std::vector<uint8_t> b;
    template <class T>
    void put(T v) {
        const auto* p = reinterpret_cast<const uint8_t*>(&v);
        b.insert(b.end(), p, p + sizeof v);
    }
    void raw(const void* p, size_t n) {
        const auto* q = static_cast<const uint8_t*>(p);
        b.insert(b.end(), q, q + n);
    }
};

void put_ptr(Out& o, const PtrRecord& r, size_t elem) {
    o.put<uint8_t>(uint8_t(r.tag));
    switch (r.tag) {
    case PtrTag::Data:
        o.put<uint32_t>(r.count);
        o.raw(r.data, r.count * elem);
        break;
    case PtrTag::Offset:
    case PtrTag::ClientAddress: o.put<uint64_t>(r.value); break;
    default: break;
    }
}

void put_value(Out& o, const ParamInfo& p, uint64_t bits) {
    if (p.kind == ArgKind::Value) o.raw(&bits, wire_bytes(p.wire));
    else o.put<uint64_t>(bits);
}

// The body of a decoded GL call, written as the encoder would.
std::vector<uint8_t> encode_body(const Call& c) {
    Out o;
    const CommandInfo& ci = *c.info;
    for (uint16_t i = 0; i < ci.param_count; ++i) {
        const ParamInfo& p = ci.params[i];
        const Arg& a = c.args[i];
        switch (p.kind) {
        case ArgKind::Value:
        case ArgKind::Address: put_value(o, p, a.bits); break;
        case ArgKind::StringArray:
        case ArgKind::IndexArrays:
            o.put<uint32_t>(uint32_t(a.strings.size()));
            for (const PtrRecord& r : a.strings) put_ptr(o, r, wire_bytes(p.wire));
            break;
        default: put_ptr(o, a.ptr, wire_bytes(p.wire)); break;
        }
    }
    if (ci.has_ret) {
        if (ci.ret.kind == ArgKind::Value || ci.ret.kind == ArgKind::Address) put_value(o, ci.ret, c.ret.bits);
        else put_ptr(o, c.ret.ptr, wire_bytes(ci.ret.kind == ArgKind::Out ? Wire::U64 : ci.ret.wire));
    }
    for (uint16_t i = 0; i < ci.param_count; ++i) {
        const ParamInfo& p = ci.params[i];
        const Arg& a = c.args[i];
        if ((p.kind == ArgKind::Out || p.kind == ArgKind::OutString) && a.ptr.tag == PtrTag::Reply) {
            o.put<uint32_t>(a.reply.count);
            o.raw(a.reply.data, a.reply.count * wire_bytes(p.kind == ArgKind::OutString ? Wire::I8 : p.wire));
        }
    }
    return o.b;
}

const char* synth_name(uint32_t op) {
    switch (op) {
    case kSynthClientArrays: return "client_arrays";
    case kSynthBufferWrite: return "buffer_write";
    case kSynthUnserialized: return "unserialized";
    case kSynthDrawableSize: return "drawable_size";
    case kSynthContext: return "context";
    default: return "?";
    }
}

void tuple(Out& o, uint32_t opcode, uint32_t context, const std::vector<uint8_t>& body) {
    o.put<uint32_t>(opcode);
    o.put<uint32_t>(context);
    o.put<uint32_t>(uint32_t(body.size()));
    o.raw(body.data(), body.size());
}

[[noreturn]] void die(const std::string& what) {
    std::cerr << "glcast_stream_edit: " << what << "\n";
    std::exit(2);
}

int arg_index(const std::string& field) {
    if (field.compare(0, 3, "arg") != 0) die("bad field " + field);
    return std::atoi(field.c_str() + 3);
}

// A new GL call from "glFoo(a,b,...)" (see the header).
void insert(const std::string& spec, uint32_t context, Out& o) {
    const auto paren = spec.find('(');
    if (paren == std::string::npos || spec.back() != ')') die("bad call " + spec);
    const int op = opcode_by_name(spec.substr(0, paren).c_str());
    if (op < 0) die("no command " + spec.substr(0, paren));
    const CommandInfo& ci = *command_info(uint32_t(op));
    std::vector<std::string> args;
    std::string cur;
    for (char ch : spec.substr(paren + 1, spec.size() - paren - 2)) {
        if (ch == ',') args.push_back(cur), cur.clear();
        else cur += ch;
    }
    if (!cur.empty()) args.push_back(cur);
    if (args.size() != ci.param_count) die(spec + ": " + std::to_string(ci.param_count) + " arguments expected");
    Out req, rep;
    for (uint16_t i = 0; i < ci.param_count; ++i) {
        const ParamInfo& p = ci.params[i];
        const std::string& a = args[i];
        if (p.kind == ArgKind::Value || p.kind == ArgKind::Address) {
            put_value(req, p, std::strtoull(a.c_str(), nullptr, 0));
        } else if (a.rfind("o:", 0) == 0) {
            req.put<uint8_t>(uint8_t(PtrTag::Offset));
            req.put<uint64_t>(std::strtoull(a.c_str() + 2, nullptr, 0));
        } else if (a.rfind("d:", 0) == 0) {
            std::vector<uint8_t> bytes;
            for (size_t k = 2; k + 1 < a.size(); k += 2) bytes.push_back(uint8_t(std::stoul(a.substr(k, 2), nullptr, 16)));
            req.put<uint8_t>(uint8_t(PtrTag::Data));
            req.put<uint32_t>(uint32_t(bytes.size() / wire_bytes(p.wire)));
            req.raw(bytes.data(), bytes.size());
        } else if (a.rfind("r:", 0) == 0) {
            req.put<uint8_t>(uint8_t(PtrTag::Reply));
            const uint32_t n = uint32_t(std::strtoul(a.c_str() + 2, nullptr, 0));
            rep.put<uint32_t>(n);
            rep.b.resize(rep.b.size() + n * wire_bytes(p.kind == ArgKind::OutString ? Wire::I8 : p.wire), 0);
        } else if (a == "n") {
            req.put<uint8_t>(uint8_t(PtrTag::Null));
        } else {
            die("bad argument " + a);
        }
    }
    if (ci.has_ret) die(spec + ": commands with a return value are not supported");
    req.raw(rep.b.data(), rep.b.size());
    tuple(o, uint32_t(op), context, req.b);
}

// Applies `e` to the tuple and appends the result (one or more tuples) to `o`.
void apply(const Edit& e, Call& c, Out& o) {
    if (e.field == ":after") {
        tuple(o, c.opcode, c.context, std::vector<uint8_t>(c.body, c.body + c.body_bytes));
        insert(e.text, c.context, o);
        return;
    }
    if (c.opcode >= kSynthBase) {
        std::vector<uint8_t> body;
        Out w;
        if (c.opcode == kSynthClientArrays) {
            SynthClientArrays t;
            read_synthetic(c, t);
            w.put<uint32_t>(uint32_t(t.arrays.size()));
            for (auto& a : t.arrays) {
                if (e.field == "first_byte") a.first_byte = uint32_t(e.value);
                else if (e.field == "stride") a.stride = int32_t(e.value);
                else die("client_arrays has no field " + e.field);
                w.put(a.slot); w.put(a.index); w.put(a.size); w.put(a.type); w.put(a.stride);
                w.put(a.normalized); w.put(a.integer); w.put(a.handle); w.put(a.first_byte); w.put(a.cached);
                if (!a.cached) { w.put<uint32_t>(a.data_bytes); w.raw(a.data, a.data_bytes); }
            }
        } else if (c.opcode == kSynthDrawableSize) {
            SynthDrawableSize t;
            read_synthetic(c, t);
            if (e.field == "width") t.width = int32_t(e.value);
            else if (e.field == "height") t.height = int32_t(e.value);
            else die("drawable_size has no field " + e.field);
            w.put(t.drawable); w.put(t.width); w.put(t.height);
        } else if (c.opcode == kSynthContext && e.field == ":repeat") {
            SynthContext t;
            read_synthetic(c, t);
            tuple(o, c.opcode, c.context, std::vector<uint8_t>(c.body, c.body + c.body_bytes));
            for (uint64_t k = 1; k <= e.value; ++k) {
                Out x;
                x.put<uint32_t>(t.id + 1000 + uint32_t(k)); x.put<uint64_t>(t.handle + k); x.put<uint32_t>(0); x.put(t.api);
                tuple(o, c.opcode, c.context, x.b);
            }
            return;
        } else {
            die(std::string("cannot edit ") + synth_name(c.opcode));
        }
        tuple(o, c.opcode, c.context, w.b);
        return;
    }
    std::vector<std::vector<uint8_t>> keep;  // storage for replaced records
    if (e.field == "ret") {
        c.ret.bits = e.value;
    } else {
        const auto colon = e.field.find(':');
        const int i = arg_index(e.field.substr(0, colon));
        if (i < 0 || i >= c.info->param_count) die("no parameter " + std::to_string(i));
        Arg& a = c.args[size_t(i)];
        const std::string op = colon == std::string::npos ? "" : e.field.substr(colon + 1);
        if (op.empty()) {
            a.bits = e.value;
        } else if (op == "fill") {
            if (a.ptr.tag != PtrTag::Data) die("not a data record");
            keep.emplace_back(a.ptr.count * wire_bytes(c.info->params[i].wire), uint8_t(e.value));
            a.ptr.data = keep.back().data();
        } else if (op == "count") {
            if (a.ptr.tag != PtrTag::Data || e.value > a.ptr.count) die("can only shorten a data record");
            a.ptr.count = uint32_t(e.value);
        } else if (op == "offset") {
            a.ptr = PtrRecord{};
            a.ptr.tag = PtrTag::Offset;
            a.ptr.value = e.value;
        } else if (op == "null") {
            a.ptr = PtrRecord{};  // tag Null
        } else if (op == "client") {
            a.ptr = PtrRecord{};
            a.ptr.tag = PtrTag::ClientAddress;
            a.ptr.value = e.value;
        } else if (op == "nulls") {
            a.strings.assign(size_t(e.value), PtrRecord{});
        } else {
            die("unknown operation " + op);
        }
    }
    tuple(o, c.opcode, c.context, encode_body(c));
}

}  // namespace

int main(int argc, char** argv) {
    if (argc < 3) die("usage: glcast_stream_edit IN OUT [EDIT...]");
    std::vector<Edit> edits;
    for (int i = 3; i < argc; ++i) {
        const std::string s = argv[i];
        const auto eq = s.find('=');
        auto dot = s.find_first_of(".:");
        if (eq == std::string::npos || dot == std::string::npos || dot > eq) die("bad edit " + s);
        Edit e;
        e.target = s.substr(0, dot);
        e.field = s.substr(s[dot] == '.' ? dot + 1 : dot, eq - dot - (s[dot] == '.' ? 1 : 0));
        e.value = std::strtoull(s.c_str() + eq + 1, nullptr, 0);
        e.text = s.substr(eq + 1);
        const auto hash = e.target.find('#');
        if (hash != std::string::npos) {
            e.nth = std::atoi(e.target.c_str() + hash + 1);
            e.target.resize(hash);
        }
        edits.push_back(e);
    }
    std::ifstream in(argv[1], std::ios::binary);
    std::vector<uint8_t> file((std::istreambuf_iterator<char>(in)), {});
    if (file.size() < sizeof(FileHeader)) die("not a capture");
    CaptureReader reader(memory_source(file.data(), file.size()));
    std::vector<uint8_t> result(file.begin(), file.begin() + sizeof(FileHeader));
    std::vector<int> seen(edits.size(), 0);
    uint64_t repeat = 0;
    for (auto it = edits.begin(); it != edits.end();)
        if (it->target == "stream" && it->field == ":repeat") repeat = it->value, it = edits.erase(it);
        else ++it;
    std::vector<std::pair<MessageHeader, std::vector<uint8_t>>> messages;
    Message m;
    Call c;
    while (reader.next(m)) {
        Out payload;
        ByteReader r(m.payload.data(), m.payload.size(), 0);
        while (r.remaining()) {
            const size_t start = size_t(r.offset());
            decode_tuple(r, c);
            const char* name = c.opcode >= kSynthBase ? synth_name(c.opcode) : c.info->name;
            bool edited = false;
            for (size_t k = 0; k < edits.size() && !edited; ++k) {
                if (edits[k].done || edits[k].target != name) continue;
                if (seen[k]++ != edits[k].nth) continue;
                // Several edits of one tuple: apply them in turn on the re-decoded result.
                Out once;
                apply(edits[k], c, once);
                edits[k].done = true;
                for (size_t j = k + 1; j < edits.size(); ++j) {
                    if (edits[j].done || edits[j].target != name || seen[j] != edits[j].nth) continue;
                    seen[j]++;
                    ByteReader again(once.b.data(), once.b.size(), 0);
                    decode_tuple(again, c);
                    Out twice;
                    apply(edits[j], c, twice);
                    edits[j].done = true;
                    once.b = twice.b;
                }
                payload.raw(once.b.data(), once.b.size());
                edited = true;
            }
            if (!edited) payload.raw(m.payload.data() + start, size_t(r.offset()) - start);
        }
        MessageHeader h = m.header;
        h.flags &= ~uint32_t(kMsgCompressed | kMsgDelta);  // stored as they are: each stands alone
        h.stored_bytes = h.raw_bytes = uint32_t(payload.b.size());
        h.crc32 = uint32_t(crc32(0, payload.b.data(), uInt(payload.b.size())));
        messages.emplace_back(h, payload.b);
    }
    uint64_t sequence = 0;
    uint32_t frame = 0;
    for (uint64_t round = 0; round <= repeat; ++round) {
        for (size_t k = round ? 1 : 0; k < messages.size(); ++k) {
            MessageHeader h = messages[k].first;
            h.sequence = sequence++;
            h.frame = frame;
            if (h.flags & kMsgFrameEnd) frame++;
            const auto* hp = reinterpret_cast<const uint8_t*>(&h);
            result.insert(result.end(), hp, hp + sizeof h);
            result.insert(result.end(), messages[k].second.begin(), messages[k].second.end());
        }
    }
    for (const Edit& e : edits)
        if (!e.done) die("no tuple " + e.target + "#" + std::to_string(e.nth));
    std::ofstream out(argv[2], std::ios::binary);
    out.write(reinterpret_cast<const char*>(result.data()), std::streamsize(result.size()));
    return out ? 0 : 2;
}
