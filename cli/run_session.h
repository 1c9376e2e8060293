// What one `glcast run` owns: its temporary folder (IPC sockets) and the processes it started
// (a slave per local tile, a keeper). Whatever way run() ends, an error return included, the
// destructor stops every child still running (SIGTERM, then SIGKILL after a grace), reaps it,
// and removes the folder with what is in it.
#pragma once

#include <sys/types.h>

#include <chrono>
#include <map>
#include <string>
#include <vector>

namespace glcast::cli {

class RunSession {
public:
    // Makes the temporary folder; throws std::runtime_error naming why it cannot.
    RunSession();
    ~RunSession();
    RunSession(const RunSession&) = delete;
    RunSession& operator=(const RunSession&) = delete;

    const std::string& dir() const { return dir_; }
    // Starts argv (argv[0] a path) as a child called `name` in messages.
    void start(const std::string& name, const std::vector<std::string>& argv, bool slave);
    size_t slaves() const;
    // Waits until every slave has exited or `deadline`; those still running then are stopped.
    // Returns how many failed (exited non-zero, or were stopped). The keeper is not waited for.
    int wait_for_slaves(std::chrono::steady_clock::time_point deadline);
    // Stops every child still running: SIGTERM, SIGKILL after `grace`, each reaped.
    void stop_all(std::chrono::milliseconds grace = std::chrono::milliseconds(2000));

private:
    struct Child {
        std::string name;
        bool slave = false;
    };
    std::string dir_;
    std::map<pid_t, Child> children_;
};

}  // namespace glcast::cli
