// The shim's per-call machinery, shared by the generated entry points and interceptor/special.
//
// Every entry point has the same shape: resolve the real function, open a
// CallScope (the per-thread recursion guard), call the driver first, then encode request and
// reply. Only outermost calls (depth 0) of a process with a consumer are recorded.
#pragma once

#include <cstdint>
#include <vector>

#include "master/encoder.h"
#include "protocol/size_queries.h"

namespace glcast {

struct DrawRange;

void* real_proc(uint32_t opcode);               // the driver's function, or nullptr
class GlApi;
const GlApi& real_gl();                         // the same, typed (glcast_gl_api.h)
void* real_proc_by_name(const char* name);      // same, for names the registry lacks
extern void* const kEntryPoints[];              // generated: our wrapper per opcode
extern bool g_recording;                        // a consumer is configured and not finished

struct ThreadState;
ThreadState& thread_state();

class CallScope {
public:
    explicit CallScope(uint32_t opcode);
    ~CallScope();
    CallScope(const CallScope&) = delete;
    CallScope& operator=(const CallScope&) = delete;

    bool recording() const { return recording_; }
    uint32_t opcode() const { return opcode_; }

    // Encodes one tuple with `encode(Encoder&, SizeQueries&)` and appends it to the stream,
    // or, when a size was unknown, records the call as unserialized with the reason.
    template <class F>
    void record(F&& encode) {
        Encoder& e = begin_record();
        encode(e, sizes());
        commit_record();
    }
    // Synthetic tuple with a hand-written body (protocol/format.h).
    Encoder& begin_synthetic(uint32_t opcode);
    void commit_synthetic();

    void ship_client_arrays(const DrawRange& range);  // before a draw's tuple
    void unserialized(const char* reason = nullptr);

private:
    Encoder& begin_record();
    void commit_record();
    SizeQueries& sizes();

    uint32_t opcode_;
    bool recording_;
};

// Contexts (special/context.cpp): small ids that tuples carry instead of driver handles.
uint32_t current_context_id();
void set_current_context(uint32_t id);

// Mapped buffers (special/buffer_map.cpp): ships what the program wrote into the current
// context's persistent mappings since the last time. Called after the driver's call and before
// the tuple of every command that may read a buffer's memory (draws, compute, commands with a
// buffer-offset pointer, commands.yaml reads_mapped_memory); at a swap, the frame-end variant
// also notices a lost SIGSEGV handler (interceptor/write_tracking.h).
void ship_mapped_writes(CallScope& scope);
void ship_mapped_writes_at_frame_end(CallScope& scope);
// Before a context is destroyed: its mappings' memory may be freed with it.
void forget_mappings_of_context(uint32_t context);

}  // namespace glcast
