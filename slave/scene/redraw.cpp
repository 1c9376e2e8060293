// Running recorded calls again (redraw.h).
#include "slave/scene/redraw.h"

#include "protocol/decoder.h"

namespace glcast::slave {

void redispatch_entry(Replayer& core, const FrameRecord& rec, const RecordEntry& e, Call& c) {
    ByteReader r(rec.bytes.data() + e.begin, e.size, 0);
    decode_tuple(r, c);
    try {
        core.redispatch(c);
    } catch (const ReplayError&) {
    } catch (const GlMissing&) {
    }
}

}  // namespace glcast::slave
