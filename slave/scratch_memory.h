// Memory one replayed call uses and drops: its inputs copied for the driver, outputs for the
// driver to write, string lists. Blocks are kept from call to call (a replay allocates almost
// nothing once warm), 8-byte aligned and zeroed; a block larger than `retain_bytes` is freed
// after its call, so one large upload does not keep its size for the rest of the replay.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace glcast::slave {

class ScratchMemory {
public:
    explicit ScratchMemory(size_t retain_bytes) : retain_bytes_(retain_bytes) {}

    // `bytes` of zeroed memory, valid until end_call().
    void* take(size_t bytes);
    // The call is over: every block is free again, and the large ones are given back.
    void end_call();

    size_t blocks() const { return blocks_.size(); }
    size_t retained_bytes() const;  // capacity kept between calls

private:
    size_t retain_bytes_;
    std::vector<std::vector<uint64_t>> blocks_;
    size_t used_ = 0;
    bool grown_ = false;  // a block above retain_bytes_ was used
};

}  // namespace glcast::slave
