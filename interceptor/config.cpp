#include "interceptor/config.h"

#include <cstdio>

#include "common/environment.h"
#include "common/immortal.h"

namespace glcast {

// The shim must never stop the program: a bad value is said once and leaves glcast passive.
static bool read_uint(const char* name, uint64_t min, uint64_t max, uint64_t& out) {
    try {
        out = env_uint(name, min, max, out);
        return true;
    } catch (const EnvironmentError& e) {
        std::fprintf(stderr, "glcast: %s; glcast stays off\n", e.what());
        return false;
    }
}

static ShimConfig load() {
    ShimConfig c;
    bool ok = true;
    c.capture_path = env_text("GLCAST_CAPTURE");
    c.snapshot_dir = env_text("GLCAST_SNAPSHOT_DIR");
    c.publish = env_text("GLCAST_PUBLISH");
    c.journal_endpoint = env_text("GLCAST_JOURNAL_ENDPOINT");
    c.swap_log = env_text("GLCAST_TEST_SWAP_LOG");
    c.published_mark = env_text("GLCAST_PUBLISHED_MARK");
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
    v = 1;
    ok &= read_uint("GLCAST_MAP_TRACKING", 0, 1, v);
    c.map_tracking = v != 0;
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
    static const Immortal<ShimConfig> config(load());  // read by calls made after static destruction too
    return *config;
}

}  // namespace glcast
