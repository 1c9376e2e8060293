// A journal message sent without a copy: libzmq holds a reference to the shared message and
// releases it (from its I/O thread) once the message is on the wire or dropped.
#pragma once

#include <zmq.hpp>

#include <cstdint>
#include <memory>
#include <vector>

namespace glcast {

inline void release_shared_message(void*, void* hint) {
    delete static_cast<std::shared_ptr<const std::vector<uint8_t>>*>(hint);
}

inline zmq::message_t zero_copy_message(const std::shared_ptr<const std::vector<uint8_t>>& m) {
    return zmq::message_t(const_cast<uint8_t*>(m->data()), m->size(), release_shared_message,
                          new std::shared_ptr<const std::vector<uint8_t>>(m));
}

}  // namespace glcast
