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

void RunSession::start(const std::string& name, const std::vector<std::string>& argv, bool slave) {
    const pid_t pid = pid_t(spawn(argv));
    if (pid < 0) throw std::runtime_error("cannot start the " + name + ": " + std::strerror(errno));
    children_[pid] = Child{name, slave};
}

size_t RunSession::slaves() const {
    size_t n = 0;
    for (const auto& [pid, child] : children_) n += child.slave;
    return n;
}

int RunSession::wait_for_slaves(std::chrono::steady_clock::time_point deadline) {
    int failed = 0;
    while (slaves() > 0) {
        int status = 0;
        const pid_t pid = waitpid(-1, &status, WNOHANG);
        if (pid > 0) {
            auto it = children_.find(pid);
            if (it == children_.end()) continue;
            if (it->second.slave && !(WIFEXITED(status) && WEXITSTATUS(status) == 0)) {
                std::fprintf(stderr, "glcast run: slave %s failed\n", it->second.name.c_str());
                failed++;
            }
            children_.erase(it);  // a keeper that ended is reaped too; a failure is its own message
            continue;
        }
        if (std::chrono::steady_clock::now() > deadline) {
            for (const auto& [p, child] : children_)
                if (child.slave) {
                    std::fprintf(stderr, "glcast run: slave %s did not finish; stopping it\n", child.name.c_str());
                    failed++;
                }
            break;
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
    return failed;
}

void RunSession::stop_all(std::chrono::milliseconds grace) {
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
