// The frame's record (frame_record.h).
#include "slave/scene/frame_record.h"

#include <utility>

namespace glcast::slave {

bool FrameRecord::append(const uint8_t* tuple, size_t size, const RecordEntry& entry) {
    if (overflow || bytes.size() + size > kMaxRecordBytes) {
        overflow = true;
        return false;
    }
    bytes.insert(bytes.end(), tuple, tuple + size);
    entries.push_back(entry);
    return true;
}

void FrameRecord::clear() {
    std::vector<uint8_t> kept_bytes = std::move(bytes);
    std::vector<RecordEntry> kept_entries = std::move(entries);
    kept_bytes.clear();
    kept_entries.clear();
    *this = FrameRecord{};
    bytes = std::move(kept_bytes);
    entries = std::move(kept_entries);
}

}  // namespace glcast::slave
