#include "interceptor/config.h"

#include <cerrno>
#include <cstdio>
#include <cstdlib>

namespace glcast {

static bool read_uint(const char* name, uint64_t min, uint64_t max, uint64_t& out) {
    const char* text = std::getenv(name);
    if (!text || !*text) return true;
    char* end = nullptr;
    errno = 0;
    const unsigned long long v = std::strtoull(text, &end, 10);
    if (errno || *end || v < min || v > max || text[0] == '-') {
        std::fprintf(stderr, "glcast: %s=%s is not an integer in [%llu, %llu]; glcast stays off\n", name, text,
                     (unsigned long long)min, (unsigned long long)max);
        return false;
    }
    out = v;
    return true;
}

static ShimConfig load() {
    ShimConfig c;
    bool ok = true;
    if (const char* p = std::getenv("GLCAST_CAPTURE")) c.capture_path = p;
    if (const char* p = std::getenv("GLCAST_SNAPSHOT_DIR")) c.snapshot_dir = p;
    if (const char* p = std::getenv("GLCAST_PUBLISH")) c.publish = p;
    if (const char* p = std::getenv("GLCAST_JOURNAL_ENDPOINT")) c.journal_endpoint = p;
    if (const char* p = std::getenv("GLCAST_TEST_SWAP_LOG")) c.swap_log = p;
    ok &= read_uint("GLCAST_JOURNAL_MB", 0, 1 << 20, c.journal_mb);
    ok &= read_uint("GLCAST_SNAPSHOT_FROM", 0, UINT32_MAX, c.snapshot_from);
    ok &= read_uint("GLCAST_TEST_DROP_EVERY", 0, UINT32_MAX, c.drop_every);
    ok &= read_uint("GLCAST_WAIT_SUBSCRIBERS", 0, 1024, c.wait_subscribers);
    ok &= read_uint("GLCAST_LOCKSTEP", 0, 1024, c.lockstep);
    uint64_t v = 0;
    ok &= read_uint("GLCAST_FRAMES", 0, UINT32_MAX, c.frames);
    v = 0;
    ok &= read_uint("GLCAST_EXIT_AFTER_FRAMES", 0, 1, v);
    c.exit_after = v;
    v = 1;
    ok &= read_uint("GLCAST_ZSTD_LEVEL", 0, 19, v);
    c.zstd_level = int(v);
    v = 1;
    ok &= read_uint("GLCAST_INTER_FRAME", 0, 1, v);
    c.inter_frame = v != 0;
    v = 0;
    ok &= read_uint("GLCAST_VERBOSE", 0, 1, v);
    c.verbose = v;
    v = 10;
    ok &= read_uint("GLCAST_WRITER_NICE", 0, 19, v);
    c.writer_nice = int(v);
    if (!ok) {
        c.capture_path.clear();
        c.publish.clear();
    }
    return c;
}

const ShimConfig& shim_config() {
    static const ShimConfig config = load();
    return config;
}

}  // namespace glcast
