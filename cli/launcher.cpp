#include "cli/launcher.h"

#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <climits>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>

#include "common/environment.h"

namespace glcast::cli {

static bool readable(const std::string& p) { return access(p.c_str(), R_OK) == 0; }

std::string shim_path() {
    if (const std::string& p = environment().shim; !p.empty()) return p;
    char exe[PATH_MAX] = {};
    const ssize_t n = readlink("/proc/self/exe", exe, sizeof exe - 1);
    if (n > 0) {
        std::string dir(exe, size_t(n));
        dir = dir.substr(0, dir.rfind('/'));
        // Beside it (the build tree), or where the install rules put it (GNUInstallDirs).
        for (const char* rel : {"/libglcast.so", "/" GLCAST_SHIM_FROM_BIN "/libglcast.so"})
            if (readable(dir + rel)) return dir + rel;
    }
    return std::string(GLCAST_LIBDIR) + "/libglcast.so";
}

namespace {

volatile sig_atomic_t g_program = 0;  // the program run_with_shim waits for

void pass_on(int sig) {
    if (g_program > 0) kill(pid_t(g_program), sig);
}

}  // namespace

int run_with_shim(const std::vector<std::string>& argv, const std::map<std::string, std::string>& env) {
    const std::string shim = shim_path();
    if (!readable(shim)) {
        std::fprintf(stderr, "glcast: the shim %s is missing (set GLCAST_SHIM or build target glcast)\n", shim.c_str());
        return -1;
    }
    const pid_t pid = fork();
    if (pid < 0) {
        std::fprintf(stderr, "glcast: fork: %s\n", std::strerror(errno));
        return -1;
    }
    if (pid == 0) {
        std::string preload = shim;
        if (const char* old = std::getenv("LD_PRELOAD"); old && *old) preload += std::string(":") + old;
        setenv("LD_PRELOAD", preload.c_str(), 1);
        for (const auto& [k, v] : env) setenv(k.c_str(), v.c_str(), 1);
        std::vector<char*> args;
        for (const auto& a : argv) args.push_back(const_cast<char*>(a.c_str()));
        args.push_back(nullptr);
        execvp(args[0], args.data());
        std::fprintf(stderr, "glcast: cannot run %s: %s\n", args[0], std::strerror(errno));
        _exit(127);
    }
    // Ctrl-C reaches the program (same process group); we only wait for it. A SIGTERM or SIGHUP
    // sent to glcast alone (timeout(1), a service manager) is passed on: the program ends, and
    // whatever glcast does after it (finishing a capture) still runs.
    signal(SIGINT, SIG_IGN);
    g_program = pid;
    struct sigaction pass{}, old_term{}, old_hup{};
    pass.sa_handler = pass_on;
    sigemptyset(&pass.sa_mask);
    sigaction(SIGTERM, &pass, &old_term);
    sigaction(SIGHUP, &pass, &old_hup);
    int status = 0;
    bool waited = true;
    while (waitpid(pid, &status, 0) < 0)
        if (errno != EINTR) {
            waited = false;
            break;
        }
    sigaction(SIGTERM, &old_term, nullptr);
    sigaction(SIGHUP, &old_hup, nullptr);
    g_program = 0;
    signal(SIGINT, SIG_DFL);
    if (!waited) return -1;
    if (WIFEXITED(status)) return WEXITSTATUS(status);
    if (WIFSIGNALED(status)) return 128 + WTERMSIG(status);
    return -1;
}

std::string self_exe() {
    char exe[PATH_MAX] = {};
    const ssize_t n = readlink("/proc/self/exe", exe, sizeof exe - 1);
    return n > 0 ? std::string(exe, size_t(n)) : "glcast";
}

int spawn(const std::vector<std::string>& argv) {
    const pid_t pid = fork();
    if (pid == 0) {
        std::vector<char*> args;
        for (const auto& a : argv) args.push_back(const_cast<char*>(a.c_str()));
        args.push_back(nullptr);
        execv(args[0], args.data());
        std::fprintf(stderr, "glcast: cannot start %s: %s\n", args[0], std::strerror(errno));
        _exit(127);
    }
    return pid;
}

}  // namespace glcast::cli
