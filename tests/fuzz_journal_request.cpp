// libFuzzer target: any sequence of multi-part messages on the journal channel is classified
// without reading past a part (every part lives in a buffer of exactly its size, under ASan),
// a request is accepted only in one of its documented forms, and the admission state stays
// bounded however many identities ask.
#include <fuzzer/FuzzedDataProvider.h>

#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "master/journal_requests.h"

using namespace glcast;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    FuzzedDataProvider in(data, size);
    JournalAdmission admission;
    double now = 0;
    while (in.remaining_bytes() > 0) {
        const size_t count = in.ConsumeIntegralInRange<size_t>(0, 12);
        std::vector<std::unique_ptr<char[]>> storage;
        std::vector<std::string_view> parts;
        for (size_t i = 0; i < count; i++) {
            const std::string s = in.ConsumeRandomLengthString(300);
            storage.emplace_back(new char[s.size() ? s.size() : 1]);
            std::memcpy(storage.back().get(), s.data(), s.size());
            parts.emplace_back(storage.back().get(), s.size());
        }
        const JournalRequest r = classify_journal_request(parts.data(), parts.size());
        switch (r.kind) {
        case JournalRequestKind::snapshot:
            if (count != 2 || parts[0].empty() || parts[1] != "SNAPSHOT") std::abort();
            break;
        case JournalRequestKind::done:
            // The one spelling std::to_string gives, of a 32-bit frame number.
            if (count != 2 || parts[0].empty() || r.frame > UINT32_MAX ||
                std::string(parts[1]) != "DONE " + std::to_string(r.frame))
                std::abort();
            break;
        case JournalRequestKind::since:
            if (count != 2 || parts[0].empty() || std::string(parts[1]) != "SINCE " + std::to_string(r.sequence)) std::abort();
            break;
        case JournalRequestKind::snapshot_at:
            if (count != 2 || parts[0].empty() || std::string(parts[1]) != "SNAPSHOT AT " + std::to_string(r.frame))
                std::abort();
            break;
        case JournalRequestKind::invalid:
            if (r.drop == JournalDrop::none) std::abort();
            break;
        }
        now += in.ConsumeIntegralInRange<int>(-10, 2000) / 1000.0;
        if (r.kind != JournalRequestKind::invalid) admission.admit(parts[0], r.kind, now);
        if (admission.peers() > journal_limits::kMaxPeers) std::abort();
    }
    return 0;
}
