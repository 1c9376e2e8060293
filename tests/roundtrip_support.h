// Harness for the generated round-trip test (glcast_roundtrip_test.cpp): hands out argument
// values and arrays, remembers what went in, decodes what came out and compares.
#pragma once

#include <cstdint>
#include <cstring>
#include <map>
#include <string>
#include <type_traits>
#include <vector>

#include "glcast_commands.h"
#include "glcast_encode.h"
#include "master/encoder.h"
#include "protocol/size_queries.h"

namespace glcast::roundtrip {

// Fixed, driver-free answers: default pixel store, nothing bound, every driver count 4.
class FakeSizes : public SizeQueries {
public:
    PixelStore pixel_store(Dir) override { return {}; }
    bool bound(uint32_t) override { return false; }
    int64_t driver_count(uint32_t) override { return 4; }
    int64_t tex_level(uint32_t, int32_t, uint32_t) override { return 2; }
    bool client_pointer(const void*) override { return false; }
};

class Harness {
public:
    Harness();
    void begin(uint32_t opcode);

    template <class Q>
    std::remove_const_t<Q> value(int index, const char* name, uint32_t sample_pname) {
        using T = std::remove_const_t<Q>;
        uint64_t bits = pick(name, sample_pname);
        T v;
        if constexpr (std::is_pointer_v<T>) {
            v = reinterpret_cast<T>(uintptr_t(bits));
        } else if constexpr (std::is_floating_point_v<T>) {
            v = T(1.5);
        } else {
            v = static_cast<T>(bits);
        }
        uint64_t stored = 0;
        if constexpr (std::is_pointer_v<T>) stored = uint64_t(uintptr_t(v));
        else std::memcpy(&stored, &v, sizeof v < 8 ? sizeof v : 8);
        if (index >= 0) values_[index] = stored;
        else ret_ = stored;
        return v;
    }
    void* buffer(const char* name);
    const char* text() { return "abc"; }
    const char* const* texts() { return texts_; }
    const void* const* pointers() { return pointers_; }
    XVisualInfo* visual() { return &visual_; }
    void* address() { return reinterpret_cast<void*>(uintptr_t(0x1000)); }

    Encoder& encoder() { return encoder_; }
    SizeQueries& sizes() { return sizes_; }
    void check();  // decode and compare; records failures

    int encoded = 0, size_unknown = 0;
    std::vector<std::string> failures;       // mismatches: test failures
    std::vector<std::string> unknown_sizes;  // encoders that refused (size unknown)

private:
    uint64_t pick(const char* name, uint32_t sample_pname);

    uint32_t opcode_ = 0;
    ByteVector out_;
    Encoder encoder_{out_};
    FakeSizes sizes_;
    std::map<int, uint64_t> values_;
    uint64_t ret_ = 0;
    std::vector<uint8_t> pattern_, zeros_;
    std::vector<int64_t> attribs_;
    const char* texts_[2] = {"abc", "de"};
    const void* pointers_[2];
    XVisualInfo visual_{};
};

void run_all(Harness& h);  // generated

}  // namespace glcast::roundtrip
