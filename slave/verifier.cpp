#include "slave/verifier.h"

#include <cinttypes>
#include <cstdio>
#include <cstring>

#include "slave/replayer.h"

namespace glcast::slave {

bool Verifier::wants(uint32_t opcode, const CommandInfo* info) const {
    return info && kReplayKind[opcode] == ReplayKind::ReplyOnly;
}

bool Verifier::replace_call(const Call& c) {
    core_.stats().reply_only++;
    if (!kVerify[c.opcode]) return true;
    core_.current();
    checking_ = true;
    try {
        kVerify[c.opcode](core_, c);
    } catch (...) {
        checking_ = false;
        throw;
    }
    checking_ = false;
    return true;
}

void Verifier::mismatch(const Call& c, const std::string& what) {
    core_.stats().mismatches++;
    std::fprintf(stderr, "glcast replay --verify: frame %" PRIu64 ", call %" PRIu64 ": %s: %s\n", core_.frame(), core_.call_index(),
                 c.info->name, what.c_str());
}

void Verifier::check_reply(const Call& c, int i, const void* slave_output, int64_t slave_elements) {
    const Arg& a = c.args[size_t(i)];
    if (!checking_ || a.ptr.tag != PtrTag::Reply || !slave_output) return;
    // A headless slave's window framebuffer is single-buffered: these answers describe the
    // slave's window system, not the replay, and are not compared there.
    if (!core_.current().double_buffered && (c.info->sem.flags & kSemWindowQuery) &&
        is_window_system_pname(uint32_t(c.args[0].bits)))
        return;
    core_.stats().verified++;
    const ParamInfo& p = c.info->params[i];
    const size_t unit = p.kind == ArgKind::OutString ? 1 : wire_bytes(p.wire);
    // The slave's output holds what the slave computed the call writes; a reply that says more
    // is compared no further than that.
    if (p.kind != ArgKind::OutString && int64_t(a.reply.count) != slave_elements)
        return mismatch(c, std::string(p.name) + ": the master's reply has " + std::to_string(a.reply.count) +
                               " elements, the slave's state says the call writes " + std::to_string(slave_elements));
    if (int64_t(a.reply.count) > slave_elements)
        return mismatch(c, std::string(p.name) + ": the master's reply has " + std::to_string(a.reply.count) +
                               " bytes, more than the " + std::to_string(slave_elements) + " the call may write");
    const size_t bytes = a.reply.count * unit;
    if (std::memcmp(slave_output, a.reply.data, bytes) == 0) return;
    if (same_object(c, a, p, slave_output)) return;
    size_t first = 0;
    const auto* s = static_cast<const uint8_t*>(slave_output);
    while (first < bytes && s[first] == a.reply.data[first]) ++first;
    mismatch(c, std::string(p.name) + " differs from the master's reply from byte " + std::to_string(first) + " of " +
                    std::to_string(bytes));
}

// An answer that names an object (semantics.yaml name_pnames) is the slave's name for it: the
// master's answer is compared through the context's name map. (kSemWindowQuery marks the glGet*v
// family, semantics.yaml window_system_pnames.commands; an integer answer is glGetIntegerv's or
// glGetInteger64v's.)
bool Verifier::same_object(const Call& c, const Arg& a, const ParamInfo& p, const void* slave_output) {
    if (!(c.info->sem.flags & kSemWindowQuery) || a.reply.count != 1 || (p.wire != Wire::I32 && p.wire != Wire::I64))
        return false;
    const Ns ns = name_pname_namespace(uint32_t(c.args[0].bits));
    if (ns == Ns::none) return false;
    int64_t master = 0, slave = 0;
    if (p.wire == Wire::I32) {
        int32_t m, s;
        std::memcpy(&m, a.reply.data, 4), std::memcpy(&s, slave_output, 4);
        master = m, slave = s;
    } else {
        std::memcpy(&master, a.reply.data, 8), std::memcpy(&slave, slave_output, 8);
    }
    uint64_t mapped = 0;
    return master > 0 && core_.current().names.map(ns).find(uint64_t(master), mapped) && int64_t(mapped) == slave;
}

void Verifier::check_return(const Call& c, uint64_t slave_value) {
    if (!checking_) return;
    core_.stats().verified++;
    const uint64_t mask = wire_bytes(c.info->ret.wire) >= 8 ? ~0ull : (1ull << (8 * wire_bytes(c.info->ret.wire))) - 1;
    if ((slave_value & mask) != (c.ret.bits & mask))
        mismatch(c, "returned " + std::to_string(slave_value & mask) + ", the master got " + std::to_string(c.ret.bits & mask));
}

void Verifier::check_return_string(const Call& c, const char* slave_value) {
    if (!checking_) return;
    core_.stats().verified++;
    const PtrRecord& r = c.ret.ptr;
    const std::string master = r.tag == PtrTag::Data ? std::string(reinterpret_cast<const char*>(r.data), r.count) : "";
    if (master != (slave_value ? slave_value : ""))
        mismatch(c, "returned \"" + std::string(slave_value ? slave_value : "") + "\", the master got \"" + master + "\"");
}

}  // namespace glcast::slave
