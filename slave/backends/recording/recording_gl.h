// A driver that records instead of drawing: the slave's test seam below any real GL. Every
// gl.xml command has a generated function (glcast_recording_gl.cpp, from
// codegen/templates/recording_gl.cpp.j2) that appends the call, as text and as argument bits,
// to the RecordingGl the backend holds, and answers as a driver with nothing in it would:
// names for the generators, GL_NO_ERROR, a complete framebuffer, zero elsewhere. A test may
// answer a call itself (`answer`), and reads what reached the driver from `calls`.
//
// The RecordingBackend carries it through the ordinary Backend interface, so a Replayer, its
// observers and the injected passes' GL calls run over it unchanged (tests/unit/replay_harness.h).
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "slave/backend.h"

namespace glcast::slave {

struct RecordedCall {
    uint32_t opcode = 0;
    uint32_t context = 0;        // the backend's context current when it was called (0: none)
    std::vector<uint64_t> args;  // bits as a Call holds them: integers, float bits, addresses
    std::string text;            // "glViewport(0, 0, 320, 240)", enums by name
    uint64_t reply = 0;          // the return value's bits

    const char* name() const;
    template <class T>
    T* pointer(size_t i) const { return reinterpret_cast<T*>(uintptr_t(args.at(i))); }
};

class RecordingGl {
public:
    std::vector<RecordedCall> calls;
    // Called after a call is recorded and its default answer set: may change `reply` or fill
    // the call's output pointers (glGetIntegerv's params, ...).
    std::function<void(RecordedCall&)> answer;
    uint32_t current_context = 0;

    // The texts of the calls recorded so far, optionally only those whose name starts with
    // `prefix` ("glViewport", "glDraw").
    std::vector<std::string> texts(const std::string& prefix = "") const;
    void clear() { calls.clear(); }

    // -- used by the generated functions -----------------------------------------------
    static RecordingGl* current();  // the one the newest live RecordingBackend holds
    RecordedCall& begin(uint32_t opcode);
    void finish(RecordedCall& c);
    uint32_t new_names(uint32_t count);  // consecutive names from one counter for every kind

private:
    uint32_t next_name_ = 1;
};

// A Backend whose contexts exist by id only and whose driver is `gl`.
std::unique_ptr<Backend> make_recording_backend(std::shared_ptr<RecordingGl> gl);

// The generated function of `opcode` (a gl.xml command), or nullptr for GLX and EGL commands.
void* recording_gl_function(uint32_t opcode);

}  // namespace glcast::slave
