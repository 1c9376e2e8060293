// The journal channel: a ROUTER socket, served from a thread of its own, that answers slaves
// that join late or lost messages (the zguide's Clone pattern: a slave subscribes first, asks
// for the snapshot, then drops live messages it already has), and takes lockstep's "DONE n".
//
// A request is one part "SNAPSHOT"; the answer is every message from the first, one part each,
// then "END". "SINCE n": the messages from sequence n on, then "END". A journal that no longer
// holds the first message asked for answers "GONE". Anything else is dropped and counted
// (master/journal_requests.h). It never waits on a peer: a peer that takes nothing for
// kStallSeconds is no longer served.
#pragma once

#include <atomic>
#include <cstdint>
#include <deque>
#include <string>
#include <string_view>
#include <thread>

#include "master/journal.h"
#include "master/journal_requests.h"
#include "master/lockstep_barrier.h"

namespace zmq {
class context_t;
class socket_t;
}  // namespace zmq

namespace glcast {

class JournalServer {
public:
    // Starts serving `journal` on `endpoint` (a bind failure is said on stderr, and nothing is
    // served); `lockstep` takes the DONE requests when it is enabled.
    JournalServer(zmq::context_t& context, std::string endpoint, const Journal& journal, LockstepBarrier& lockstep,
                  bool verbose);
    ~JournalServer();  // stops the thread; with verbose, prints what was served and dropped

private:
    struct Session {
        std::string identity;
        bool whole = true;           // SNAPSHOT: from message 0; else SINCE `next`
        uint64_t next = 0, end = 0;  // sequence numbers still to send
        double last_progress = 0;
        bool started = false;
    };
    void run();
    bool read_requests(zmq::socket_t& router);  // true: something was read
    void handle_request(const std::string_view* parts, size_t count, double now);
    bool serve(zmq::socket_t& router, Session& s, double now);  // true: finished or given up
    bool stalled(const Session& s, double now);
    void say_counts() const;

    zmq::context_t& context_;
    const std::string endpoint_;
    const Journal& journal_;
    LockstepBarrier& lockstep_;
    const bool verbose_;
    std::atomic<bool> stopping_{false};
    // The serving thread's own.
    JournalAdmission admission_;
    std::deque<Session> active_, pending_;
    uint64_t drops_[size_t(JournalDrop::count_)] = {};
    uint64_t served_ = 0, stalled_ = 0;
    std::thread thread_;
};

}  // namespace glcast
