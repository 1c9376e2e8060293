// The master's side of the stream: tuples appended by application threads are batched into
// messages (a frame ends at a swap, a large frame is split), and a writer thread compresses
// and hands each message to the sinks (capture file now; the ZeroMQ publisher later) behind
// a bounded queue, so encoding is the only work on the application's threads.
#pragma once

#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "common/byte_vector.h"
#include "common/spin_lock.h"

namespace glcast {

class MessageSink {
public:
    virtual ~MessageSink() = default;
    // header + stored payload of one message, as framed by protocol/format.h
    virtual void write(const std::vector<uint8_t>& message) = 0;
    virtual void close() {}
};

struct StreamStats {
    uint64_t frames = 0, tuples = 0, raw_bytes = 0, stored_bytes = 0, messages = 0;
    uint64_t unserialized = 0, array_cache_hits = 0, array_cache_misses = 0;
    double compress_seconds = 0;  // the writer thread's time compressing (all messages)
    uint64_t compressions = 0;    // zstd runs by the writer (a coded message may be compressed two ways)
};

class Stream {
public:
    // inter_frame: code messages against the previous one (format version 2; GLCAST_INTER_FRAME=0
    // turns it off, for comparison). writer_nice: the writer thread runs below the program's own
    // threads by this nice value (0: beside them).
    Stream(std::vector<std::unique_ptr<MessageSink>> sinks, int zstd_level, size_t queue_depth, bool inter_frame = true,
           int writer_nice = 10);
    ~Stream();

    void append(const uint8_t* tuple, size_t bytes);  // one whole tuple; thread-safe
    void end_frame();                                  // after a swap's tuple
    void flush();                                      // seal the open batch, wait for the writer
    // Seal the open batch and wait until the writer has handed every batch sealed so far to the
    // sinks (not those other threads seal meanwhile: it ends while they go on recording).
    void drain();
    void close();                                      // flush, stop the writer, close sinks
    uint64_t frame() const;
    StreamStats stats() const;
    void count_cache(bool hit);
    void count_unserialized();

private:
    void seal_open(bool frame_end);  // with open_lock_ held
    void writer_loop();

    struct Batch {
        ByteVector payload;
        uint64_t sequence;
        uint32_t frame;
        bool frame_end;
    };

    // Two locks: open_lock_ over the batch being filled, which the program's threads take once a
    // call; mutex_ over the queue and the writer's side, taken once a batch (and per frame).
    // Always open_lock_ first.
    mutable SpinLock open_lock_;
    ByteVector open_;                 // the batch being filled
    uint32_t open_frame_ = 0;
    uint64_t open_tuples_ = 0, open_raw_bytes_ = 0;  // not yet in stats_
    bool closed_ = false;

    mutable std::mutex mutex_;
    std::condition_variable queue_changed_;
    ByteVector spare_;                // a payload buffer the writer is done with, for the next batch
    std::deque<Batch> queue_;
    size_t queue_depth_;
    size_t in_flight_ = 0;
    bool stopping_ = false;
    uint64_t next_sequence_ = 0;
    uint64_t written_batches_ = 0;  // handed to the sinks (batches are written in sequence order)
    StreamStats stats_;
    int zstd_level_;
    bool inter_frame_;
    int writer_nice_;
    std::vector<std::unique_ptr<MessageSink>> sinks_;
    std::thread writer_;
};

struct FileHeader;
FileHeader make_file_header();  // the header this build writes (magic, version, table hash)

// Writes a capture file: the file header, then each message as it arrives.
class CaptureFileSink : public MessageSink {
public:
    explicit CaptureFileSink(const std::string& path);
    ~CaptureFileSink() override;
    // A message that cannot be written whole (a full disk) stops the capture: the file is cut
    // back to its last whole message and nothing more is written; the program goes on.
    void write(const std::vector<uint8_t>& message) override;
    void close() override;  // a capture not stopped ends with its end record
    bool failed() const { return failed_.load(std::memory_order_relaxed); }  // any thread

private:
    bool write_whole(const void* data, size_t size);  // false: stopped, the file cut back
    std::string path_;
    int fd_ = -1;
    std::atomic<bool> failed_{false};  // set by the writer thread
    uint64_t whole_bytes_ = 0;  // the file up to its last whole message
    uint64_t next_sequence_ = 0, next_frame_ = 0;  // what the end record says it follows
};

}  // namespace glcast
