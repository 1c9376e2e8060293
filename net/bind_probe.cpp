#include "net/bind_probe.h"

#include <zmq.hpp>

#include <stdexcept>

namespace glcast::net {

void check_can_bind(const std::string& endpoint, const std::string& role) {
    if (endpoint.rfind("tcp://", 0) != 0) return;
    zmq::context_t context;
    zmq::socket_t probe(context, zmq::socket_type::pull);
    probe.set(zmq::sockopt::linger, 0);
    try {
        probe.bind(endpoint);
    } catch (const zmq::error_t& e) {
        const std::string port = endpoint.substr(endpoint.rfind(':') + 1);
        std::string why = e.what();
        if (e.num() == EADDRINUSE)
            why += " (another program, or another wall, listens there: give this wall another port)";
        else if (e.num() == EADDRNOTAVAIL)
            why += " (not an address of this machine)";
        throw std::runtime_error("the wall's " + role + " cannot listen on port " + port + " (" + endpoint + "): " + why);
    }
    // Closed here, and released before the context ends (its I/O thread closes the listener).
}

}  // namespace glcast::net
