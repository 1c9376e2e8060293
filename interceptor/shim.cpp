// Per-call recursion guard, tuple recording, and the stream the tuples go to (opened at the first
// recorded call; when it closes: interceptor/lifetime.h).
#include "interceptor/shim.h"

#include <fcntl.h>
#include <time.h>
#include <unistd.h>

#include <cstdlib>

#include <atomic>
#include <cstdio>
#include <cstring>
#include <memory>
#include <mutex>

#include "glcast_commands.h"
#include "interceptor/client_arrays.h"
#include "glcast_synthetic_encode.h"
#include "interceptor/config.h"
#include "interceptor/driver_size_queries.h"
#include "interceptor/lifetime.h"
#include "interceptor/shim_internal.h"
#include "master/publisher.h"
#include "master/stream.h"
#include "protocol/format.h"

namespace glcast {

bool g_recording = false;

static std::atomic<uint32_t> g_unserialized[kOpcodeCount];
static std::once_flag g_stream_once;
// Never deleted (interceptor/lifetime.h): a call from a destructor that runs after the stream
// closed must still find it, closed, and the writer's buffers are the process's until it ends.
static Stream* g_stream = nullptr;
static pid_t g_stream_pid = 0;  // the process that opened it: a forked child never closes it

// Set once the stream exists: std::call_once writes two thread_locals of libstdc++'s (through
// __tls_get_addr) on every call, even when done, and stream() is asked on every GL call.
static std::atomic<Stream*> g_stream_ready{nullptr};

Stream* stream() {
    if (Stream* s = g_stream_ready.load(std::memory_order_acquire)) [[likely]] return in_forked_child() ? nullptr : s;
    if (in_forked_child()) return nullptr;  // a call_once the parent was inside at fork never ends here
    std::call_once(g_stream_once, [] {
        const ShimConfig& c = shim_config();
        std::vector<std::unique_ptr<MessageSink>> sinks;
        try {
            if (!c.capture_path.empty()) sinks.push_back(std::make_unique<CaptureFileSink>(c.capture_path));
            if (!c.publish.empty()) {
                PublisherOptions p;
                p.endpoint = c.publish;
                p.snapshot_endpoint = c.journal_endpoint;
                p.journal_limit_bytes = size_t(c.journal_mb) << 20;
                p.drop_every = c.drop_every;
                p.wait_subscribers = int(c.wait_subscribers);
                p.lockstep = int(c.lockstep);
                p.verbose = c.verbose;
                sinks.push_back(std::make_unique<PublisherSink>(p));
            }
        } catch (const std::exception& e) {
            std::fprintf(stderr, "glcast: %s; capture disabled\n", e.what());
            g_recording = false;
            return;
        }
        g_stream = new Stream(std::move(sinks), c.zstd_level, 16, c.inter_frame, c.writer_nice);
        g_stream_pid = getpid();
        g_stream_ready.store(g_stream, std::memory_order_release);
        watch_for_the_last_thread(!c.publish.empty());
        if (!c.published_mark.empty()) {  // glcast run: the program draws, its slaves have something to wait for
            const int fd = ::open(c.published_mark.c_str(), O_WRONLY | O_CREAT | O_CLOEXEC | O_NOFOLLOW, 0600);
            if (fd >= 0) ::close(fd);
        }
    });
    return g_stream;
}

CallScope::CallScope(uint32_t opcode) : opcode_(opcode) {
    ThreadState& ts = thread_state();
    recording_ = g_recording && ts.depth == 0 && records_while_ending();
    if (!recording_ && g_stream_ready.load(std::memory_order_relaxed) && ts.depth == 0) [[unlikely]] {
        stay_out_of_the_exit();
        count_call_after_end(opcode);
    }
    ts.depth++;
    ts.opcode = opcode;
}

CallScope::~CallScope() { thread_state().depth--; }

Encoder& CallScope::begin_record() {
    ThreadState& ts = thread_state();
    ts.scratch.clear();
    ts.encoder.set_context(ts.context_id);
    ts.encoder.clear_failure();
    ts.sizes.clear_failure();
    return ts.encoder;
}

SizeQueries& CallScope::sizes() { return thread_state().sizes; }

void CallScope::commit_record() {
    ThreadState& ts = thread_state();
    const std::string& why = !ts.encoder.failure().empty() ? ts.encoder.failure() : ts.sizes.failure();
    if (!why.empty()) {
        const std::string reason = why;  // unserialized() reuses the encoder
        unserialized(reason.c_str());
        return;
    }
    if (Stream* s = stream()) s->append(ts.scratch.data(), ts.scratch.size());
}

Encoder& CallScope::begin_synthetic(uint32_t opcode) {
    ThreadState& ts = thread_state();
    ts.synthetic.clear();
    Encoder& e = ts.synthetic_encoder;
    e.set_context(ts.context_id);
    e.begin(opcode);
    return e;
}

void CallScope::commit_synthetic() {
    ThreadState& ts = thread_state();
    ts.synthetic_encoder.end();
    if (Stream* s = stream()) s->append(ts.synthetic.data(), ts.synthetic.size());
}

void CallScope::unserialized(const char* reason) {
    const CommandInfo* info = command_info(opcode_);
    if (!reason || !*reason) reason = info && *info->reason ? info->reason : "not serializable";
    if (g_unserialized[opcode_].fetch_add(1, std::memory_order_relaxed) == 0 && shim_config().verbose)
        std::fprintf(stderr, "glcast: %s forwarded, not serialized: %s\n", info ? info->name : "?", reason);
    encode_synth_unserialized(begin_synthetic(kSynthUnserialized), opcode_, reason);
    commit_synthetic();
    if (Stream* s = stream()) s->count_unserialized();
}

uint32_t current_context_id() { return thread_state().context_id; }
void set_current_context(uint32_t id) { thread_state().context_id = id; }

void print_summary() {
    if (!g_stream) return;
    const StreamStats st = g_stream->stats();
    std::fprintf(stderr,
                 "glcast: %llu frames, %llu tuples, %.1f KiB raw, %.1f KiB stored, compression %.3f ms a frame, "
                 "array cache %llu hits / %llu misses, %llu calls unserialized\n",
                 (unsigned long long)st.frames, (unsigned long long)st.tuples, st.raw_bytes / 1024.0,
                 st.stored_bytes / 1024.0, st.frames ? st.compress_seconds * 1000 / double(st.frames) : 0.0,
                 (unsigned long long)st.array_cache_hits,
                 (unsigned long long)st.array_cache_misses, (unsigned long long)st.unserialized);
    for (uint32_t op = 0; op < kOpcodeCount; ++op)
        if (uint32_t n = g_unserialized[op].load())
            std::fprintf(stderr, "glcast:   unserialized %s x%u: %s\n", command_info(op)->name, n,
                         *command_info(op)->reason ? command_info(op)->reason : "size unknown at run time");
}

void drain_stream() {
    if (g_stream && g_stream_pid == getpid()) g_stream->drain();
}

void finish_stream() {
    if (!g_stream || g_stream_pid != getpid()) return;
    g_stream->close();
    if (shim_config().verbose) print_summary();
}

void on_frame_end() {
    Stream* s = stream();
    if (!s) return;
    // When each frame left the program (CLOCK_MONOTONIC, taken before it is sent: a slave may
    // have it before this thread writes the line): glcast run --timing, wall latency benchmarks.
    static FILE* swap_log = shim_config().swap_log.empty() ? nullptr : std::fopen(shim_config().swap_log.c_str(), "w");
    timespec swapped{};
    if (swap_log) clock_gettime(CLOCK_MONOTONIC, &swapped);
    s->end_frame();
    if (swap_log) {
        std::fprintf(swap_log, "%llu %.6f\n", (unsigned long long)(s->frame() - 1), swapped.tv_sec + swapped.tv_nsec * 1e-9);
        std::fflush(swap_log);
    }
    const ShimConfig& c = shim_config();
    if (c.lockstep) s->flush();  // lockstep: back to the program only when the slaves replayed the frame
    if (c.frames && s->frame() >= c.frames) {
        g_recording = false;
        finish_stream();
        if (c.exit_after) _exit(0);
    }
}

}  // namespace glcast
