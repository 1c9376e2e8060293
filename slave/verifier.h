// `glcast replay --verify`: every reply-only call (glGet*, glIs*, glReadPixels, ...) is asked
// of the slave's driver too, and its answer compared with the reply the master's driver gave.
// A difference is reported with frame, call and the first differing byte, and counted.
#pragma once

#include <cstdint>
#include <string>

#include "slave/replay_observer.h"

namespace glcast {
struct Arg;
struct ParamInfo;
}  // namespace glcast

namespace glcast::slave {

class Replayer;

class Verifier : public ReplayObserver {
public:
    explicit Verifier(Replayer& core) : core_(core) {}

    bool wants(uint32_t opcode, const CommandInfo* info) const override;
    bool replace_call(const Call& c) override;

    // Called by the generated verify functions with what the slave's call produced.
    void check_reply(const Call& c, int i, const void* slave_output, int64_t slave_elements);
    void check_return(const Call& c, uint64_t slave_value);
    void check_return_string(const Call& c, const char* slave_value);

private:
    void mismatch(const Call& c, const std::string& what);
    bool same_object(const Call& c, const Arg& a, const ParamInfo& p, const void* slave_output);

    Replayer& core_;
    bool checking_ = false;
};

}  // namespace glcast::slave
