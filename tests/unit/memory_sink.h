// A message sink that keeps every message the stream's writer hands it, for tests of the master's
// stream (tests/unit/inter_frame_test.cpp, stream_threads_test.cpp).
#pragma once

#include <cstdint>
#include <vector>

#include "master/stream.h"

namespace glcast {

class MemorySink : public MessageSink {
public:
    explicit MemorySink(std::vector<std::vector<uint8_t>>& out) : out_(out) {}
    void write(const std::vector<uint8_t>& message) override { out_.push_back(message); }

private:
    std::vector<std::vector<uint8_t>>& out_;
};

}  // namespace glcast
