// The master's stream taken by several threads at once: the program's threads append tuples under
// the open batch's lock (common/spin_lock.h) while one of them ends frames and another flushes,
// and the writer compresses behind a queue of two. Every tuple must arrive once, each thread's in
// the order it appended them, and the counts must add up.
#include <gtest/gtest.h>

#include <cstring>
#include <thread>
#include <vector>

#include "master/stream.h"
#include "protocol/decoder.h"
#include "protocol/format.h"
#include "tests/unit/memory_sink.h"

namespace glcast {
namespace {

struct Tagged {
    uint32_t opcode, context, body, thread, counter;
};

}  // namespace

TEST(StreamThreads, EveryThreadsTuplesArriveOnceAndInItsOrder) {
    constexpr uint32_t kThreads = 4, kTuples = 40000;
    std::vector<std::vector<uint8_t>> messages;
    std::vector<std::unique_ptr<MessageSink>> sinks;
    sinks.push_back(std::make_unique<MemorySink>(messages));
    Stream stream(std::move(sinks), 1, 2, true);
    std::vector<std::thread> threads;
    for (uint32_t t = 0; t < kThreads; ++t)
        threads.emplace_back([&stream, t] {
            for (uint32_t i = 0; i < kTuples; ++i) {
                const Tagged tuple{1, t + 1, 8, t, i};
                stream.append(reinterpret_cast<const uint8_t*>(&tuple), sizeof tuple);
                if (t == 0 && i % 1000 == 999) stream.end_frame();
                if (t == 1 && i % 7919 == 0) stream.flush();
            }
        });
    for (auto& th : threads) th.join();
    stream.close();

    std::vector<uint32_t> next(kThreads, 0);
    MessageChain chain;
    Message m;
    uint64_t tuples = 0;
    for (const auto& bytes : messages) {
        decode_message(bytes.data(), bytes.size(), 0, m, &chain);
        ASSERT_EQ(m.payload.size() % sizeof(Tagged), 0u);
        for (size_t at = 0; at < m.payload.size(); at += sizeof(Tagged)) {
            Tagged tuple;
            std::memcpy(&tuple, m.payload.data() + at, sizeof tuple);
            ASSERT_LT(tuple.thread, kThreads);
            ASSERT_EQ(tuple.counter, next[tuple.thread]) << "thread " << tuple.thread;
            next[tuple.thread]++;
            tuples++;
        }
    }
    for (uint32_t t = 0; t < kThreads; ++t) EXPECT_EQ(next[t], kTuples) << "thread " << t;
    const StreamStats stats = stream.stats();
    EXPECT_EQ(stats.tuples, uint64_t(kThreads) * kTuples);
    EXPECT_EQ(tuples, stats.tuples);
    EXPECT_EQ(stats.frames, kTuples / 1000);
    EXPECT_EQ(stats.raw_bytes, stats.tuples * sizeof(Tagged));
}

}  // namespace glcast
