#include "master/journal.h"

#include <algorithm>
#include <cstring>

#include "protocol/format.h"

namespace glcast {

namespace {

bool is_delta(const std::vector<uint8_t>& message) {
    MessageHeader h{};
    if (message.size() >= sizeof h) std::memcpy(&h, message.data(), sizeof h);
    return (h.flags & (kMsgDelta | kMsgXor)) != 0;  // coded against the message before it
}

}  // namespace

bool Journal::append(Shared message, uint64_t sequence) {
    std::deque<Shared> gone;  // freed after the lock is released
    bool first_loss = false;
    std::lock_guard lock(mutex_);
    if (messages_.empty()) first_ = sequence;
    bytes_ += message->size();
    messages_.push_back(std::move(message));
    while (bytes_ > limit_bytes_ && messages_.size() > 1) {
        first_loss |= first_ == 0;
        bytes_ -= messages_.front()->size();
        gone.push_back(std::move(messages_.front()));
        messages_.pop_front();
        first_++;
    }
    return first_loss;
}

uint64_t Journal::end_now() const {
    std::lock_guard lock(mutex_);
    return first_ + messages_.size();
}

uint64_t Journal::start_for(uint64_t wanted, uint64_t end) const {
    std::lock_guard lock(mutex_);
    if (end <= first_ || wanted < first_) return wanted;
    // From the key at or before the one asked for (or before the newest, when the one asked for
    // is yet to come, coded against the newest).
    uint64_t at = std::min(wanted, end - 1);
    while (at > first_ && is_delta(*messages_[size_t(at - first_)])) at--;
    if (is_delta(*messages_[size_t(at - first_)])) return first_ > 0 ? first_ - 1 : end + 1;  // the key is gone
    return std::min(wanted, at);
}

size_t Journal::take(uint64_t next, uint64_t end, Shared* out, size_t at_most, bool& held) const {
    std::lock_guard lock(mutex_);
    held = next >= first_ && next <= end;
    size_t n = 0;
    if (held)
        for (; n < at_most && next + n < end; n++) out[n] = messages_[size_t(next + n - first_)];
    return n;
}

}  // namespace glcast
