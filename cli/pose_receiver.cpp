#include "cli/pose_receiver.h"

#include <zmq.hpp>

#include <chrono>
#include <cstdio>

#include "display_configs/head_poses.h"

namespace glcast::cli {

struct PoseReceiver::Sockets {
    zmq::context_t context{1};
    std::unique_ptr<net::Authenticator> authenticator;  // before the socket: ZAP must be bound first
    zmq::socket_t pull{context, zmq::socket_type::pull};
};

PoseReceiver::PoseReceiver(std::string endpoint, const net::Security& security)
    : endpoint_(std::move(endpoint)), sockets_(std::make_unique<Sockets>()) {
    try {
        sockets_->authenticator = net::authenticator_for(sockets_->context, "the wall's pose socket", security);
        zmq::socket_t& pull = sockets_->pull;
        pull.set(zmq::sockopt::linger, 0);
        pull.set(zmq::sockopt::maxmsgsize, int64_t(slave::kMaxPoseBytes));  // a longer one drops its sender
        pull.set(zmq::sockopt::rcvhwm, 64);
        net::secure_server(pull, endpoint_, security);
        pull.bind(endpoint_);
        bound_ = pull.get(zmq::sockopt::last_endpoint);
    } catch (const std::exception& e) {
        throw std::runtime_error("the wall's pose socket on " + endpoint_ + ": " + e.what());
    }
    thread_ = std::thread([this] { serve(); });
}

PoseReceiver::~PoseReceiver() {
    stopping_ = true;
    if (thread_.joinable()) thread_.join();
}

bool PoseReceiver::latest(slave::HeadPose& out) const {
    std::lock_guard lock(mutex_);
    if (has_pose_) out = pose_;
    return has_pose_;
}

uint64_t PoseReceiver::unauthenticated() const {
    return sockets_->authenticator ? sockets_->authenticator->refused() : 0;
}

void PoseReceiver::serve() {
    zmq::socket_t& pull = sockets_->pull;
    while (!stopping_) {
        zmq::pollitem_t item{pull.handle(), 0, ZMQ_POLLIN, 0};
        zmq::poll(&item, 1, std::chrono::milliseconds(50));
        for (int n = 0; n < 256 && (item.revents & ZMQ_POLLIN); n++) {
            zmq::message_t message;
            if (!pull.recv(message, zmq::recv_flags::dontwait)) break;
            bool one_part = !pull.get(zmq::sockopt::rcvmore);
            while (pull.get(zmq::sockopt::rcvmore)) (void)pull.recv(message);  // extra parts: read and refused
            slave::HeadPose pose;
            std::string error = "a message of several parts";
            if (one_part && slave::parse_head_pose(message.to_string(), pose, nullptr, nullptr, error)) {
                std::lock_guard lock(mutex_);
                pose_ = pose;
                has_pose_ = true;
                accepted_++;
                continue;
            }
            if (refused_++ == 0)
                std::fprintf(stderr, "\nglcast run: pose socket: a pose refused (%s); the last good one holds "
                                     "(refusals are counted from now on)\n", error.c_str());
        }
    }
}

}  // namespace glcast::cli
