#include "keeper/trim.h"

#include <chrono>
#include <cstring>

#include "keeper/kept_calls.h"
#include "master/stream.h"
#include "protocol/decoder.h"
#include "protocol/format.h"
#include "slave/replayer.h"

namespace glcast::keeper {

bool append_message(Stream& out, const Message& m) {
    for (size_t at = 0; at + kTupleHeaderBytes <= m.payload.size();) {
        uint32_t body = 0;
        std::memcpy(&body, m.payload.data() + at + 8, 4);
        if (body > m.payload.size() - at - kTupleHeaderBytes)
            throw DecodeError(m.offset, "message " + std::to_string(m.header.sequence) + ": a tuple runs past its end");
        out.append(m.payload.data() + at, kTupleHeaderBytes + body);
        at += kTupleHeaderBytes + body;
    }
    if (!(m.header.flags & kMsgFrameEnd)) return false;
    out.end_frame();
    return true;
}

TrimResult trim_capture(MessageSource& in, uint64_t first, uint64_t last, std::unique_ptr<slave::Backend> backend,
                        const std::string& out_path) {
    TrimResult result;
    slave::ReplayOptions options;
    options.last_frame = first ? first - 1 : 0;
    slave::Replayer keeper(std::move(backend), options);
    KeptCalls kept(keeper);
    keeper.watch(&kept);
    if (first) keeper.replay(in);  // stops after the swap that ends frame first - 1
    result.replayed_frames = keeper.stats().frames;
    result.keeper_errors = keeper.stats().errors;

    std::vector<std::unique_ptr<MessageSink>> sinks;
    sinks.push_back(std::make_unique<CaptureFileSink>(out_path));
    Stream out(std::move(sinks), 1, 4);
    const auto start = std::chrono::steady_clock::now();
    result.snapshot = write_snapshot(keeper, kept, [&](const uint8_t* t, size_t n) { out.append(t, n); });
    result.snapshot_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    Message m;
    while (in.next(m)) {
        if (m.header.frame > last) break;
        if (append_message(out, m)) {
            result.frames++;
            if (m.header.frame >= last) break;
        }
    }
    out.close();
    return result;
}

}  // namespace glcast::keeper
