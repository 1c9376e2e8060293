// Write tracking by page protection (write_tracking.h). The signal handler reads only the fixed
// slot table below; a slot's bitmaps are freed only after its range is cleared and no handler
// is inside it (`users`).
#include "interceptor/write_tracking.h"

#include <dlfcn.h>
#include <errno.h>
#include <signal.h>
#include <sys/mman.h>

#include <algorithm>
#include <atomic>
#include <cstdio>
#include <cstring>
#include <mutex>
#include <sched.h>

#include "common/immortal.h"
#include "interceptor/config.h"
#include "interceptor/dl_hooks.h"

namespace glcast {
namespace {

constexpr int kSlots = 256;
// A fault costs a signal and a system call that splits the kernel's map of the range, and a
// page's re-protection another; comparing a page with its shadow costs a memcmp of 4 KiB. So:
//  - a fault on the page after the last ones opened (a program writing forward, as a ring does)
//    opens twice as many pages as the last time, up to kMaxAhead;
//  - pages opened are left writable after a take and compared again at each take, until a take
//    finds more fresh pages than it can keep: then the older ones are protected again (one
//    mprotect a run), and at a frame's end every one is.
constexpr size_t kMaxAhead = 8;
constexpr int kOpenPages = 8;

struct Slot {
    std::atomic<uintptr_t> lo{0}, hi{0};           // the range; hi == 0: free
    std::atomic<uint64_t>* pages = nullptr;        // one bit per page
    std::atomic<uint64_t>* groups = nullptr;       // one bit per word of `pages`
    size_t page_words = 0, group_words = 0;
    std::atomic<int> users{0};                     // handlers inside this slot now
    std::atomic<bool> written{false};
    std::atomic<size_t> ahead_from{0}, ahead_to{0};  // the pages the last fault opened
    size_t pages_total = 0;
    size_t open[kOpenPages] = {};                    // writable pages, ascending (the taker's alone)
    int open_count = 0;
};

Slot g_slots[kSlots];
std::mutex g_slots_mutex;       // track/untrack; the handler never takes it
// Scratch of take_written_pages (its callers serialize its calls).
Immortal<std::vector<std::pair<size_t, size_t>>> g_fresh, g_older;

using SigactionFn = int (*)(int, const struct sigaction*, struct sigaction*);
using SignalFn = sighandler_t (*)(int, sighandler_t);
SigactionFn real_sigaction() {
    static const auto fn = reinterpret_cast<SigactionFn>(real_dlsym(RTLD_NEXT, "sigaction"));
    return fn;
}

// The program's own SIGSEGV disposition while glcast's handler is installed.
std::atomic<bool> g_installed{false};
std::atomic_flag g_action_lock = ATOMIC_FLAG_INIT;  // a spin lock: sigaction may be called from handlers
struct sigaction g_program_action;
std::atomic<bool> g_handler_lost{false};

struct ActionLock {
    ActionLock() { while (g_action_lock.test_and_set(std::memory_order_acquire)) sched_yield(); }
    ~ActionLock() { g_action_lock.clear(std::memory_order_release); }
};

void say_once(std::atomic<bool>& said, const char* what) {
    if (!said.exchange(true)) std::fprintf(stderr, "glcast: %s\n", what);
}

bool mark_written(uintptr_t address) {
    for (Slot& s : g_slots) {
        if (address < s.lo.load() || address >= s.hi.load()) continue;
        s.users.fetch_add(1);
        const uintptr_t lo = s.lo.load(), hi = s.hi.load();
        const bool ours = address >= lo && address < hi;
        if (ours) {
            const size_t page = (address - lo) / kTrackedPage;
            const size_t from = s.ahead_from.load(), to = s.ahead_to.load();
            const size_t ahead = page > from && page <= to ? std::min((to - from) * 2, kMaxAhead) : 1;
            const size_t end = std::min(page + ahead, s.pages_total);
            for (size_t p = page; p < end; ++p) {
                s.pages[p / 64].fetch_or(uint64_t(1) << (p % 64));
                s.groups[p / 4096].fetch_or(uint64_t(1) << (p / 64 % 64));
            }
            s.ahead_from.store(page);
            s.ahead_to.store(end);
            s.written.store(true);
            mprotect(reinterpret_cast<void*>(lo + page * kTrackedPage), (end - page) * kTrackedPage,
                     PROT_READ | PROT_WRITE);
        }
        s.users.fetch_sub(1);
        if (ours) return true;
    }
    return false;
}

// A fault that is not ours, given to the program's disposition as the kernel would have.
void pass_on(int sig, siginfo_t* info, void* context) {
    struct sigaction act;
    {
        ActionLock lock;
        act = g_program_action;
        if (act.sa_flags & SA_RESETHAND) {
            g_program_action.sa_handler = SIG_DFL;
            g_program_action.sa_flags &= ~SA_SIGINFO;
        }
    }
    const bool with_info = act.sa_flags & SA_SIGINFO;
    if (!with_info && (act.sa_handler == SIG_DFL || act.sa_handler == SIG_IGN)) {
        // A fault ignored would fault again forever; the kernel kills then too.
        struct sigaction dfl;
        std::memset(&dfl, 0, sizeof dfl);
        dfl.sa_handler = SIG_DFL;
        real_sigaction()(sig, &dfl, nullptr);
        if (info->si_code <= 0) raise(sig);  // sent, not a fault: delivered as we return
        return;
    }
    sigset_t saved;
    pthread_sigmask(SIG_BLOCK, &act.sa_mask, &saved);
    if (with_info)
        act.sa_sigaction(sig, info, context);
    else
        act.sa_handler(sig);
    pthread_sigmask(SIG_SETMASK, &saved, nullptr);
}

void on_segv(int sig, siginfo_t* info, void* context) {
    const int saved_errno = errno;
    const bool ours = info && info->si_code == SEGV_ACCERR && mark_written(reinterpret_cast<uintptr_t>(info->si_addr));
    errno = saved_errno;
    if (!ours) pass_on(sig, info, context);
}

bool install_handler() {
    if (g_installed.load()) return true;
    struct sigaction ours;
    std::memset(&ours, 0, sizeof ours);
    ours.sa_sigaction = on_segv;
    ours.sa_flags = SA_SIGINFO | SA_ONSTACK | SA_RESTART;
    sigemptyset(&ours.sa_mask);
    ActionLock lock;
    if (!real_sigaction() || real_sigaction()(SIGSEGV, &ours, &g_program_action) != 0) return false;
    g_installed.store(true);
    return true;
}

std::atomic<bool> g_said_off{false}, g_said_slots{false}, g_said_protect{false}, g_said_handler{false},
    g_said_lost{false};

}  // namespace

int track_writes(uint8_t* begin, size_t bytes) {
    if (!shim_config().map_tracking) {
        say_once(g_said_off, "GLCAST_MAP_TRACKING=0: persistent buffer mappings are compared whole at each draw");
        return -1;
    }
    if (g_handler_lost.load() || bytes == 0) return -1;
    if (!install_handler()) {
        say_once(g_said_handler, "cannot install a SIGSEGV handler: persistent buffer mappings are compared whole "
                                 "at each draw");
        return -1;
    }
    std::lock_guard lock(g_slots_mutex);
    Slot* slot = nullptr;
    for (Slot& s : g_slots)
        if (s.hi.load() == 0 && !s.pages) { slot = &s; break; }
    if (!slot) {
        say_once(g_said_slots, "more than 256 persistent buffer mappings at once: the others are compared whole "
                               "at each draw");
        return -1;
    }
    const size_t pages = bytes / kTrackedPage;
    slot->page_words = (pages + 63) / 64;
    slot->group_words = (slot->page_words + 63) / 64;
    slot->pages = new std::atomic<uint64_t>[slot->page_words]();
    slot->groups = new std::atomic<uint64_t>[slot->group_words]();
    slot->written.store(false);
    slot->pages_total = pages;
    slot->ahead_from.store(0);
    slot->ahead_to.store(0);
    slot->lo.store(reinterpret_cast<uintptr_t>(begin));
    slot->hi.store(reinterpret_cast<uintptr_t>(begin) + bytes);
    if (mprotect(begin, bytes, PROT_READ) != 0) {
        char what[200];
        std::snprintf(what, sizeof what, "cannot write-protect a persistent buffer mapping (%s): such mappings are "
                      "compared whole at each draw", std::strerror(errno));
        say_once(g_said_protect, what);
        slot->hi.store(0);
        slot->lo.store(0);
        delete[] slot->pages;
        delete[] slot->groups;
        slot->pages = slot->groups = nullptr;
        return -1;
    }
    return int(slot - g_slots);
}

void untrack_writes(int index) {
    if (index < 0 || index >= kSlots) return;
    std::lock_guard lock(g_slots_mutex);
    Slot& s = g_slots[index];
    const uintptr_t lo = s.lo.load(), hi = s.hi.load();
    if (!hi) return;
    // Writable first, then cleared: a write in flight faults into a range still there.
    mprotect(reinterpret_cast<void*>(lo), hi - lo, PROT_READ | PROT_WRITE);
    s.hi.store(0);
    s.lo.store(0);
    while (s.users.load()) sched_yield();
    s.written.store(false);
    s.open_count = 0;
    delete[] s.pages;
    delete[] s.groups;
    s.pages = s.groups = nullptr;
}

namespace {

void add_page(std::vector<std::pair<size_t, size_t>>& runs, size_t page) {
    if (!runs.empty() && runs.back().second == page)
        runs.back().second = page + 1;
    else
        runs.push_back({page, page + 1});
}

void protect(const Slot& s, const std::vector<std::pair<size_t, size_t>>& runs) {
    const uintptr_t lo = s.lo.load();
    for (const auto& [first, end] : runs)
        mprotect(reinterpret_cast<void*>(lo + first * kTrackedPage), (end - first) * kTrackedPage, PROT_READ);
}

}  // namespace

void take_written_pages(int index, std::vector<std::pair<size_t, size_t>>& runs, bool close_all) {
    runs.clear();
    if (index < 0 || index >= kSlots) return;
    Slot& s = g_slots[index];
    if (!s.written.load() && (!s.open_count || !close_all)) {  // only the open pages, still writable
        for (int i = 0; i < s.open_count; ++i) add_page(runs, s.open[i]);
        return;
    }
    s.written.store(false);
    std::vector<std::pair<size_t, size_t>>& fresh = *g_fresh;
    fresh.clear();
    for (size_t g = 0; g < s.group_words; ++g) {
        uint64_t group = s.groups[g].exchange(0);
        while (group) {
            const size_t word = g * 64 + size_t(__builtin_ctzll(group));
            group &= group - 1;
            uint64_t bits = s.pages[word].exchange(0);
            while (bits) {
                add_page(fresh, word * 64 + size_t(__builtin_ctzll(bits)));
                bits &= bits - 1;
            }
        }
    }
    // Every page to compare: the open ones and the fresh ones, merged in order.
    size_t fresh_pages = 0;
    for (const auto& [first, end] : fresh) fresh_pages += end - first;
    auto f = fresh.begin();
    size_t next_fresh = f == fresh.end() ? SIZE_MAX : f->first;
    int o = 0;
    while (o < s.open_count || next_fresh != SIZE_MAX) {
        size_t page;
        if (o < s.open_count && s.open[o] <= next_fresh) {
            page = s.open[o++];
        } else {
            page = next_fresh;
            if (++next_fresh == f->second) next_fresh = ++f == fresh.end() ? SIZE_MAX : f->first;
        }
        if (runs.empty() || runs.back().second <= page) add_page(runs, page);
    }
    if (close_all || fresh_pages > size_t(kOpenPages)) {
        protect(s, runs);
        s.open_count = 0;
        return;
    }
    if (size_t(s.open_count) + fresh_pages > size_t(kOpenPages)) {  // the older ones closed, the fresh kept open
        std::vector<std::pair<size_t, size_t>>& older = *g_older;
        older.clear();
        for (int i = 0; i < s.open_count; ++i) add_page(older, s.open[i]);
        protect(s, older);
        s.open_count = 0;
        for (const auto& [first, end] : fresh)
            for (size_t page = first; page < end; ++page) s.open[s.open_count++] = page;
        return;
    }
    s.open_count = 0;
    for (const auto& [first, end] : runs)
        for (size_t page = first; page < end; ++page) s.open[s.open_count++] = page;
}

bool check_handler() {
    if (!g_installed.load() || g_handler_lost.load()) return !g_handler_lost.load();
    struct sigaction now;
    if (real_sigaction()(SIGSEGV, nullptr, &now) != 0 || !(now.sa_flags & SA_SIGINFO) || now.sa_sigaction != on_segv) {
        g_handler_lost.store(true);
        say_once(g_said_lost, "the program replaced glcast's SIGSEGV handler without sigaction or signal: "
                              "persistent buffer mappings are compared whole at each draw from now on");
        return false;
    }
    return true;
}

}  // namespace glcast

using namespace glcast;

// The program's SIGSEGV disposition is kept aside while glcast's handler is installed; every
// other signal, and SIGSEGV before any range is tracked, go straight to libc.
extern "C" __attribute__((visibility("default"))) int sigaction(int sig, const struct sigaction* act,
                                                                struct sigaction* old) {
    if (sig != SIGSEGV || !g_installed.load() || g_handler_lost.load()) {
        const SigactionFn real = real_sigaction();
        if (!real) { errno = ENOSYS; return -1; }
        return real(sig, act, old);
    }
    ActionLock lock;
    if (old) *old = g_program_action;
    if (act) g_program_action = *act;
    return 0;
}

extern "C" __attribute__((visibility("default"))) sighandler_t signal(int sig, sighandler_t handler) {
    if (sig != SIGSEGV || !g_installed.load() || g_handler_lost.load()) {
        static const auto real = reinterpret_cast<SignalFn>(real_dlsym(RTLD_NEXT, "signal"));
        if (!real) { errno = ENOSYS; return SIG_ERR; }
        return real(sig, handler);
    }
    struct sigaction act, old;  // glibc's signal(): BSD semantics
    std::memset(&act, 0, sizeof act);
    act.sa_handler = handler;
    sigemptyset(&act.sa_mask);
    sigaddset(&act.sa_mask, sig);
    act.sa_flags = SA_RESTART;
    if (sigaction(sig, &act, &old) != 0) return SIG_ERR;
    if (!(old.sa_flags & SA_SIGINFO)) return old.sa_handler;
    sighandler_t previous;  // what glibc's signal() returns for an SA_SIGINFO handler: its address
    static_assert(sizeof previous == sizeof old.sa_sigaction);
    std::memcpy(&previous, &old.sa_sigaction, sizeof previous);
    return previous;
}
