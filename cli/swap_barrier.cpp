#include "cli/swap_barrier.h"

#include <zmq.hpp>

#include <chrono>
#include <cstdlib>
#include <map>
#include <vector>

namespace glcast::cli {

struct SwapBarrier::Sockets {
    zmq::context_t context{1};
    zmq::socket_t router{context, zmq::socket_type::router};
};

SwapBarrier::SwapBarrier(std::string endpoint, int tiles)
    : endpoint_(std::move(endpoint)), tiles_(tiles), sockets_(std::make_unique<Sockets>()) {
    sockets_->router.set(zmq::sockopt::linger, 0);
    try {
        sockets_->router.bind(endpoint_);
    } catch (const zmq::error_t& e) {
        throw std::runtime_error("swap barrier on " + endpoint_ + ": " + e.what());
    }
    thread_ = std::thread([this] { serve(); });
}

SwapBarrier::~SwapBarrier() {
    stopping_ = true;
    if (thread_.joinable()) thread_.join();
}

void SwapBarrier::serve() {
    zmq::socket_t& router = sockets_->router;
    std::map<uint64_t, std::vector<std::string>> ready;  // frame -> the tiles that have it
    while (!stopping_) {
        zmq::pollitem_t item{router.handle(), 0, ZMQ_POLLIN, 0};
        zmq::poll(&item, 1, std::chrono::milliseconds(100));
        if (!(item.revents & ZMQ_POLLIN)) continue;
        zmq::message_t identity, request;
        if (!router.recv(identity) || !router.get(zmq::sockopt::rcvmore) || !router.recv(request)) continue;
        const std::string what = request.to_string();
        if (what.rfind("READY ", 0) != 0) continue;
        const uint64_t frame = std::strtoull(what.c_str() + 6, nullptr, 10);
        auto& waiting = ready[frame];
        waiting.push_back(identity.to_string());
        if (int(waiting.size()) < tiles_) continue;
        const std::string go = "GO " + std::to_string(frame);
        for (const std::string& id : waiting) {
            router.send(zmq::buffer(id), zmq::send_flags::sndmore);
            router.send(zmq::buffer(go), zmq::send_flags::none);
        }
        ready.erase(ready.begin(), ready.upper_bound(frame));
    }
}

}  // namespace glcast::cli
