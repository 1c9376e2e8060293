// Bad input: truncated, corrupted and foreign files, unknown opcodes, table mismatches and
// absurd lengths give a DecodeError naming the byte offset; never a crash or a huge allocation.
#include <GL/gl.h>
#include <gtest/gtest.h>
#include <zlib.h>

#include <cstdio>
#include <cstring>

#include "glcast_commands.h"
#include "glcast_encode.h"
#include "master/encoder.h"
#include "master/stream.h"
#include "protocol/decoder.h"
#include "protocol/dump.h"
#include "protocol/format.h"
#include "tests/roundtrip_support.h"

using namespace glcast;

namespace {

// One uncompressed message that ends frame `seq` (one frame per message).
template <class Bytes>
std::vector<uint8_t> message(const Bytes& payload, uint64_t seq) {
    MessageHeader h{};
    h.magic = kMessageMagic;
    h.flags = kMsgFrameEnd;
    h.sequence = seq;
    h.frame = uint32_t(seq);
    h.stored_bytes = h.raw_bytes = uint32_t(payload.size());
    h.crc32 = uint32_t(crc32(0, payload.data(), uInt(payload.size())));
    std::vector<uint8_t> m(sizeof h + payload.size());
    std::memcpy(m.data(), &h, sizeof h);
    if (payload.size()) std::memcpy(m.data() + sizeof h, payload.data(), payload.size());
    return m;
}

std::vector<uint8_t> valid_capture() {
    roundtrip::FakeSizes sz;
    ByteVector payload;
    Encoder e(payload);
    GLuint names[2] = {1, 2};
    encode_glGenTextures(e, sz, 2, names);
    std::vector<uint8_t> pixels(64, 9);
    encode_glTexImage2D(e, sz, GL_TEXTURE_2D, 0, GL_RGBA, 4, 4, 0, GL_RGBA, GL_UNSIGNED_BYTE, pixels.data());
    encode_glClear(e, sz, GL_COLOR_BUFFER_BIT);
    const FileHeader fh = make_file_header();
    std::vector<uint8_t> file(reinterpret_cast<const uint8_t*>(&fh), reinterpret_cast<const uint8_t*>(&fh) + sizeof fh);
    for (uint64_t seq = 0; seq < 3; ++seq) {
        const auto m = message(payload, seq);
        file.insert(file.end(), m.begin(), m.end());
    }
    return file;
}

// Dumps a capture held in memory; returns "" or the DecodeError text.
std::string dump(const std::vector<uint8_t>& file) {
    FILE* null = std::fopen("/dev/null", "w");
    std::string error;
    try {
        CaptureReader reader(memory_source(file.data(), file.size()));
        dump_capture(reader, DumpOptions{}, null);
    } catch (const DecodeError& e) {
        error = e.what();
        EXPECT_LE(e.offset(), file.size());
        EXPECT_NE(error.find("at byte"), std::string::npos) << error;
    }
    std::fclose(null);
    return error;
}

}  // namespace

TEST(BadInput, ValidCaptureDumps) { EXPECT_EQ(dump(valid_capture()), ""); }

TEST(BadInput, EveryTruncationIsRefusedOrAMessageBoundary) {
    const auto file = valid_capture();
    const size_t message_bytes = (file.size() - sizeof(FileHeader)) / 3;
    for (size_t n = 0; n < file.size(); ++n) {
        const std::vector<uint8_t> cut(file.begin(), file.begin() + long(n));
        const std::string err = dump(cut);
        const bool boundary = n >= sizeof(FileHeader) && (n - sizeof(FileHeader)) % message_bytes == 0;
        EXPECT_EQ(err.empty(), boundary) << "truncated to " << n << " bytes: " << err;
    }
}

TEST(BadInput, EveryFlippedByteIsCaughtOrHarmless) {
    const auto file = valid_capture();
    int refused = 0;
    for (size_t i = 0; i < file.size(); ++i) {
        auto bad = file;
        bad[i] ^= 0x5a;
        if (!dump(bad).empty()) refused++;
    }
    // Header padding (registry text, reserved) is not checked; everything else is.
    EXPECT_GT(refused, int(file.size()) - 40);
}

TEST(BadInput, ForeignFile) {
    const std::string text = "P6\n4 4\n255\n................................................................";
    const std::string err = dump(std::vector<uint8_t>(text.begin(), text.end()));
    EXPECT_NE(err.find("not a glcast capture"), std::string::npos) << err;
}

TEST(BadInput, OpcodeTableMismatch) {
    auto file = valid_capture();
    file[16] ^= 1;
    EXPECT_NE(dump(file).find("opcode table mismatch"), std::string::npos);
}

TEST(BadInput, AbsurdLength) {
    auto file = valid_capture();
    const uint32_t huge = 0xFFFFFFF0u;
    std::memcpy(file.data() + sizeof(FileHeader) + offsetof(MessageHeader, stored_bytes), &huge, 4);
    const std::string err = dump(file);
    EXPECT_NE(err.find("absurd message length"), std::string::npos) << err;
    EXPECT_NE(err.find("at byte " + std::to_string(sizeof(FileHeader) + 20)), std::string::npos) << err;
}

TEST(BadInput, UnknownOpcodeAndOverlongTuple) {
    const FileHeader fh = make_file_header();
    auto with_payload = [&](std::vector<uint8_t> payload) {
        std::vector<uint8_t> f(reinterpret_cast<const uint8_t*>(&fh), reinterpret_cast<const uint8_t*>(&fh) + sizeof fh);
        const auto m = message(payload, 0);
        f.insert(f.end(), m.begin(), m.end());
        return f;
    };
    std::vector<uint8_t> tuple(12, 0);
    const uint32_t op = kOpcodeCount + 5;
    std::memcpy(tuple.data(), &op, 4);
    std::string err = dump(with_payload(tuple));
    EXPECT_NE(err.find("unknown opcode"), std::string::npos) << err;
    const uint32_t clear = OP_glClear, body = 1u << 30;
    std::memcpy(tuple.data(), &clear, 4);
    std::memcpy(tuple.data() + 8, &body, 4);
    err = dump(with_payload(tuple));
    EXPECT_NE(err.find("runs past the message"), std::string::npos) << err;
}

TEST(BadInput, SequenceGapIsReported) {
    auto file = valid_capture();
    const uint64_t seq = 7;
    std::memcpy(file.data() + sizeof(FileHeader) + offsetof(MessageHeader, sequence), &seq, 8);
    EXPECT_NE(dump(file).find("sequence"), std::string::npos);
}
