// The swap barrier of a wall (docs/wall.md): each tile's slave says "READY n" before it
// presents frame n and waits for "GO n", sent once every tile has said it. Served by
// `glcast run`, which outlives the program (slaves still present frames after it ended).
#pragma once

#include <atomic>
#include <memory>
#include <string>
#include <thread>

namespace glcast::cli {

class SwapBarrier {
public:
    SwapBarrier(std::string endpoint, int tiles);  // binds a ROUTER; throws std::runtime_error
    ~SwapBarrier();

private:
    void serve();
    std::string endpoint_;
    int tiles_;
    std::atomic<bool> stopping_{false};
    std::thread thread_;
    struct Sockets;
    std::unique_ptr<Sockets> sockets_;
};

}  // namespace glcast::cli
