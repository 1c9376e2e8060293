// The processes and files of one `glcast run` (run_session.h).
#include "cli/run_session.h"

#include <dirent.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <algorithm>
#include <stdexcept>
#include <thread>

#include "cli/launcher.h"

namespace glcast::cli {

// In $TMPDIR when it is set (an absolute path), else /tmp. (Its IPC socket paths must stay
// within the 107 bytes a Unix socket's name may have.)
RunSession::RunSession() {
    const char* tmp = std::getenv("TMPDIR");
    std::string dir = (tmp && tmp[0] == '/' ? std::string(tmp) : std::string("/tmp")) + "/glcast-run-XXXXXX";
    if (dir.size() > 80) throw std::runtime_error("TMPDIR " + std::string(tmp) + " is too long for the run's sockets");
    if (!mkdtemp(dir.data())) throw std::runtime_error("mkdtemp " + dir + ": " + std::strerror(errno));
    dir_ = dir;
}

RunSession::~RunSession() {
    stop_all();
    // The folder holds only the sockets of this run (flat, no subfolders).
    if (DIR* d = opendir(dir_.c_str())) {
        while (const dirent* e = readdir(d))
            if (std::strcmp(e->d_name, ".") != 0 && std::strcmp(e->d_name, "..") != 0)
                ::unlink((dir_ + "/" + e->d_name).c_str());
        closedir(d);
    }
    ::rmdir(dir_.c_str());
}

pid_t RunSession::start_locked(Child child) {
    const pid_t pid = pid_t(spawn(child.argv));
    if (pid < 0) throw std::runtime_error("cannot start the " + child.name + ": " + std::strerror(errno));
    child.started = std::chrono::steady_clock::now();
    children_[pid] = std::move(child);
    return pid;
}

void RunSession::start(const std::string& name, const std::vector<std::string>& argv, bool slave) {
    std::lock_guard<std::mutex> lock(mutex_);
    start_locked(Child{name, slave, false, argv, {}, 0});
}

void RunSession::keep(const std::string& name, const std::vector<std::string>& argv) {
    std::lock_guard<std::mutex> lock(mutex_);
    keeping_ = true;
    start_locked(Child{name, false, true, argv, {}, 0});
    if (!watcher_.joinable()) watcher_ = std::thread([this] { watch_kept(); });
}

void RunSession::end_keeping() {
    {
        std::lock_guard<std::mutex> lock(mutex_);
        keeping_ = false;
    }
    keeping_ended_.notify_all();
    if (watcher_.joinable()) watcher_.join();
}

namespace {

// How long before a kept child is started again, after `quick_failures` ends in a row each
// within 10 s of its start: 1 s, and from the third on 5, 10, 20, then 30 s.
std::chrono::seconds restart_delay(int quick_failures) {
    if (quick_failures < 3) return std::chrono::seconds(1);
    return std::chrono::seconds(std::min(30, 5 << std::min(quick_failures - 3, 3)));
}

}  // namespace

// Each kept child is waited for by its own pid (never waitpid(-1): the program and the slaves are
// waited for elsewhere).
void RunSession::watch_kept() {
    for (;;) {
        std::this_thread::sleep_for(std::chrono::milliseconds(100));
        std::unique_lock<std::mutex> lock(mutex_);
        if (!keeping_) return;
        for (auto it = children_.begin(); it != children_.end();) {
            Child& c = it->second;
            int status = 0;
            if (!c.kept || waitpid(it->first, &status, WNOHANG) != it->first) {
                ++it;
                continue;
            }
            Child ended = std::move(c);
            it = children_.erase(it);
            if (WIFEXITED(status) && WEXITSTATUS(status) == 0) continue;  // it ended with the stream
            const bool quick = std::chrono::steady_clock::now() - ended.started < std::chrono::seconds(10);
            ended.quick_failures = quick ? ended.quick_failures + 1 : 0;
            char why[64];
            if (WIFSIGNALED(status)) std::snprintf(why, sizeof why, "was killed (signal %d)", WTERMSIG(status));
            else std::snprintf(why, sizeof why, "failed (exit %d)", WEXITSTATUS(status));
            const std::chrono::seconds delay = restart_delay(ended.quick_failures);
            std::fprintf(stderr, "glcast run: the %s %s%s; starting it again in %lld s\n", ended.name.c_str(), why,
                         ended.quick_failures >= 3 ? ", again within 10 s of its start" : "",
                         static_cast<long long>(delay.count()));
            // The lock is let go while it waits: stop_all and the slaves' reaping go on meanwhile,
            // and end_keeping() ends the wait at once.
            if (keeping_ended_.wait_for(lock, delay, [this] { return !keeping_; })) return;
            try {
                start_locked(std::move(ended));
            } catch (const std::exception& e) {
                std::fprintf(stderr, "glcast run: %s\n", e.what());
            }
            break;  // children_ changed: look again at the next tick
        }
    }
}

size_t RunSession::slaves() const {
    std::lock_guard<std::mutex> lock(mutex_);
    size_t n = 0;
    for (const auto& [pid, child] : children_) n += child.slave;
    return n;
}

int RunSession::wait_for_slaves(std::chrono::steady_clock::time_point deadline) {
    int failed = 0;
    while (slaves() > 0) {
        {
            std::lock_guard<std::mutex> lock(mutex_);
            // Each child by its pid: the program is waited for elsewhere. A keeper that ended is
            // reaped too; a failure of one is its own message.
            for (auto it = children_.begin(); it != children_.end();) {
                int status = 0;
                if (it->second.kept && keeping_) {
                    ++it;
                    continue;
                }
                if (waitpid(it->first, &status, WNOHANG) != it->first) {
                    ++it;
                    continue;
                }
                if (it->second.slave && !(WIFEXITED(status) && WEXITSTATUS(status) == 0)) {
                    std::fprintf(stderr, "glcast run: slave %s failed\n", it->second.name.c_str());
                    failed++;
                }
                it = children_.erase(it);
            }
            if (std::chrono::steady_clock::now() > deadline) {
                for (const auto& [p, child] : children_)
                    if (child.slave) {
                        std::fprintf(stderr, "glcast run: slave %s did not finish; stopping it\n", child.name.c_str());
                        failed++;
                    }
                break;
            }
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
    return failed;
}

void RunSession::stop_all(std::chrono::milliseconds grace) {
    end_keeping();
    std::lock_guard<std::mutex> lock(mutex_);
    for (const auto& [pid, child] : children_) kill(pid, SIGTERM);
    const auto until = std::chrono::steady_clock::now() + grace;
    while (!children_.empty()) {
        for (auto it = children_.begin(); it != children_.end();)
            it = waitpid(it->first, nullptr, WNOHANG) != 0 ? children_.erase(it) : std::next(it);
        if (children_.empty()) break;
        if (std::chrono::steady_clock::now() > until) {
            for (const auto& [pid, child] : children_) {
                kill(pid, SIGKILL);
                waitpid(pid, nullptr, 0);
            }
            children_.clear();
            break;
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
}

}  // namespace glcast::cli
