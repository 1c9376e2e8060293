#include "net/wall_endpoints.h"

#include <stdexcept>

namespace glcast::net {

namespace {

const char* const kSuffix[] = {"", "-journal", "-keeper", "-control"};

bool starts_with(const std::string& s, const char* prefix) { return s.rfind(prefix, 0) == 0; }

// The port after the last ':' of `endpoint`; -1 when there is none.
int port_of(const std::string& endpoint, size_t& colon) {
    colon = endpoint.rfind(':');
    if (colon == std::string::npos || colon + 1 >= endpoint.size() || endpoint.size() - colon > 6) return -1;
    int port = 0;
    for (size_t i = colon + 1; i < endpoint.size(); ++i) {
        if (endpoint[i] < '0' || endpoint[i] > '9') return -1;
        port = port * 10 + (endpoint[i] - '0');
    }
    return port;
}

}  // namespace

std::string wall_channel(const std::string& stream, WallChannel channel) {
    const int k = int(channel);
    if (starts_with(stream, "ipc://")) return k == 0 ? stream : stream + kSuffix[k];
    const bool multicast = starts_with(stream, "epgm://") || starts_with(stream, "pgm://");
    if (!multicast && !starts_with(stream, "tcp://"))
        throw std::invalid_argument("endpoint " + stream + ": not tcp://, epgm://, pgm:// or ipc://");
    size_t colon = 0;
    const int port = port_of(stream, colon);
    if (port < 1 || port > 65532)
        throw std::invalid_argument("endpoint " + stream +
                                    ": needs a port from 1 to 65532 (it and the next three are the wall's channels)");
    if (k == 0) return stream;
    if (multicast) {  // epgm://INTERFACE;GROUP:PORT: the side channels on the interface's address
        const size_t scheme = stream.find("://") + 3;
        const size_t semicolon = stream.find(';', scheme);
        if (semicolon == std::string::npos || semicolon > colon)
            throw std::invalid_argument("endpoint " + stream + ": multicast is INTERFACE;GROUP:PORT");
        return "tcp://" + stream.substr(scheme, semicolon - scheme) + ":" + std::to_string(port + k);
    }
    return stream.substr(0, colon + 1) + std::to_string(port + k);
}

WallEndpoints wall_endpoints(const std::string& stream) {
    WallEndpoints e;
    e.stream = wall_channel(stream, WallChannel::stream);
    e.journal = wall_channel(stream, WallChannel::journal);
    e.keeper = wall_channel(stream, WallChannel::keeper);
    e.control = wall_channel(stream, WallChannel::control);
    e.reachable = !starts_with(stream, "ipc://");
    return e;
}

WallEndpoints wall_endpoints_at(const std::string& host, int port) {
    return wall_endpoints("tcp://" + host + ":" + std::to_string(port));
}

std::string connectable(const std::string& bound) {
    const size_t star = bound.find("://*");
    return star == std::string::npos ? bound : bound.substr(0, star) + "://127.0.0.1" + bound.substr(star + 4);
}

}  // namespace glcast::net
