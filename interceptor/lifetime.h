// The shim's life inside the host program. The program decides when threads end, when it forks,
// in what order its exit handlers and its libraries' destructors run, and it may make GL calls
// from any of them: the shim's state must stay valid for every one of those calls, and the stream
// must be closed after the last call it can still record.
//  - Each thread's recording state is freed as the thread exits, after its own thread-local
//    destructors and with the program's pthread key destructors (a call made after that makes
//    a new one); the main thread's is never freed, so exit handlers find it whole.
//  - Process-wide state is Immortal (common/immortal.h): never destroyed.
//  - The stream is closed after every exit handler and library destructor has run (the
//    shim's own destructor registers the close as the last exit handler), so calls made there
//    are recorded; a call after that is passed to the driver and counted.
//  - When the program's exit handlers have run, what the stream holds is written before the
//    libraries' destructors, and from then on only the exiting thread's calls are recorded
//    (others are passed to the driver, as calls the process's end cuts off). While the exiting
//    thread closes the stream after those destructors (the driver's among them), a call of
//    another thread waits there for the process to end, as it would have ended already
//    without glcast: a thread that goes on drawing as another calls exit must not reach a
//    driver torn down for longer than it would alone.
//  - When the program's last thread exits, glcast's own threads do not keep it alive.
//  - A forked child passes every call to the driver and touches nothing of the shim's: the
//    stream is its parent's (a child that execs starts a shim of its own).
#pragma once

#include <atomic>
#include <cstdint>
#include <mutex>

namespace glcast {

// Locks `m` across fork(), so that a child never inherits it held by a thread it does not have.
// For a mutex a forked child may take (one that calls passed to the driver take); a leaf: no other
// lock is taken while it is held. Call at static initialisation.
void hold_across_fork(std::mutex& m);

// Started with the stream: when every thread left is glcast's own (the program's last thread has
// exited), ends the process with exit(0), as glibc would have without them.
void watch_for_the_last_thread(bool publishing);

// True in a child forked from a program whose shim had a consumer.
bool in_forked_child();

// False for a call of a thread other than the exiting one once the process has begun to end.
bool records_while_ending();

// For a call of a thread other than the one closing the stream at exit: returns only when the
// stream is not being closed at exit.
void stay_out_of_the_exit();

// Calls passed to the driver because the stream had ended (or belongs to the parent). Counted by
// CallScope; the first is said on stderr under GLCAST_VERBOSE.
void count_call_after_end(uint32_t opcode);

}  // namespace glcast
