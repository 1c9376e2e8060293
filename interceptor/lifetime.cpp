#include "interceptor/lifetime.h"

#include <dirent.h>
#include <fcntl.h>
#include <pthread.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <thread>

#include "glcast_commands.h"
#include "interceptor/config.h"
#include "interceptor/shim.h"
#include "interceptor/shim_internal.h"
#include "protocol/command_info.h"

extern "C" int __cxa_atexit(void (*fn)(void*), void* arg, void* dso_handle);

namespace glcast {

namespace {

// The calling thread's state, found with one instruction: a trivial pointer in the initial-exec
// TLS model (the shim is preloaded, so it has static TLS; 8 bytes fit glibc's surplus even if
// something dlopens it). A thread_local object with a constructor costs a __tls_get_addr call and
// a guard test on every access (8% of a glVertex3f's time in the shim, bench/call_cost.c under
// perf), and glibc destroys it before the thread's exit handlers and before the program's atexit
// handlers, which make GL calls.
[[gnu::tls_model("initial-exec")]] thread_local ThreadState* t_state = nullptr;

pthread_key_t g_thread_exit_key;
pthread_once_t g_thread_exit_key_once = PTHREAD_ONCE_INIT;

// A pthread key's destructor: runs as a thread exits (pthread_exit or a return from its start
// function), after its thread_local destructors, in a round with the program's own key
// destructors. A later call of this thread makes a new state, and setting the key again makes
// glibc run this once more (up to PTHREAD_DESTRUCTOR_ITERATIONS rounds; a state made after the
// last round is left to the process, one per such thread).
void thread_exits(void* state) {
    t_state = nullptr;
    delete static_cast<ThreadState*>(state);
}

void make_thread_exit_key() { pthread_key_create(&g_thread_exit_key, thread_exits); }

[[gnu::noinline]] ThreadState& adopt_thread() {
    pthread_once(&g_thread_exit_key_once, make_thread_exit_key);
    auto* state = new ThreadState;
    t_state = state;
    pthread_setspecific(g_thread_exit_key, state);
    return *state;
}

// hold_across_fork's mutexes: a fixed table, so that registering allocates nothing and the
// table needs no destructor.
constexpr int kMaxForkMutexes = 8;
std::mutex* g_fork_mutexes[kMaxForkMutexes];
int g_fork_mutex_count = 0;
std::atomic<bool> g_forked_child{false};

void before_fork() {
    for (int i = 0; i < g_fork_mutex_count; ++i) g_fork_mutexes[i]->lock();
}
void after_fork_in_parent() {
    for (int i = g_fork_mutex_count; i-- > 0;) g_fork_mutexes[i]->unlock();
}
void after_fork_in_child() {
    for (int i = g_fork_mutex_count; i-- > 0;) g_fork_mutexes[i]->unlock();
    if (!g_recording) return;  // a shim that records nothing has nothing that is its parent's
    g_recording = false;
    g_forked_child.store(true, std::memory_order_relaxed);
}

std::atomic<uint64_t> g_calls_after_end{0};

// glibc ends a process with exit(0) when its last thread exits; glcast's own threads (the stream's
// writer, the journal, ZeroMQ's) would keep a program alive that ended that way. A thread of ours
// looks, four times a second, whether every live thread left is glcast's, and if so does what
// glibc would have done. Threads are told apart by name ("glcast-*", and ZeroMQ's "ZMQbg/*" when
// the shim publishes); a zombie main thread (after its pthread_exit) is not alive.
std::atomic<bool> g_watching{false};
bool g_publishing = false;

bool ours(const char* name) {
    return std::strncmp(name, "glcast-", 7) == 0 || (g_publishing && std::strncmp(name, "ZMQbg/", 6) == 0);
}

bool only_ours_left() {
    DIR* tasks = opendir("/proc/self/task");
    if (!tasks) return false;
    bool only = true;
    while (dirent* e = readdir(tasks)) {
        if (e->d_name[0] == '.') continue;
        char path[300], stat[512] = {}, name[32] = {};
        std::snprintf(path, sizeof path, "/proc/self/task/%s/stat", e->d_name);
        const int fd = ::open(path, O_RDONLY | O_CLOEXEC);
        if (fd < 0) continue;  // gone meanwhile
        const ssize_t n = ::read(fd, stat, sizeof stat - 1);
        ::close(fd);
        // "tid (comm) S ...": the name may hold spaces and parentheses; the state follows the last ')'.
        const char* open = n > 0 ? std::strchr(stat, '(') : nullptr;
        const char* close = n > 0 ? std::strrchr(stat, ')') : nullptr;
        if (!open || !close || close < open || close[1] != ' ') continue;
        if (close[2] == 'Z' || close[2] == 'X') continue;  // exited, not yet reaped
        std::memcpy(name, open + 1, std::min<size_t>(size_t(close - open - 1), sizeof name - 1));
        if (!ours(name)) {
            only = false;
            break;
        }
    }
    closedir(tasks);
    return only;
}

void watch_last_thread() {
    pthread_setname_np(pthread_self(), "glcast-watch");
    while (g_watching.load(std::memory_order_relaxed)) {
        usleep(250 * 1000);
        if (g_watching.load(std::memory_order_relaxed) && only_ours_left()) exit(0);
    }
}

// The thread that runs the exit handlers (set before the flags that say it is known).
pthread_t g_exiting_thread;
std::atomic<bool> g_exit_begun{false};      // the drain before the libraries' destructors began
std::atomic<bool> g_closing_at_exit{false};  // the close after them began

void close_at_last(void*) {
    if (!g_exit_begun.load(std::memory_order_acquire)) g_exiting_thread = pthread_self();
    g_closing_at_exit.store(true, std::memory_order_release);
    g_watching.store(false, std::memory_order_relaxed);
    g_recording = false;
    finish_stream();
}

}  // namespace

ThreadState& thread_state() {
    if (ThreadState* state = t_state) [[likely]] return *state;
    return adopt_thread();
}

void hold_across_fork(std::mutex& m) {
    if (g_fork_mutex_count == kMaxForkMutexes) {
        std::fprintf(stderr, "glcast: more than %d mutexes held across fork\n", kMaxForkMutexes);
        std::abort();  // a build error, found by every test that loads the shim
    }
    g_fork_mutexes[g_fork_mutex_count++] = &m;
}

void watch_for_the_last_thread(bool publishing) {
    g_publishing = publishing;
    g_watching.store(true, std::memory_order_relaxed);
    std::thread(watch_last_thread).detach();
}

bool in_forked_child() { return g_forked_child.load(std::memory_order_relaxed); }

bool records_while_ending() {
    return !g_exit_begun.load(std::memory_order_acquire) || pthread_equal(pthread_self(), g_exiting_thread);
}

void stay_out_of_the_exit() {
    if (!g_closing_at_exit.load(std::memory_order_acquire) || pthread_equal(pthread_self(), g_exiting_thread)) return;
    for (;;) pause();  // until exit_group ends the process with this thread in it
}

void count_call_after_end(uint32_t opcode) {
    if (g_calls_after_end.fetch_add(1, std::memory_order_relaxed) == 0 && shim_config().verbose)
        std::fprintf(stderr, "glcast: %s (pid %d) after %s: passed to the driver, not recorded\n",
                     command_info(opcode)->name, int(getpid()),
                     in_forked_child() ? "fork (the stream is the parent's)" : "the stream ended");
}

// The program's own exit handlers have run (they were registered later), its threads may still
// be drawing, and next the dynamic linker runs every library's destructors, the driver's among
// them: what the stream holds is written now, so that closing it after those destructors takes
// only what they added, not a backlog during which the program's other threads would run into a
// torn-down driver (alone, the process would already have ended).
// From here on only the exiting thread's calls are recorded: what other threads draw while the
// process ends is cut off by its end, alone as under glcast.
void drain_before_the_libraries_end(void*) {
    if (!g_recording || in_forked_child()) return;
    g_exiting_thread = pthread_self();
    g_exit_begun.store(true, std::memory_order_release);
    drain_stream();
}

__attribute__((constructor)) static void shim_init() {
    g_recording = shim_config().has_consumer();
    // Registered before the program's constructors run: after the dynamic linker's own
    // (registered before any constructor), so it runs before every library's destructor.
    if (g_recording) __cxa_atexit(drain_before_the_libraries_end, nullptr, nullptr);
    pthread_once(&g_thread_exit_key_once, make_thread_exit_key);  // before the program makes keys of its own
    pthread_atfork(before_fork, after_fork_in_parent, after_fork_in_child);
}

// Runs when the dynamic linker finalises the shim at exit. Other libraries' destructors may run
// after it and make GL calls (a toolkit's singleton that owns the context), so the stream is
// closed by an exit handler registered now: glibc runs a handler registered while the exit
// handlers run right after the one running (here the dynamic linker's, which runs every
// library's destructors). With no DSO handle, nothing else runs it early.
__attribute__((destructor)) static void shim_fini() {
    if (in_forked_child()) {
        if (shim_config().verbose && g_calls_after_end.load())
            std::fprintf(stderr, "glcast: forked child %d passed %llu GL calls to the driver, unrecorded\n",
                         int(getpid()), (unsigned long long)g_calls_after_end.load());
        return;
    }
    if (__cxa_atexit(close_at_last, nullptr, nullptr) != 0) close_at_last(nullptr);
}

}  // namespace glcast
