// Running recorded calls again: one entry of a frame's record through the replay core, and the
// scope that puts a context's pending client-array ranges back when a redraw ends.
#pragma once

#include <cstdint>
#include <vector>

#include "slave/replayer.h"
#include "slave/scene/frame_record.h"

namespace glcast::slave {

// Runs one recorded call again (a redraw): a call the stream got wrong was reported when the
// frame was replayed, and is skipped here.
void redispatch_entry(Replayer& core, const FrameRecord& rec, const RecordEntry& e, Call& c);

// The pending client-array ranges of a context (slave/replayer.h), put back when a redraw ends:
// a glcast.client_arrays tuple whose draw the redraw leaves out would otherwise stay pending and
// be checked against the program's next draw.
class PendingClientArrays {
public:
    explicit PendingClientArrays(SlaveContext& ctx)
        : ctx_(ctx), pending_(ctx.client_range_pending), refused_(ctx.client_arrays_refused), first_(ctx.client_first),
          end_(ctx.client_end), instances_(ctx.client_instances) {}
    ~PendingClientArrays() {
        ctx_.client_range_pending = pending_, ctx_.client_arrays_refused = refused_;
        ctx_.client_first = first_, ctx_.client_end = end_;
        ctx_.client_instances = std::move(instances_);
    }
    PendingClientArrays(const PendingClientArrays&) = delete;
    PendingClientArrays& operator=(const PendingClientArrays&) = delete;

private:
    SlaveContext& ctx_;
    bool pending_, refused_;
    int64_t first_, end_;
    std::vector<ClientInstanceRange> instances_;
};

}  // namespace glcast::slave
