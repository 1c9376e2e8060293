#include "master/stream.h"

#include <fcntl.h>
#include <sys/file.h>
#include <sys/resource.h>
#include <sys/syscall.h>
#include <unistd.h>
#include <zlib.h>
#include <zstd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <stdexcept>

#include "common/xor_bytes.h"
#include "glcast_commands.h"
#include "protocol/format.h"

namespace glcast {

// A frame larger than this is split over several messages, bounding every allocation.
static constexpr size_t kBatchBytes = 8u << 20;
// The least zstd level an XOR residual is compressed at (see writer_loop).
static constexpr int kXorResidualLevel = 5;
static constexpr uint64_t kXorProbeInterval = 16;

Stream::Stream(std::vector<std::unique_ptr<MessageSink>> sinks, int zstd_level, size_t queue_depth, bool inter_frame)
    : queue_depth_(queue_depth ? queue_depth : 1), zstd_level_(zstd_level), inter_frame_(inter_frame),
      sinks_(std::move(sinks)) {
    writer_ = std::thread([this] { writer_loop(); });
}

Stream::~Stream() { close(); }

void Stream::append(const uint8_t* tuple, size_t bytes) {
    std::lock_guard lock(open_lock_);
    if (closed_) return;
    if (open_.size() + bytes > kBatchBytes && !open_.empty()) seal_open(false);
    open_.append(tuple, bytes);
    open_tuples_++;
    open_raw_bytes_ += bytes;
}

void Stream::end_frame() {
    std::lock_guard lock(open_lock_);
    if (closed_) return;
    seal_open(true);
}

// Lossless sinks: a full queue makes the program wait here rather than drop data; what waits is
// the thread that fills the batch (the program's calls go on into the next batch only when the
// writer has room for this one).
void Stream::seal_open(bool frame_end) {
    if (open_.empty() && !frame_end) return;
    std::unique_lock lock(mutex_);
    queue_changed_.wait(lock, [&] { return queue_.size() < queue_depth_ || stopping_; });
    queue_.push_back(Batch{std::move(open_), next_sequence_++, open_frame_, frame_end});
    // The next batch fills a buffer the writer is done with: in a steady run appending a call
    // allocates nothing.
    open_ = std::move(spare_);
    spare_ = {};
    open_.clear();
    stats_.tuples += open_tuples_;
    stats_.raw_bytes += open_raw_bytes_;
    open_tuples_ = open_raw_bytes_ = 0;
    if (frame_end) open_frame_ = uint32_t(++stats_.frames);
    in_flight_++;
    queue_changed_.notify_all();
}

void Stream::flush() {
    {
        std::lock_guard lock(open_lock_);
        if (closed_) return;
        seal_open(false);
    }
    std::unique_lock lock(mutex_);
    queue_changed_.wait(lock, [&] { return in_flight_ == 0; });
}

void Stream::close() {
    {
        std::lock_guard open_lock(open_lock_);
        if (closed_) return;
        seal_open(false);
        closed_ = true;
        std::lock_guard lock(mutex_);
        stopping_ = true;
        queue_changed_.notify_all();
    }
    if (writer_.joinable()) writer_.join();
    for (auto& s : sinks_) s->close();
}

uint64_t Stream::frame() const {
    std::lock_guard lock(mutex_);
    return stats_.frames;
}

StreamStats Stream::stats() const {
    std::lock_guard open_lock(open_lock_);
    std::lock_guard lock(mutex_);
    StreamStats s = stats_;
    s.tuples += open_tuples_;
    s.raw_bytes += open_raw_bytes_;
    return s;
}

void Stream::count_cache(bool hit) {
    std::lock_guard lock(mutex_);
    (hit ? stats_.array_cache_hits : stats_.array_cache_misses)++;
}

void Stream::count_unserialized() {
    std::lock_guard lock(mutex_);
    stats_.unserialized++;
}

// Inter-frame coding (docs/stream-format.md, version 2): most messages are compressed with the
// previous message's payload as a zstd prefix, or XORed with it, so a frame that repeats the last
// one costs what changed. Every kKeyIntervalMessages-th message (and the first) is a key,
// compressed alone.
void Stream::writer_loop() {
    // Below the program's own threads: on a busy machine the program draws first, and the
    // writer takes what is left (the bounded queue still holds the program back if it is never
    // left anything).
    const char* nice = std::getenv("GLCAST_WRITER_NICE");  // 0..19; 10 by default
    const long level = nice && *nice ? std::strtol(nice, nullptr, 10) : 10;
    if (level > 0 && level < 20) setpriority(PRIO_PROCESS, pid_t(syscall(SYS_gettid)), int(level));
    ZSTD_CCtx* cctx = ZSTD_createCCtx();
    std::vector<uint8_t> message;  // header + stored payload, as the sinks take it
    ByteVector body;  // the compressed payload, before it is known how long it is: never zero-filled
    ByteVector previous;  // the last message's payload, the next one's prefix
    ByteVector xored;
    std::vector<uint8_t> alternative, probe;  // kept across messages: no allocation per message
    // The level XOR residuals are compressed at: the lazy level where it pays, re-decided on
    // every kXorProbeInterval-th XORed message by compressing it at both.
    const int lazy_level = std::max(zstd_level_, kXorResidualLevel);
    int xor_level = lazy_level;
    uint64_t xored_messages = 0;
    // A program whose frames XOR far better than the prefix codes them (CPU-animated vertices:
    // atlantis, engine, ff_scene's flag) does so frame after frame: while the last message coded
    // both ways came out at least a quarter smaller XORed, the prefix coding is skipped (half the
    // writer's time there) and tried again on every kXorProbeInterval-th message, or when the
    // XOR residual is half as large again as the last one or over an eighth of the frame (a frame
    // unlike the last, where the prefix coding may win by far: atlantis now and then). Measured on
    // the same raw frames (docs/performance.md): as many bytes, 30-35% fewer compressions.
    bool xor_mode = false;
    uint64_t coded_messages = 0;
    size_t last_xor_bytes = 0;
    for (;;) {
        Batch batch;
        {
            std::unique_lock lock(mutex_);
            queue_changed_.wait(lock, [&] { return !queue_.empty() || stopping_; });
            if (queue_.empty()) break;
            batch = std::move(queue_.front());
            queue_.pop_front();
            queue_changed_.notify_all();
        }
        MessageHeader h{};
        h.magic = kMessageMagic;
        h.sequence = batch.sequence;
        h.frame = batch.frame;
        h.raw_bytes = uint32_t(batch.payload.size());
        body.resize(ZSTD_compressBound(batch.payload.size()));
        size_t stored = batch.payload.size();
        const auto compress_start = std::chrono::steady_clock::now();
        uint64_t compressions = 0;
        if (zstd_level_ > 0 && !batch.payload.empty()) {
            const ByteVector& raw = batch.payload;
            const bool coded = inter_frame_ && batch.sequence % kKeyIntervalMessages != 0 && !previous.empty();
            auto compress = [&](uint8_t* dst, size_t capacity, const ByteVector& src, bool with_prefix,
                                int level) {
                compressions++;
                ZSTD_CCtx_reset(cctx, ZSTD_reset_session_and_parameters);
                ZSTD_CCtx_setParameter(cctx, ZSTD_c_compressionLevel, level);
                if (with_prefix) {
                    // The window spans the prefix and the message, so that any of the prefix can be matched.
                    int window_log = 10;
                    while (window_log < 27 && (size_t(1) << window_log) < previous.size() + src.size()) window_log++;
                    ZSTD_CCtx_setParameter(cctx, ZSTD_c_windowLog, window_log);
                    ZSTD_CCtx_refPrefix(cctx, previous.data(), previous.size());
                }
                return ZSTD_compress2(cctx, dst, capacity, src.data(), src.size());
            };
            auto xor_with_previous = [&] {
                xored.resize(raw.size());
                xor_bytes(xored.data(), raw.data(), previous.data(), xored.size());
            };
            // A frame of the same calls as the last, with numbers that moved (animated vertices):
            // XORed with the last, what stayed is zeros and what moved keeps its high bytes alike
            // (about half the prefix coding's bytes on xscreensaver's superquadrics, 2/3 on
            // atlantis). Tried, and kept when smaller, where the prefix left more than 1/64 of the
            // frame: a frame that mostly repeats the last (moebius: 0.4%) gains nothing from it.
            // Compressing twice costs the writer 0.1-0.3 ms a frame (docs/performance.md).
            // The XOR residual is mostly runs of zeros between a few changed bytes, where zstd's
            // lazy match finder (level 5) often finds far more than level 1's greedy one:
            // superquadrics 9,960 -> 4,547 bytes a frame, ff_scene 1,378 -> 359, engine 6,134 ->
            // 4,776; but on atlantis 4,953 -> 4,734 for 5x the time. So the writer probes both
            // levels now and then and keeps the lazy one only while it saves a tenth.
            const bool same_length = coded && previous.size() == raw.size();
            const bool xor_only = same_length && xor_mode && coded_messages++ % kXorProbeInterval != 0;
            size_t n = xor_only ? static_cast<size_t>(-1)  // not tried: an error code for ZSTD_isError
                                : compress(body.data(), body.size(), raw, coded, zstd_level_);
            uint32_t how = coded ? uint32_t(kMsgDelta) : 0u;
            if (same_length && (xor_only || (!ZSTD_isError(n) && n > raw.size() / 64))) {
                xor_with_previous();
                alternative.resize(ZSTD_compressBound(xored.size()));
                size_t x = compress(alternative.data(), alternative.size(), xored, false, xor_level);
                if (lazy_level != zstd_level_ && xored_messages++ % kXorProbeInterval == 0 && !ZSTD_isError(x)) {
                    const int other = xor_level == lazy_level ? zstd_level_ : lazy_level;
                    probe.resize(alternative.size());
                    const size_t y = compress(probe.data(), probe.size(), xored, false, other);
                    if (!ZSTD_isError(y)) {
                        const size_t lazy = other == lazy_level ? y : x, greedy = other == lazy_level ? x : y;
                        xor_level = lazy * 10 < greedy * 9 ? lazy_level : zstd_level_;
                        if (y < x) alternative.swap(probe), x = y;
                    }
                }
                if (xor_only && (ZSTD_isError(x) || x > raw.size() / 8 || 2 * x > 3 * last_xor_bytes))  // both
                    n = compress(body.data(), body.size(), raw, true, zstd_level_);
                if (!ZSTD_isError(x)) last_xor_bytes = x;
                if (!ZSTD_isError(n) && !ZSTD_isError(x)) xor_mode = x * 4 <= n * 3;  // both tried
                if (!ZSTD_isError(x) && (ZSTD_isError(n) || x < n)) {
                    std::memcpy(body.data(), alternative.data(), x);
                    n = x;
                    how = kMsgXor;
                }
            } else if (coded && !xor_only) {
                xor_mode = false;  // the prefix coding left too little for XOR to be tried
            }
            if (!ZSTD_isError(n) && n < raw.size()) {
                stored = n;
                h.flags |= kMsgCompressed | how;
            }
        }
        const double compress_seconds =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - compress_start).count();
        // Sized to what is stored: resizing it to zstd's bound zero-filled a whole raw frame
        // (180 KB on atlantis) for every message.
        message.resize(sizeof h + stored);
        if (stored)
            std::memcpy(message.data() + sizeof h, (h.flags & kMsgCompressed) ? body.data() : batch.payload.data(),
                        stored);
        if (batch.frame_end) h.flags |= kMsgFrameEnd;
        h.stored_bytes = uint32_t(stored);
        h.crc32 = uint32_t(crc32(0, message.data() + sizeof h, uInt(stored)));
        std::memcpy(message.data(), &h, sizeof h);
        for (auto& s : sinks_) s->write(message);
        previous.swap(batch.payload);  // the batch is done with: no copy
        std::lock_guard lock(mutex_);
        if (spare_.capacity() < batch.payload.capacity()) spare_.swap(batch.payload);  // the older prefix, for reuse
        stats_.messages++;
        stats_.stored_bytes += message.size();
        stats_.compress_seconds += compress_seconds;
        stats_.compressions += compressions;
        in_flight_--;
        queue_changed_.notify_all();
    }
    ZSTD_freeCCtx(cctx);
}

static void write_all(int fd, const void* data, size_t n, const std::string& path) {
    auto p = static_cast<const uint8_t*>(data);
    while (n) {
        const ssize_t w = ::write(fd, p, n);
        if (w < 0 && errno == EINTR) continue;
        if (w < 0) {
            std::fprintf(stderr, "glcast: writing %s: %s\n", path.c_str(), std::strerror(errno));
            return;
        }
        p += w;
        n -= size_t(w);
    }
}

FileHeader make_file_header() {
    FileHeader h{};
    std::memcpy(h.magic, kFileMagic, sizeof h.magic);
    h.version = kFormatVersion;
    h.header_bytes = sizeof h;
    h.opcode_table_hash = kOpcodeTableHash;
    h.opcode_count = kOpcodeCount;
    std::snprintf(h.registry, sizeof h.registry, "%s", GLCAST_REGISTRY_REVISION);
    return h;
}

// A second GL process writing to the same path (a program that starts another GL program)
// would interleave two streams: the first takes an exclusive lock, later ones write beside it.
static int open_locked(const std::string& path) {
    const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_CLOEXEC, 0644);
    if (fd < 0) throw std::runtime_error("cannot create " + path + ": " + std::strerror(errno));
    if (flock(fd, LOCK_EX | LOCK_NB) != 0) {
        ::close(fd);
        return -1;
    }
    if (ftruncate(fd, 0) != 0) {
        ::close(fd);
        throw std::runtime_error("cannot truncate " + path + ": " + std::strerror(errno));
    }
    return fd;
}

CaptureFileSink::CaptureFileSink(const std::string& path) : path_(path) {
    fd_ = open_locked(path_);
    if (fd_ < 0) {
        path_ = path + "." + std::to_string(getpid());
        std::fprintf(stderr, "glcast: %s is being written by another process; this one writes %s\n", path.c_str(),
                     path_.c_str());
        fd_ = open_locked(path_);
        if (fd_ < 0) throw std::runtime_error("cannot lock " + path_);
    }
    const FileHeader h = make_file_header();
    write_all(fd_, &h, sizeof h, path_);
}

CaptureFileSink::~CaptureFileSink() { close(); }

void CaptureFileSink::write(const std::vector<uint8_t>& message) {
    if (fd_ >= 0) write_all(fd_, message.data(), message.size(), path_);
}

void CaptureFileSink::close() {
    if (fd_ >= 0) ::close(fd_);
    fd_ = -1;
}

}  // namespace glcast
