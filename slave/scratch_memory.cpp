#include "slave/scratch_memory.h"

namespace glcast::slave {

void* ScratchMemory::take(size_t bytes) {
    if (used_ == blocks_.size()) blocks_.emplace_back();
    std::vector<uint64_t>& block = blocks_[used_++];
    block.assign(bytes / 8 + 2, 0);
    if (bytes > retain_bytes_) grown_ = true;
    return block.data();
}

void ScratchMemory::end_call() {
    used_ = 0;
    if (!grown_) return;
    grown_ = false;
    const size_t keep = retain_bytes_ / 8 + 2;
    for (std::vector<uint64_t>& block : blocks_)
        if (block.capacity() > keep) std::vector<uint64_t>().swap(block);
}

size_t ScratchMemory::retained_bytes() const {
    size_t n = 0;
    for (const std::vector<uint64_t>& block : blocks_) n += block.capacity() * 8;
    return n;
}

}  // namespace glcast::slave
