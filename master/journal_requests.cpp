#include "master/journal_requests.h"

#include <algorithm>

namespace glcast {

const char* journal_drop_name(JournalDrop d) {
    switch (d) {
    case JournalDrop::none: return "none";
    case JournalDrop::parts: return "parts";
    case JournalDrop::identity: return "identity";
    case JournalDrop::size: return "size";
    case JournalDrop::unknown: return "unknown";
    case JournalDrop::rate: return "rate";
    case JournalDrop::busy: return "busy";
    case JournalDrop::no_lockstep: return "no-lockstep";
    case JournalDrop::window: return "window";
    case JournalDrop::count_: break;
    }
    return "?";
}

JournalRequest classify_journal_request(const std::string_view* parts, size_t count) {
    using namespace journal_limits;
    JournalRequest r;
    if (count != 2) {
        r.drop = JournalDrop::parts;
        return r;
    }
    if (parts[0].empty() || parts[0].size() > kMaxIdentityBytes) {
        r.drop = JournalDrop::identity;
        return r;
    }
    const std::string_view body = parts[1];
    if (body.size() > kMaxRequestBytes) {
        r.drop = JournalDrop::size;
        return r;
    }
    if (body == "SNAPSHOT") {
        r.kind = JournalRequestKind::snapshot;
        return r;
    }
    r.drop = JournalDrop::unknown;
    // "WORD n": n decimal as std::to_string writes it (no sign, no leading zero), at most `max`.
    struct Form {
        std::string_view word;
        JournalRequestKind kind;
        uint64_t max;
    };
    static constexpr Form forms[] = {{"SNAPSHOT AT ", JournalRequestKind::snapshot_at, UINT32_MAX},
                                     {"SINCE ", JournalRequestKind::since, UINT64_MAX},
                                     {"DONE ", JournalRequestKind::done, UINT32_MAX}};
    for (const Form& f : forms) {
        if (body.size() <= f.word.size() || body.substr(0, f.word.size()) != f.word) continue;
        const std::string_view digits = body.substr(f.word.size());
        if (digits.size() > 20 || (digits.size() > 1 && digits[0] == '0')) return r;
        uint64_t n = 0;
        for (char c : digits) {
            if (c < '0' || c > '9') return r;
            if (n > (f.max - uint64_t(c - '0')) / 10) return r;  // past the form's maximum
            n = n * 10 + uint64_t(c - '0');
        }
        r.kind = f.kind;
        r.drop = JournalDrop::none;
        (f.kind == JournalRequestKind::since ? r.sequence : r.frame) = n;
        return r;
    }
    return r;
}

bool JournalAdmission::Bucket::full(double burst, double rate, double now) const {
    return tokens < 0 || tokens + (now - last) * rate >= burst;
}

bool JournalAdmission::Bucket::take(double burst, double rate, double now) {
    if (tokens < 0) {
        tokens = burst;
        last = now;
    }
    if (now > last) tokens = std::min(burst, tokens + (now - last) * rate);
    last = std::max(last, now);  // a clock that goes back refills nothing
    if (tokens < 1) return false;
    tokens -= 1;
    return true;
}

bool JournalAdmission::admit(std::string_view identity, JournalRequestKind kind, double now) {
    using namespace journal_limits;
    if (kind == JournalRequestKind::invalid) return false;
    auto it = peers_.find(std::string(identity));
    if (it == peers_.end()) {
        if (peers_.size() >= kMaxPeers) {
            // A peer whose buckets have refilled is the same as one never seen: forget it.
            for (auto p = peers_.begin(); p != peers_.end();)
                p = p->second.snapshot.full(kSnapshotBurstPerPeer, kSnapshotRatePerPeer, now) &&
                            p->second.done.full(kDoneBurstPerPeer, kDoneRatePerPeer, now)
                        ? peers_.erase(p)
                        : std::next(p);
            if (peers_.size() >= kMaxPeers) return false;
        }
        it = peers_.emplace(std::string(identity), Peer{}).first;
    }
    // The peer's bucket first, so that one peer's flood does not drain everyone's. SINCE
    // sends messages as SNAPSHOT does, and shares its buckets.
    if (kind == JournalRequestKind::snapshot || kind == JournalRequestKind::since ||
        kind == JournalRequestKind::snapshot_at)
        return it->second.snapshot.take(kSnapshotBurstPerPeer, kSnapshotRatePerPeer, now) &&
               snapshot_total_.take(kSnapshotBurstTotal, kSnapshotRateTotal, now);
    return it->second.done.take(kDoneBurstPerPeer, kDoneRatePerPeer, now) &&
           done_total_.take(kDoneBurstTotal, kDoneRateTotal, now);
}

}  // namespace glcast
