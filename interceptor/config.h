// Every GLCAST_* environment variable the shim reads, read once and checked here, so that a
// bad value is one clear message at start and not a surprise later. docs/environment.md lists
// them, and those the glcast command and the slaves read.
#pragma once

#include <cstdint>
#include <string>

namespace glcast {

struct ShimConfig {
    std::string capture_path;   // GLCAST_CAPTURE: write the stream to this file
    uint64_t frames = 0;        // GLCAST_FRAMES: stop recording after this many frames (0: never)
    bool exit_after = false;    // GLCAST_EXIT_AFTER_FRAMES=1: end the program once they are written
    int zstd_level = 1;         // GLCAST_ZSTD_LEVEL: 0 stores messages uncompressed
    bool inter_frame = true;    // GLCAST_INTER_FRAME: 0 compresses each message alone (format version 2 still)
    bool verbose = false;       // GLCAST_VERBOSE=1: summary on stderr at exit
    int writer_nice = 10;       // GLCAST_WRITER_NICE: the writer thread's nice value, 0..19 (0: the program's)
    bool map_tracking = true;   // GLCAST_MAP_TRACKING=0: persistent mappings compared whole, not page-tracked
    std::string snapshot_dir;   // GLCAST_SNAPSHOT_DIR: the program's own frames as PNGs (tests)
    uint64_t snapshot_from = 0; // GLCAST_SNAPSHOT_FROM: ... from this frame on
    std::string publish;        // GLCAST_PUBLISH: ZeroMQ endpoint the stream is published on
    std::string journal_endpoint;  // GLCAST_JOURNAL_ENDPOINT: ROUTER serving late joiners
    uint64_t journal_mb = 64;      // GLCAST_JOURNAL_MB: the journal keeps the newest messages up to this
    uint64_t drop_every = 0;       // GLCAST_TEST_DROP_EVERY: lose every Nth message (tests)
    uint64_t wait_subscribers = 0; // GLCAST_WAIT_SUBSCRIBERS: slaves to wait for at start
    uint64_t lockstep = 0;         // GLCAST_LOCKSTEP: slaves that must replay each frame before the next
    std::string swap_log;          // GLCAST_TEST_SWAP_LOG: when each frame left the program (benchmarks)
    std::string published_mark;    // GLCAST_PUBLISHED_MARK: a file made when the stream starts (glcast run)
    bool has_consumer() const { return !capture_path.empty() || !publish.empty(); }
};

// Parsed on first use; an invalid value is reported and the shim stays passive.
const ShimConfig& shim_config();

}  // namespace glcast
