// libFuzzer target: any byte string as a capture file must dump or give a DecodeError,
// never crash, hang or allocate without bound (run under ASan/UBSan by run_fuzzer.sh).
#include <cstdint>
#include <cstdio>

#include "protocol/decoder.h"
#include "protocol/dump.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    static FILE* null = std::fopen("/dev/null", "w");
    try {
        glcast::CaptureReader reader(glcast::memory_source(data, size));
        glcast::dump_capture(reader, glcast::DumpOptions{}, null);
    } catch (const glcast::DecodeError&) {
    }
    return 0;
}
