#include "master/stream.h"

#include <fcntl.h>
#include <pthread.h>
#include <sys/file.h>
#include <sys/resource.h>
#include <sys/syscall.h>
#include <unistd.h>
#include <zlib.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <stdexcept>

#include "glcast_commands.h"
#include "master/message_coder.h"
#include "protocol/format.h"

namespace glcast {

// A frame larger than this is split over several messages, bounding every allocation.
static constexpr size_t kBatchBytes = 8u << 20;

Stream::Stream(std::vector<std::unique_ptr<MessageSink>> sinks, int zstd_level, size_t queue_depth, bool inter_frame,
               int writer_nice)
    : queue_depth_(queue_depth ? queue_depth : 1), zstd_level_(zstd_level), inter_frame_(inter_frame),
      writer_nice_(writer_nice),
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

void Stream::drain() {
    uint64_t sealed = 0;
    {
        std::lock_guard lock(open_lock_);
        if (closed_) return;
        seal_open(false);
        std::lock_guard queue_lock(mutex_);
        sealed = next_sequence_;
    }
    std::unique_lock lock(mutex_);
    queue_changed_.wait(lock, [&] { return written_batches_ >= sealed || stopping_; });
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

// The writer thread: each batch coded against the one before it (master/message_coder.h),
// framed as a message and handed to every sink.
void Stream::writer_loop() {
    // Below the program's own threads: on a busy machine the program draws first, and the
    // writer takes what is left (the bounded queue still holds the program back if it is never
    // left anything).
    if (writer_nice_ > 0 && writer_nice_ < 20) setpriority(PRIO_PROCESS, pid_t(syscall(SYS_gettid)), writer_nice_);
    pthread_setname_np(pthread_self(), "glcast-writer");  // glcast's own, not the program's (interceptor/lifetime.h)
    MessageCoder coder(zstd_level_, inter_frame_);
    std::vector<uint8_t> message;  // header + stored payload, as the sinks take it
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
        const auto compress_start = std::chrono::steady_clock::now();
        uint32_t flags = 0;
        const size_t stored = coder.code(batch.sequence, batch.payload, flags);
        h.flags |= flags;
        const double compress_seconds =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - compress_start).count();
        // Sized to what is stored: a buffer of zstd's bound would zero-fill a raw frame a message.
        message.resize(sizeof h + stored);
        if (stored)
            std::memcpy(message.data() + sizeof h, (h.flags & kMsgCompressed) ? coder.coded() : batch.payload.data(),
                        stored);
        if (batch.frame_end) h.flags |= kMsgFrameEnd;
        h.stored_bytes = uint32_t(stored);
        h.crc32 = uint32_t(crc32(0, message.data() + sizeof h, uInt(stored)));
        std::memcpy(message.data(), &h, sizeof h);
        for (auto& s : sinks_) s->write(message);
        coder.next_prefix(batch.payload);  // the batch is done with: no copy
        std::lock_guard lock(mutex_);
        if (spare_.capacity() < batch.payload.capacity()) spare_.swap(batch.payload);  // the older prefix, for reuse
        stats_.messages++;
        stats_.stored_bytes += message.size();
        stats_.compress_seconds += compress_seconds;
        stats_.compressions += coder.compressions();
        in_flight_--;
        written_batches_++;
        queue_changed_.notify_all();
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
    FileHeader h = make_file_header();
    h.features |= kFileHasEndRecord;
    if (!write_whole(&h, sizeof h)) throw std::runtime_error("cannot write " + path_ + "'s header");
}

CaptureFileSink::~CaptureFileSink() { close(); }

bool CaptureFileSink::write_whole(const void* data, size_t size) {
    if (failed_ || fd_ < 0) return false;
    auto p = static_cast<const uint8_t*>(data);
    for (size_t n = size; n;) {
        const ssize_t w = ::write(fd_, p, n);
        if (w < 0 && errno == EINTR) continue;
        if (w <= 0) {
            const int error = w < 0 ? errno : ENOSPC;
            failed_ = true;
            const bool cut = ::ftruncate(fd_, off_t(whole_bytes_)) == 0;
            std::fprintf(stderr, "glcast: writing %s: %s; the capture stops%s %llu whole messages (the program goes on)\n",
                         path_.c_str(), std::strerror(error), cut ? ", the file keeps its first" : " after",
                         (unsigned long long)next_sequence_);
            ::close(fd_);
            fd_ = -1;
            return false;
        }
        p += w;
        n -= size_t(w);
    }
    whole_bytes_ += size;
    return true;
}

void CaptureFileSink::write(const std::vector<uint8_t>& message) {
    if (!write_whole(message.data(), message.size())) return;
    MessageHeader h{};
    if (message.size() < sizeof h) return;
    std::memcpy(&h, message.data(), sizeof h);
    next_sequence_ = h.sequence + 1;
    next_frame_ = h.frame + ((h.flags & kMsgFrameEnd) ? 1 : 0);
}

void CaptureFileSink::close() {
    if (fd_ < 0) return;
    MessageHeader end{};
    end.magic = kMessageMagic;
    end.sequence = next_sequence_;
    end.frame = next_frame_;
    end.flags = kMsgStreamEnd;  // no payload: stored, raw and the CRC of nothing are 0
    if (write_whole(&end, sizeof end)) {
        ::close(fd_);
        fd_ = -1;
    }
}

}  // namespace glcast
