// What one `glcast run` owns: its temporary folder (IPC sockets) and the processes it started
// (a slave per local tile, a keeper). Whatever way run() ends, an error return included, the
// destructor stops every child still running (SIGTERM, then SIGKILL after a grace), reaps it,
// and removes the folder with what is in it.
//
// A kept child (the keeper) is started again a second after it is killed or fails, as systemd's
// Restart=on-failure would, until end_keeping(): slaves that join later need it, and nothing else
// on this machine would notice it gone. One that ends within 10 s of its start three times in a
// row or more is started again after a longer wait each time (5, 10, 20, then every 30 s), never
// given up on: a keeper killed from outside in quick succession ends as one that crashes does,
// and a wall that lost its keeper for good could not let a tile join for the rest of the program.
#pragma once

#include <sys/types.h>

#include <chrono>
#include <condition_variable>
#include <map>
#include <mutex>
#include <string>
#include <thread>
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
    // Starts argv as a kept child (above).
    void keep(const std::string& name, const std::vector<std::string>& argv);
    // Kept children are no longer started again (the program has ended: they end with its stream).
    void end_keeping();
    size_t slaves() const;
    // Waits until every slave has exited or `deadline`; those still running then are stopped.
    // Returns how many failed (exited non-zero, or were stopped). The keeper is not waited for.
    int wait_for_slaves(std::chrono::steady_clock::time_point deadline);
    // Stops every child still running (kept ones are no longer kept): SIGTERM, SIGKILL after
    // `grace`, each reaped.
    void stop_all(std::chrono::milliseconds grace = std::chrono::milliseconds(2000));

private:
    struct Child {
        std::string name;
        bool slave = false;
        bool kept = false;
        std::vector<std::string> argv;
        std::chrono::steady_clock::time_point started;
        int quick_failures = 0;  // in a row, each within 10 s of its start
    };
    void watch_kept();
    pid_t start_locked(Child child);

    std::string dir_;
    mutable std::mutex mutex_;  // children_ and keeping_: the watcher thread restarts kept children
    std::map<pid_t, Child> children_;
    bool keeping_ = false;
    std::condition_variable keeping_ended_;  // wakes the watcher from a wait before a restart
    std::thread watcher_;
};

}  // namespace glcast::cli
