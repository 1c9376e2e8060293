// libFuzzer target through the whole slave: decode, dispatch and replay on a real headless
// context. The decoder only guarantees that a tuple is well formed; the replay must also
// survive well-formed tuples whose values lie (a size above the shipped data, a count of
// names no reply carries, an offset where a pointer was expected). Random bytes almost never
// get past the decoder, so the input is not a stream: it picks one of the committed captures
// (tests/data/*.glcs) and a list of mutation commands applied to its decoded tuples, each
// re-encoded with correct lengths. Every mutated stream therefore decodes, and the replay is
// what gets tested.
//
// Input: byte 0 selects the capture; then commands until the input ends, each
//   u8 kind, u16 tuple index, then the kind's operands (see apply()).
// No commands at all replays the capture as it is (the seed corpus, and the CI test).
//
// ReplayError/DecodeError/EffectsError/GlMissing are the slave's answers to a bad stream and
// fine; anything else that escapes, and every sanitizer report, is a finding.
//
// GLCAST_FUZZ_VERBOSE=1 prints the decoded commands (what a saved crash input does).
#include <fuzzer/FuzzedDataProvider.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <deque>
#include <dirent.h>
#include <memory>
#include <string>
#include <vector>

#include "glcast_commands.h"
#include "glcast_synthetic.h"
#include "protocol/decoder.h"
#include "protocol/format.h"
#include "slave/effects_runner.h"
#include "slave/replayer.h"

#ifndef GLCAST_FUZZ_DATA_DIR
#define GLCAST_FUZZ_DATA_DIR "tests/data"
#endif

using namespace glcast;

namespace {

struct Tuple {
    uint32_t opcode = 0, context = 0;
    std::vector<uint8_t> body;
    uint32_t message = 0;  // index of the message it came in: swaps end messages
};

struct MessageInfo {
    uint32_t flags = 0, frame = 0;
};

struct Capture {
    std::string name;
    std::vector<Tuple> tuples;
    std::vector<MessageInfo> messages;
};

std::vector<Capture> g_captures;
std::unique_ptr<slave::Replayer> g_replayer;
bool g_verbose = false;
// GLCAST_FUZZ_SKIP=null: no Null tags on inputs. A crash class found within seconds (GL
// handed NULL where it reads an array) would otherwise be all a run finds.
bool g_skip_null = false;

// Only the first frames of each capture: they hold the set-up (contexts, objects, shaders, the
// first draws) where nearly every kind of call happens once, and later frames repeat them;
// whole captures would run at a few inputs per second.
uint32_t frame_limit() {
    const char* env = std::getenv("GLCAST_FUZZ_FRAMES");
    return env && *env ? uint32_t(std::strtoul(env, nullptr, 10)) : 3;
}

void load_captures() {
    const uint32_t frames = frame_limit();
    const char* env = std::getenv("GLCAST_FUZZ_DATA");
    const std::string dir = env && *env ? env : GLCAST_FUZZ_DATA_DIR;
    std::vector<std::string> names;
    if (DIR* d = opendir(dir.c_str())) {
        while (dirent* e = readdir(d)) {
            const std::string n = e->d_name;
            if (n.size() > 5 && n.compare(n.size() - 5, 5, ".glcs") == 0) names.push_back(n);
        }
        closedir(d);
    }
    // Sorted, the captures of the first saved inputs first: byte 0 of a saved input must name
    // the same capture on every machine, and a capture committed later must not move them.
    static const std::vector<std::string> kFirst = {"core_scene.glcs", "ff_scene.glcs", "glfw_dynamic.glcs",
                                                    "glxgears.glcs"};
    auto rank = [](const std::string& n) {
        const auto it = std::find(kFirst.begin(), kFirst.end(), n);
        return std::make_pair(it - kFirst.begin(), n);
    };
    std::sort(names.begin(), names.end(), [&](const std::string& a, const std::string& b) { return rank(a) < rank(b); });
    for (const std::string& n : names) {
        Capture cap;
        cap.name = n;
        CaptureReader reader(open_file_source(dir + "/" + n));
        Message m;
        while (reader.next(m) && m.header.frame < frames) {
            ByteReader r(m.payload.data(), m.payload.size(), 0);
            Call c;
            while (r.remaining()) {
                decode_tuple(r, c);
                Tuple t;
                t.opcode = c.opcode;
                t.context = c.context;
                t.body.assign(c.body, c.body + c.body_bytes);
                t.message = uint32_t(cap.messages.size());
                cap.tuples.push_back(std::move(t));
            }
            cap.messages.push_back({m.header.flags & ~uint32_t(kMsgCompressed | kMsgDelta), m.header.frame});
        }
        g_captures.push_back(std::move(cap));
    }
    if (g_captures.empty()) {
        std::fprintf(stderr, "fuzz_replay: no captures (*.glcs) in %s (set GLCAST_FUZZ_DATA)\n", dir.c_str());
        std::abort();
    }
}

// --- a decoded tuple in a form that can be changed and written back ----------------------

struct Record {
    PtrTag tag = PtrTag::Null;
    uint32_t count = 0;
    std::vector<uint8_t> data;  // count * element bytes
    uint64_t value = 0;
};

struct Param {
    uint64_t bits = 0;
    Record rec;
    std::vector<Record> list;  // StringArray, IndexArrays
    Record reply;              // Out / OutString with tag Reply
};

size_t elem_bytes(const ParamInfo& p) {
    return p.kind == ArgKind::OutString ? 1 : wire_bytes(p.wire);
}

Record to_record(const PtrRecord& p, size_t elem) {
    Record r;
    r.tag = p.tag;
    r.count = p.count;
    r.value = p.value;
    if (p.tag == PtrTag::Data && p.data) r.data.assign(p.data, p.data + size_t(p.count) * elem);
    return r;
}

template <class T>
void put(std::vector<uint8_t>& o, T v) {
    const auto* b = reinterpret_cast<const uint8_t*>(&v);
    o.insert(o.end(), b, b + sizeof v);
}

void put_record(std::vector<uint8_t>& o, const Record& r) {
    put<uint8_t>(o, uint8_t(r.tag));
    switch (r.tag) {
    case PtrTag::Data:
        put<uint32_t>(o, r.count);
        o.insert(o.end(), r.data.begin(), r.data.end());
        break;
    case PtrTag::Offset:
    case PtrTag::ClientAddress: put<uint64_t>(o, r.value); break;
    default: break;
    }
}

struct Decoded {
    const CommandInfo* info = nullptr;
    std::vector<Param> params;
    Param ret;
};

// The same walk as decode_tuple, keeping every field.
bool decode(const Tuple& t, Decoded& d) {
    std::vector<uint8_t> raw;
    put<uint32_t>(raw, t.opcode);
    put<uint32_t>(raw, t.context);
    put<uint32_t>(raw, uint32_t(t.body.size()));
    raw.insert(raw.end(), t.body.begin(), t.body.end());
    ByteReader r(raw.data(), raw.size(), 0);
    Call c;
    try {
        decode_tuple(r, c);
    } catch (const DecodeError&) {
        return false;  // an earlier command already broke it
    }
    if (!c.info) return false;
    d.info = c.info;
    d.params.resize(c.info->param_count);
    for (uint16_t i = 0; i < c.info->param_count; ++i) {
        const ParamInfo& p = c.info->params[i];
        const Arg& a = c.args[i];
        Param& q = d.params[i];
        q.bits = a.bits;
        q.rec = to_record(a.ptr, elem_bytes(p));
        for (const PtrRecord& s : a.strings) q.list.push_back(to_record(s, wire_bytes(p.wire)));
        if (a.reply.tag == PtrTag::Data) q.reply = to_record(a.reply, elem_bytes(p));
    }
    if (c.info->has_ret) {
        d.ret.bits = c.ret.bits;
        const Wire w = c.info->ret.kind == ArgKind::Out ? Wire::U64 : c.info->ret.wire;
        d.ret.rec = to_record(c.ret.ptr, wire_bytes(w));
    }
    return true;
}

void put_value(std::vector<uint8_t>& o, const ParamInfo& p, uint64_t bits) {
    if (p.kind == ArgKind::Value) {
        const size_t n = wire_bytes(p.wire);
        const auto* b = reinterpret_cast<const uint8_t*>(&bits);
        o.insert(o.end(), b, b + n);
    } else {
        put<uint64_t>(o, bits);
    }
}

std::vector<uint8_t> encode(const Decoded& d) {
    std::vector<uint8_t> o;
    const CommandInfo& ci = *d.info;
    for (uint16_t i = 0; i < ci.param_count; ++i) {
        const ParamInfo& p = ci.params[i];
        const Param& q = d.params[i];
        switch (p.kind) {
        case ArgKind::Value:
        case ArgKind::Address: put_value(o, p, q.bits); break;
        case ArgKind::StringArray:
        case ArgKind::IndexArrays:
            put<uint32_t>(o, uint32_t(q.list.size()));
            for (const Record& r : q.list) put_record(o, r);
            break;
        default: put_record(o, q.rec); break;
        }
    }
    if (ci.has_ret) {
        if (ci.ret.kind == ArgKind::Value || ci.ret.kind == ArgKind::Address)
            put_value(o, ci.ret, d.ret.bits);
        else
            put_record(o, d.ret.rec);
    }
    for (uint16_t i = 0; i < ci.param_count; ++i) {
        const ParamInfo& p = ci.params[i];
        const Param& q = d.params[i];
        if ((p.kind == ArgKind::Out || p.kind == ArgKind::OutString) && q.rec.tag == PtrTag::Reply) {
            put<uint32_t>(o, q.reply.count);
            o.insert(o.end(), q.reply.data.begin(), q.reply.data.end());
        }
    }
    return o;
}

// --- values near the boundaries the replay must check -------------------------------------

uint64_t boundary(FuzzedDataProvider& in, uint64_t orig, const Decoded* d, Wire w) {
    const bool is_float = w == Wire::F32 || w == Wire::F64;
    const uint8_t pick = in.ConsumeIntegral<uint8_t>();
    if (is_float && pick % 2) {
        static const double f[] = {0.0, -1.0, 1e30, -1e30, 1e300, 3e9, -3e9, 1.0 / 0.0, 0.0 / 0.0, 2147483648.0};
        const double v = f[(pick / 2) % (sizeof f / sizeof f[0])];
        uint64_t bits = 0;
        if (w == Wire::F32) {
            const float x = float(v);
            std::memcpy(&bits, &x, sizeof x);
        } else {
            std::memcpy(&bits, &v, sizeof v);
        }
        return bits;
    }
    // A count shipped in one of the call's records: the value a size argument should agree with.
    uint64_t shipped = 0;
    if (d)
        for (const Param& q : d->params)
            if (q.rec.tag == PtrTag::Data) shipped = std::max<uint64_t>(shipped, q.rec.count);
    switch (pick % 20) {
    case 0: return 0;
    case 1: return 1;
    case 2: return ~uint64_t(0);  // -1 in every width
    case 3: return 0x7FFFFFFF;
    case 4: return 0x80000000u;
    case 5: return 1u << 28;
    case 6: return 0xFFFF;
    case 7: return 0x10000;
    case 8: return orig + 1;
    case 9: return orig - 1;
    case 10: return orig * 2 + 1;
    case 11: return orig * 1024;
    case 12: return shipped + 1;
    case 13: return shipped ? shipped - 1 : 0;
    case 14: return shipped * 8 + 1;
    case 15: return orig ^ (uint64_t(1) << (in.ConsumeIntegral<uint8_t>() % 32));
    case 16: return 0xFFFFFFF0u;
    case 17: {
        static const uint32_t enums[] = {0x0DE1, 0x1406, 0x1401, 0x1908, 0x8D40, 0x8892, 0x8893, 0x1403,
                                         0x1405, 0x140A, 0x1907, 0x0000, 0x0004, 0x8513, 0x806F, 0x8C1A};
        return enums[in.ConsumeIntegral<uint8_t>() % (sizeof enums / sizeof enums[0])];
    }
    case 18: return in.ConsumeIntegral<uint32_t>();
    default: return in.ConsumeIntegral<uint64_t>();
    }
}

// A new length for a record's data, in elements: truncated, a little more, or much more.
uint32_t new_count(FuzzedDataProvider& in, uint32_t count) {
    switch (in.ConsumeIntegral<uint8_t>() % 8) {
    case 0: return 0;
    case 1: return 1;
    case 2: return count / 2;
    case 3: return count ? count - 1 : 0;
    case 4: return count + 1;
    case 5: return count * 2 + 3;
    case 6: return 4096;
    default: return in.ConsumeIntegralInRange<uint32_t>(0, 65536);
    }
}

void resize_record(FuzzedDataProvider& in, Record& r, size_t elem) {
    const uint32_t n = new_count(in, r.count);
    const size_t cap = size_t(1) << 20;  // the input picks the size; keep one record under 1 MiB
    const uint32_t count = uint32_t(std::min<size_t>(n, cap / std::max<size_t>(elem, 1)));
    const size_t old = r.data.size();
    r.data.resize(size_t(count) * elem);
    // Grown data: 0xFF bytes are the worst indices, names and sizes a slave can be handed.
    const uint8_t fill = in.ConsumeBool() ? 0xFF : 0x00;
    for (size_t k = old; k < r.data.size(); ++k) r.data[k] = fill;
    r.count = count;
    r.tag = PtrTag::Data;
}

void retag(FuzzedDataProvider& in, Record& r, size_t elem, bool output) {
    static const uint64_t offsets[] = {0, 4, 0x10000, 0x7FFFFFFF, 0x80000000u, ~uint64_t(0), uint64_t(1) << 40};
    switch (in.ConsumeIntegral<uint8_t>() % 5) {
    case 0:
        if (!g_skip_null || output) r = Record{};
        break;
    case 1:
        if (r.tag != PtrTag::Data) r.count = 0, r.data.clear();
        resize_record(in, r, elem);
        break;
    case 2:
    case 3:
        r.tag = in.ConsumeBool() ? PtrTag::Offset : PtrTag::ClientAddress;
        r.value = offsets[in.ConsumeIntegral<uint8_t>() % (sizeof offsets / sizeof offsets[0])];
        r.count = 0;
        r.data.clear();
        break;
    default:
        if (output) r = Record{}, r.tag = PtrTag::Reply;
        break;
    }
}

// --- synthetic tuples: decoded with the generated reader, written back field by field ------

std::vector<uint8_t> encode(const SynthClientArrays& t) {
    std::vector<uint8_t> o;
    put<uint32_t>(o, uint32_t(t.arrays.size()));
    for (const auto& a : t.arrays) {
        put<uint8_t>(o, a.slot);
        put<uint32_t>(o, a.index);
        put<int32_t>(o, a.size);
        put<uint32_t>(o, a.type);
        put<int32_t>(o, a.stride);
        put<uint8_t>(o, a.normalized);
        put<uint8_t>(o, a.integer);
        put<uint32_t>(o, a.handle);
        put<uint32_t>(o, a.first_byte);
        put<uint8_t>(o, a.cached);
        if (!a.cached) {
            put<uint32_t>(o, a.data_bytes);
            o.insert(o.end(), a.data, a.data + a.data_bytes);
        }
    }
    return o;
}

Call synthetic_call(const Tuple& t) {
    Call c;
    c.opcode = t.opcode;
    c.context = t.context;
    c.body = t.body.data();
    c.body_bytes = uint32_t(t.body.size());
    return c;
}

std::deque<std::vector<uint8_t>> g_scratch;  // data that mutated synthetic items point into

bool mutate_synthetic(FuzzedDataProvider& in, Tuple& t, std::string& what) {
    const Call c = synthetic_call(t);
    const uint8_t field = in.ConsumeIntegral<uint8_t>();
    try {
        switch (t.opcode) {
        case kSynthClientArrays: {
            SynthClientArrays s;
            read_synthetic(c, s);
            if (s.arrays.empty()) return false;
            auto& a = s.arrays[in.ConsumeIntegral<uint8_t>() % s.arrays.size()];
            const uint64_t v = boundary(in, 0, nullptr, Wire::U32);
            static const char* names[] = {"slot", "index", "size", "type", "stride", "handle", "first_byte",
                                          "cached", "data", "duplicate item"};
            switch (field % 10) {
            case 0: a.slot = uint8_t(v); break;
            case 1: a.index = uint32_t(v); break;
            case 2: a.size = int32_t(v); break;
            case 3: a.type = uint32_t(v); break;
            case 4: a.stride = int32_t(v); break;
            case 5: a.handle = uint32_t(v); break;
            case 6: a.first_byte = uint32_t(v); break;
            case 7:
                a.cached = !a.cached;
                if (!a.cached) a.data = nullptr, a.data_bytes = 0;
                break;
            case 8: {
                Record r;
                r.count = a.data_bytes;
                if (a.data) r.data.assign(a.data, a.data + a.data_bytes);
                resize_record(in, r, 1);
                g_scratch.push_back(std::move(r.data));
                a.data = g_scratch.back().data();
                a.data_bytes = uint32_t(g_scratch.back().size());
                a.cached = 0;
                break;
            }
            default: s.arrays.push_back(a); break;
            }
            what = std::string("client_arrays.") + names[field % 10] + " = " + std::to_string(int64_t(int32_t(v)));
            t.body = encode(s);
            return true;
        }
        case kSynthBufferWrite: {
            SynthBufferWrite s;
            read_synthetic(c, s);
            Record r;
            r.count = s.data_bytes;
            if (s.data) r.data.assign(s.data, s.data + s.data_bytes);
            r.tag = s.data_present ? PtrTag::Data : PtrTag::Null;
            switch (field % 4) {
            case 0: s.buffer = uint32_t(boundary(in, s.buffer, nullptr, Wire::U32)); what = "buffer_write.buffer"; break;
            case 1: s.offset = boundary(in, s.offset, nullptr, Wire::U64); what = "buffer_write.offset"; break;
            case 2: resize_record(in, r, 1); what = "buffer_write.data size " + std::to_string(r.count); break;
            default: r = Record{}; what = "buffer_write.data absent"; break;
            }
            std::vector<uint8_t> o;
            put<uint32_t>(o, s.buffer);
            put<uint64_t>(o, s.offset);
            put<uint8_t>(o, r.tag == PtrTag::Data ? 1 : 0);
            if (r.tag == PtrTag::Data) {
                put<uint32_t>(o, r.count);
                o.insert(o.end(), r.data.begin(), r.data.end());
            }
            t.body = std::move(o);
            return true;
        }
        case kSynthDrawableSize: {
            SynthDrawableSize s;
            read_synthetic(c, s);
            const uint64_t v = boundary(in, 0, nullptr, Wire::I32);
            switch (field % 3) {
            case 0: s.drawable = v; what = "drawable_size.drawable"; break;
            case 1: s.width = int32_t(v); what = "drawable_size.width = " + std::to_string(s.width); break;
            default: s.height = int32_t(v); what = "drawable_size.height = " + std::to_string(s.height); break;
            }
            std::vector<uint8_t> o;
            put<uint64_t>(o, s.drawable);
            put<int32_t>(o, s.width);
            put<int32_t>(o, s.height);
            t.body = std::move(o);
            return true;
        }
        case kSynthContext: {
            SynthContext s;
            read_synthetic(c, s);
            const uint64_t v = boundary(in, 0, nullptr, Wire::U32);
            switch (field % 4) {
            case 0: s.id = uint32_t(v); what = "context.id = " + std::to_string(s.id); break;
            case 1: s.handle = v; what = "context.handle"; break;
            case 2: s.share = uint32_t(v); what = "context.share = " + std::to_string(s.share); break;
            default: s.api = uint8_t(v); what = "context.api = " + std::to_string(s.api); break;
            }
            std::vector<uint8_t> o;
            put<uint32_t>(o, s.id);
            put<uint64_t>(o, s.handle);
            put<uint32_t>(o, s.share);
            put<uint8_t>(o, s.api);
            t.body = std::move(o);
            return true;
        }
        default: return false;
        }
    } catch (const DecodeError&) {
        return false;
    }
}

const char* opcode_name(uint32_t op) {
    if (op >= kSynthBase) {
        const char* n = synthetic_name(op);
        return n ? n : "glcast.?";
    }
    const CommandInfo* ci = command_info(op);
    return ci ? ci->name : "?";
}

// Mutation kinds. Value and record changes pick among the call's parameters of that kind, so
// that a command byte is rarely wasted on a call without one.
enum Kind : uint8_t { kValue, kRecordSize, kRecordTag, kReplySize, kListSize, kSynthetic, kDuplicate, kDrop, kSwap,
                      kContextId, kDataByte, kKinds };

void apply(FuzzedDataProvider& in, std::vector<Tuple>& tuples) {
    const uint8_t kind = in.ConsumeIntegral<uint8_t>() % kKinds;
    if (tuples.empty()) return;
    const size_t index = in.ConsumeIntegral<uint16_t>() % tuples.size();
    Tuple& t = tuples[index];
    const uint32_t opcode = t.opcode;  // `t` dangles once a tuple is inserted or erased
    std::string what;
    switch (kind) {
    case kDuplicate: tuples.insert(tuples.begin() + long(index), Tuple(t)); what = "duplicated"; break;
    case kDrop: tuples.erase(tuples.begin() + long(index)); what = "dropped"; break;
    case kSwap:
        if (index + 1 < tuples.size()) std::swap(tuples[index], tuples[index + 1]);
        what = "swapped with the next";
        break;
    case kContextId: {
        static const uint32_t ids[] = {0, 1, 2, 3, 0xFFFFFFFF};
        t.context = ids[in.ConsumeIntegral<uint8_t>() % 5];
        what = "context = " + std::to_string(t.context);
        break;
    }
    case kSynthetic:
        if (t.opcode < kSynthBase || !mutate_synthetic(in, t, what)) return;
        break;
    default: {
        if (t.opcode >= kSynthBase) {
            if (!mutate_synthetic(in, t, what)) return;
            break;
        }
        Decoded d;
        if (!decode(t, d)) return;
        const CommandInfo& ci = *d.info;
        std::vector<int> candidates;
        for (uint16_t i = 0; i < ci.param_count; ++i) {
            const ArgKind k = ci.params[i].kind;
            const bool value = k == ArgKind::Value;
            const bool list = k == ArgKind::StringArray || k == ArgKind::IndexArrays;
            const bool out = k == ArgKind::Out || k == ArgKind::OutString;
            const bool rec = !value && k != ArgKind::Address && !list;
            if ((kind == kValue && value) || ((kind == kRecordSize || kind == kRecordTag || kind == kDataByte) && rec) ||
                (kind == kReplySize && out && d.params[i].rec.tag == PtrTag::Reply) || (kind == kListSize && list))
                candidates.push_back(i);
        }
        if (candidates.empty()) return;
        const int i = candidates[in.ConsumeIntegral<uint8_t>() % candidates.size()];
        const ParamInfo& p = ci.params[i];
        Param& q = d.params[size_t(i)];
        what = std::string(p.name) + ": ";
        switch (kind) {
        case kValue:
            q.bits = boundary(in, q.bits, &d, p.wire);
            what += "value " + std::to_string(int64_t(q.bits));
            break;
        case kRecordSize:
            resize_record(in, q.rec, elem_bytes(p));
            what += "data of " + std::to_string(q.rec.count) + " elements";
            break;
        case kRecordTag:
            retag(in, q.rec, elem_bytes(p), p.kind == ArgKind::Out || p.kind == ArgKind::OutString);
            if (q.rec.tag == PtrTag::Reply && q.reply.tag != PtrTag::Data) q.reply = Record{}, q.reply.tag = PtrTag::Data;
            what += "tag " + std::to_string(int(q.rec.tag)) + " value " + std::to_string(q.rec.value) + " count " +
                    std::to_string(q.rec.count);
            break;
        case kReplySize:
            resize_record(in, q.reply, elem_bytes(p));
            what += "reply of " + std::to_string(q.reply.count) + " elements";
            break;
        case kListSize: {
            const uint32_t n = std::min<uint32_t>(new_count(in, uint32_t(q.list.size())), 4096);
            Record fill = q.list.empty() ? Record{} : q.list.back();
            q.list.resize(n, fill);
            what += "list of " + std::to_string(n);
            break;
        }
        default:  // kDataByte
            if (q.rec.data.empty()) return;
            q.rec.data[in.ConsumeIntegral<uint32_t>() % q.rec.data.size()] = in.ConsumeIntegral<uint8_t>();
            what += "data byte";
            break;
        }
        t.body = encode(d);
        break;
    }
    }
    if (g_verbose) std::fprintf(stderr, "fuzz_replay: tuple %zu %s: %s\n", index, opcode_name(opcode), what.c_str());
}

// Framed messages straight to the replayer: no header checks, CRC or zstd in the way.
class MemoryMessages : public MessageSource {
public:
    std::vector<Message> messages;
    bool next(Message& m) override {
        if (pos_ >= messages.size()) return false;
        m = std::move(messages[pos_++]);
        return true;
    }

private:
    size_t pos_ = 0;
};

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
    g_verbose = std::getenv("GLCAST_FUZZ_VERBOSE") != nullptr;
    const char* skip = std::getenv("GLCAST_FUZZ_SKIP");
    g_skip_null = skip && std::strstr(skip, "null");
    // llvmpipe's rasterizer threads would take the cores other jobs share, and make a run's
    // scheduling (and a crash's reproduction) depend on the machine.
    setenv("LP_NUM_THREADS", "0", 0);
    load_captures();
    std::string error;
    auto backend = slave::make_backend("egl", error);
    if (!backend) {
        std::fprintf(stderr, "fuzz_replay: no EGL backend: %s\n", error.c_str());
        std::abort();
    }
    // One replayer for the whole run: creating the EGL display costs far more than one input.
    // GLCAST_FUZZ_EFFECTS=shadows,cover,...: with the injected passes, so that the frame recorder
    // (what it keeps, borrows from another context, redraws) meets the mutated streams too.
    slave::ReplayOptions options;
    if (const char* effects = std::getenv("GLCAST_FUZZ_EFFECTS"); effects && *effects) {
        std::string error;
        if (!options.effects.enable(effects, error)) {
            std::fprintf(stderr, "fuzz_replay: GLCAST_FUZZ_EFFECTS: %s\n", error.c_str());
            std::abort();
        }
    }
    g_replayer = std::make_unique<slave::Replayer>(std::move(backend), options);
    return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    if (size == 0) return 0;
    FuzzedDataProvider in(data, size);
    const Capture& cap = g_captures[in.ConsumeIntegral<uint8_t>() % g_captures.size()];
    if (g_verbose) std::fprintf(stderr, "fuzz_replay: capture %s, %zu tuples\n", cap.name.c_str(), cap.tuples.size());
    std::vector<Tuple> tuples = cap.tuples;
    g_scratch.clear();
    for (int k = 0; k < 64 && in.remaining_bytes(); ++k) apply(in, tuples);

    MemoryMessages src;
    for (size_t i = 0; i < tuples.size();) {
        const uint32_t msg = tuples[i].message;
        Message m;
        m.header.magic = kMessageMagic;
        m.header.flags = cap.messages[msg].flags;
        m.header.frame = cap.messages[msg].frame;
        m.header.sequence = src.messages.size();
        for (; i < tuples.size() && tuples[i].message == msg; ++i) {
            put<uint32_t>(m.payload, tuples[i].opcode);
            put<uint32_t>(m.payload, tuples[i].context);
            put<uint32_t>(m.payload, uint32_t(tuples[i].body.size()));
            m.payload.insert(m.payload.end(), tuples[i].body.begin(), tuples[i].body.end());
        }
        m.header.raw_bytes = m.header.stored_bytes = uint32_t(m.payload.size());
        src.messages.push_back(std::move(m));
    }
    try {
        g_replayer->replay(src);
    } catch (const DecodeError&) {
    } catch (const slave::ReplayError&) {
    } catch (const slave::EffectsError&) {
    } catch (const GlMissing&) {
    }
    g_replayer->reset();
    return 0;
}
