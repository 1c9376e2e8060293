// Inter-frame coding (format version 2, docs/stream-format.md): messages compressed against the
// previous message's payload, key messages, and the readers' refusals of what they cannot read.
#include <gtest/gtest.h>
#include <zstd.h>
#include <unistd.h>
#include <zlib.h>

#include <cstring>
#include <fstream>
#include <iterator>
#include <random>

#include "common/xor_bytes.h"
#include "master/stream.h"
#include "protocol/decoder.h"
#include "protocol/format.h"
#include "tests/unit/memory_sink.h"

namespace glcast {
namespace {

// Frames that repeat with small changes, as an immediate-mode program's do: one tuple each of a
// fake opcode with 40 KB of floats, a few of them moved a little, or (moving) all of them.
std::vector<std::vector<uint8_t>> frames_of_a_program(int frames, bool moving = false) {
    std::vector<std::vector<uint8_t>> out;
    std::mt19937 random(3);
    std::vector<float> vertices(10000);
    for (float& v : vertices) v = float(random() % 1000) / 7.0f;
    for (int f = 0; f < frames; f++) {
        for (int k = 0; k < 40; k++) vertices[random() % vertices.size()] += 0.5f;  // a little moves
        if (moving)
            for (size_t i = 0; i < vertices.size(); i++) vertices[i] += 0.001f * float((i * 7 + f) % 5);
        std::vector<uint8_t> tuple(kTupleHeaderBytes + vertices.size() * 4);
        const uint32_t opcode = 1, context = 1, body = uint32_t(vertices.size() * 4);
        std::memcpy(tuple.data(), &opcode, 4);
        std::memcpy(tuple.data() + 4, &context, 4);
        std::memcpy(tuple.data() + 8, &body, 4);
        std::memcpy(tuple.data() + kTupleHeaderBytes, vertices.data(), body);
        out.push_back(tuple);
    }
    return out;
}

std::vector<std::vector<uint8_t>> encode(const std::vector<std::vector<uint8_t>>& frames, bool inter_frame,
                                         StreamStats* stats = nullptr) {
    std::vector<std::vector<uint8_t>> messages;
    std::vector<std::unique_ptr<MessageSink>> sinks;
    sinks.push_back(std::make_unique<MemorySink>(messages));
    Stream stream(std::move(sinks), 1, 4, inter_frame);
    for (const auto& f : frames) {
        stream.append(f.data(), f.size());
        stream.end_frame();
    }
    stream.close();
    if (stats) *stats = stream.stats();
    return messages;
}

MessageHeader header_of(const std::vector<uint8_t>& m) {
    MessageHeader h;
    std::memcpy(&h, m.data(), sizeof h);
    return h;
}

size_t total(const std::vector<std::vector<uint8_t>>& messages) {
    size_t n = 0;
    for (const auto& m : messages) n += m.size();
    return n;
}

std::vector<uint8_t> as_file(const std::vector<std::vector<uint8_t>>& messages, uint32_t version) {
    FileHeader h = make_file_header();
    h.version = version;
    std::vector<uint8_t> file(reinterpret_cast<const uint8_t*>(&h), reinterpret_cast<const uint8_t*>(&h) + sizeof h);
    for (const auto& m : messages) file.insert(file.end(), m.begin(), m.end());
    return file;
}

std::string error_reading(const std::vector<uint8_t>& file) {
    try {
        CaptureReader reader(memory_source(file.data(), file.size()));
        Message m;
        while (reader.next(m)) {
        }
    } catch (const DecodeError& e) {
        return e.what();
    }
    return "";
}

}  // namespace

TEST(InterFrame, SmallerAndReadBackExactly) {
    const auto frames = frames_of_a_program(150);
    const auto alone = encode(frames, false), coded = encode(frames, true);
    ASSERT_EQ(alone.size(), coded.size());
    size_t keys = 0, xored = 0;
    for (const auto& m : coded) {
        const MessageHeader h = header_of(m);
        const bool key = !(h.flags & (kMsgDelta | kMsgXor));
        keys += key;
        xored += (h.flags & kMsgXor) != 0;
        EXPECT_EQ(key, h.sequence % kKeyIntervalMessages == 0 || !(h.flags & kMsgCompressed)) << h.sequence;
    }
    EXPECT_GE(keys, 3u);  // 0, 64, 128 (and the empty end-of-frame messages, stored)
    size_t moving_xored = 0;
    for (const auto& m : encode(frames_of_a_program(20, true), true)) moving_xored += (header_of(m).flags & kMsgXor) != 0;
    EXPECT_GT(moving_xored, 15u);  // frames of one length whose numbers all moved: XORed with the last
    EXPECT_LT(total(coded) * 4, total(alone)) << "coded " << total(coded) << ", alone " << total(alone);

    const std::vector<uint8_t> file = as_file(coded, kFormatVersion);
    CaptureReader reader(memory_source(file.data(), file.size()));
    Message m;
    size_t f = 0;
    while (reader.next(m))
        if (!m.payload.empty()) {
            ASSERT_LT(f, frames.size());
            EXPECT_EQ(m.payload, frames[f]) << "frame " << f;
            f++;
        }
    EXPECT_EQ(f, frames.size());
}

// Moving numbers XORed with the last frame are runs of zeros between a few changed bytes; on
// many programs zstd's lazy match finder (level 5) finds far more there than level 1's greedy
// one. The writer probes both and keeps the lazy level while it saves a tenth. The frames of
// the committed ff_scene capture (a fixed-function scene whose vertices move): its XORed frame
// stores less than half of what level 1 would.
// The payloads of the committed ff_scene capture (a fixed-function scene whose vertices move).
static std::vector<std::vector<uint8_t>> ff_scene_payloads() {
    CaptureReader reader(open_file_source(GLCAST_SOURCE_DIR "/tests/data/ff_scene.glcs"));
    std::vector<std::vector<uint8_t>> payloads;
    Message m;
    while (reader.next(m))
        if (!m.payload.empty()) payloads.push_back(m.payload);
    return payloads;
}

TEST(InterFrame, XorResidualsAreCompressedWithTheLazyMatchFinderWhereItPays) {
    const std::vector<std::vector<uint8_t>> frames = ff_scene_payloads();
    ASSERT_GE(frames.size(), 3u);
    const auto coded = encode(frames, true);
    size_t stored = 0, greedy = 0;
    std::vector<uint8_t> residual, out;
    for (const auto& message : coded) {
        const MessageHeader h = header_of(message);
        if (!(h.flags & kMsgXor)) continue;
        const std::vector<uint8_t>& raw = frames[h.sequence];
        const std::vector<uint8_t>& previous = frames[h.sequence - 1];
        ASSERT_EQ(raw.size(), h.raw_bytes);
        residual.resize(raw.size());
        for (size_t i = 0; i < raw.size(); i++) residual[i] = raw[i] ^ previous[i];
        out.resize(ZSTD_compressBound(residual.size()));
        greedy += ZSTD_compress(out.data(), out.size(), residual.data(), residual.size(), 1);
        stored += h.stored_bytes;
    }
    ASSERT_GT(greedy, 0u) << "no frame was XORed";
    EXPECT_LT(stored * 2, greedy) << "stored " << stored << ", level 1 would store " << greedy;
}

// A program whose frames XOR far better than the prefix codes them does so frame after frame:
// the writer stops compressing each such frame both ways (it did: 2 zstd runs a message on
// ff_scene's flag frames) and probes the prefix coding only now and then, for the same bytes.
TEST(InterFrame, SteadyXorFramesAreCompressedOnceEach) {
    const std::vector<std::vector<uint8_t>> first = ff_scene_payloads();
    ASSERT_GE(first.size(), 3u);
    // 48 frames: the capture's last frames again and again, the flag waving between two of them.
    std::vector<std::vector<uint8_t>> frames;
    for (int i = 0; i < 48; ++i) frames.push_back(first[first.size() - 2 + i % 2]);
    StreamStats stats;
    const auto coded = encode(frames, true, &stats);
    size_t xored = 0;
    for (const auto& message : coded) xored += (header_of(message).flags & kMsgXor) != 0;
    ASSERT_GT(xored, 30u) << "the frames were not XOR-coded";
    EXPECT_LT(double(stats.compressions), 1.4 * double(coded.size()))
        << stats.compressions << " zstd runs for " << coded.size() << " messages";
    MessageChain chain;  // and they read back exactly
    Message m;
    for (size_t i = 0; i < coded.size(); ++i) {
        decode_message(coded[i].data(), coded[i].size(), 0, m, &chain);
        ASSERT_EQ(m.payload, frames[i]) << "message " << i;
    }
}

TEST(InterFrame, AReaderWithoutThePreviousMessageRefusesIt) {
    const auto coded = encode(frames_of_a_program(10), true);
    MessageChain chain;
    Message m;
    // From the key: fine. From message 2 without 1: refused, naming both.
    decode_message(coded[0].data(), coded[0].size(), 0, m, &chain);
    size_t delta = 1;
    while (delta < coded.size() && !(header_of(coded[delta]).flags & (kMsgDelta | kMsgXor))) delta++;
    ASSERT_LT(delta + 1, coded.size());
    MessageChain fresh;
    try {
        decode_message(coded[delta + 1].data(), coded[delta + 1].size(), 0, m, &fresh);
        FAIL() << "a delta message without its predecessor was read";
    } catch (const DecodeError& e) {
        const std::string what = e.what();
        EXPECT_NE(what.find("is coded against message " + std::to_string(header_of(coded[delta + 1]).sequence - 1) +
                            ", which this reader does not have"),
                  std::string::npos)
            << what;
    }
    EXPECT_THROW(decode_message(coded[delta].data(), coded[delta].size(), 0, m), DecodeError);  // no chain at all
}

// A coded message names its predecessor by the CRC-32 of its payload: a journal that answers
// with another stream's messages of the same numbers is refused, not unpacked against the wrong
// message (prefix-coded and XORed alike).
TEST(InterFrame, AnotherStreamsMessageIsRefusedNotUnpackedAgainstTheWrongPredecessor) {
    for (bool moving : {false, true}) {
        const auto ours = encode(frames_of_a_program(6, moving), true);
        auto other_frames = frames_of_a_program(6, moving);
        for (auto& f : other_frames) f[kTupleHeaderBytes] ^= 0x5a;  // another program's, of the same lengths
        const auto theirs = encode(other_frames, true);
        size_t coded = 1;
        while (coded < theirs.size() && !(header_of(theirs[coded]).flags & (kMsgDelta | kMsgXor))) coded++;
        ASSERT_LT(coded, theirs.size());
        EXPECT_TRUE(header_of(theirs[coded]).flags & kMsgBound);
        MessageChain chain;
        Message m;
        for (size_t i = 0; i < coded; ++i) decode_message(ours[i].data(), ours[i].size(), 0, m, &chain);
        try {
            decode_message(theirs[coded].data(), theirs[coded].size(), 0, m, &chain);
            FAIL() << "another stream's message " << coded << " was unpacked against ours"
                   << (moving ? " (XORed)" : " (prefix)");
        } catch (const DecodeError& e) {
            EXPECT_NE(std::string(e.what()).find("messages of two streams mixed"), std::string::npos) << e.what();
        }
        decode_message(ours[coded].data(), ours[coded].size(), 0, m, &chain);  // our own: read
    }
}

// The binding's own framing, crafted: a bound message too short to hold the checksum, and a key
// message that claims a predecessor.
TEST(InterFrame, CraftedBindingsAreRefusedClearly) {
    const auto coded = encode(frames_of_a_program(4), true);
    size_t k = 1;
    while (k < coded.size() && !(header_of(coded[k]).flags & kMsgBound)) k++;
    ASSERT_LT(k, coded.size());
    MessageChain chain;
    Message m;
    for (size_t i = 0; i < k; ++i) decode_message(coded[i].data(), coded[i].size(), 0, m, &chain);
    std::vector<uint8_t> shorter(coded[k].begin(), coded[k].begin() + std::ptrdiff_t(sizeof(MessageHeader) + 2));
    MessageHeader h = header_of(coded[k]);
    h.stored_bytes = 2;
    h.crc32 = uint32_t(crc32(0, shorter.data() + sizeof h, 2));
    std::memcpy(shorter.data(), &h, sizeof h);
    try {
        decode_message(shorter.data(), shorter.size(), 0, m, &chain);
        FAIL() << "a bound message of 2 bytes was read";
    } catch (const DecodeError& e) {
        EXPECT_NE(std::string(e.what()).find("shorter than its predecessor's checksum"), std::string::npos) << e.what();
    }
    std::vector<uint8_t> key = coded[0];
    MessageHeader kh = header_of(key);
    kh.flags |= kMsgBound;
    std::memcpy(key.data(), &kh, sizeof kh);
    MessageChain fresh;
    try {
        decode_message(key.data(), key.size(), 0, m, &fresh);
        FAIL() << "a key message bound to a predecessor was read";
    } catch (const DecodeError& e) {
        EXPECT_NE(std::string(e.what()).find("a key message bound to a predecessor"), std::string::npos) << e.what();
    }
}

TEST(InterFrame, VersionsAndBadDeltasAreRefusedClearly) {
    auto coded = encode(frames_of_a_program(5), true);
    EXPECT_EQ(error_reading(as_file(coded, kFormatVersion)), "");
    // A newer glcast's file, an older one that cannot have kMsgDelta, a version that never was.
    EXPECT_NE(error_reading(as_file(coded, kFormatVersion + 1)).find("written by a newer glcast"), std::string::npos);
    EXPECT_NE(error_reading(as_file(coded, 1)).find("unknown message flags"), std::string::npos);
    EXPECT_NE(error_reading(as_file(coded, 0)).find("reads versions 1 to"), std::string::npos);
    // A delta message's zstd frame damaged (its checksum made right): zstd's refusal, not a crash.
    size_t k = 1;
    while (!(header_of(coded[k]).flags & (kMsgDelta | kMsgXor))) k++;
    const size_t zstd_frame = sizeof(MessageHeader) + ((header_of(coded[k]).flags & kMsgBound) ? 4 : 0);
    for (size_t i = zstd_frame; i < coded[k].size(); i++) coded[k][i] ^= 0x5a;
    MessageHeader h = header_of(coded[k]);
    h.crc32 = uint32_t(crc32(0, coded[k].data() + sizeof h, uInt(h.stored_bytes)));
    std::memcpy(coded[k].data(), &h, sizeof h);
    const std::string damaged = error_reading(as_file(coded, kFormatVersion));
    EXPECT_NE(damaged.find("bad zstd payload (coded against the previous message)"), std::string::npos) << damaged;
    // An XORed message whose length is not the previous one's.
    auto lengths = encode(frames_of_a_program(3, true), true);
    size_t x = 1;
    while (x < lengths.size() && !(header_of(lengths[x]).flags & kMsgXor)) x++;
    ASSERT_LT(x, lengths.size());
    MessageHeader longer = header_of(lengths[x]);
    longer.raw_bytes += 4;
    longer.crc32 = uint32_t(crc32(0, lengths[x].data() + sizeof longer, uInt(longer.stored_bytes)));
    std::memcpy(lengths[x].data(), &longer, sizeof longer);
    EXPECT_NE(error_reading(as_file(lengths, kFormatVersion)).find("is XORed with message"), std::string::npos);
    // Delta without compression is not a thing.
    auto flags_only = encode(frames_of_a_program(3), true);
    MessageHeader bad = header_of(flags_only[0]);
    bad.flags = kMsgDelta;
    std::memcpy(flags_only[0].data(), &bad, sizeof bad);
    EXPECT_NE(error_reading(as_file(flags_only, kFormatVersion)).find("must be compressed"), std::string::npos);
}

}  // namespace glcast

// The residual and its inverse, word at a time: equal to the byte loop for every length and
// alignment, in place too.
TEST(InterFrame, XorBytesIsTheByteLoop) {
    std::vector<uint8_t> a(80), b(80);
    for (size_t i = 0; i < a.size(); i++) a[i] = uint8_t(i * 37 + 5), b[i] = uint8_t(i * 101 + 3);
    for (size_t offset = 0; offset < 8; offset++)
        for (size_t n = 0; n + offset <= 64; n++) {
            std::vector<uint8_t> out(n), in_place(a.begin() + long(offset), a.begin() + long(offset + n));
            glcast::xor_bytes(out.data(), a.data() + offset, b.data() + offset, n);
            glcast::xor_bytes(in_place.data(), in_place.data(), b.data() + offset, n);
            for (size_t i = 0; i < n; i++) {
                ASSERT_EQ(out[i], uint8_t(a[offset + i] ^ b[offset + i])) << "offset " << offset << ", n " << n;
                ASSERT_EQ(in_place[i], out[i]);
            }
        }
}
