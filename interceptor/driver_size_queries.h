// SizeQueries answered by the real driver of the host program's current context. The calls
// go to the driver directly (real_proc), never through our entry points, so they are not
// recorded and cannot recurse.
#pragma once

#include "protocol/size_queries.h"

namespace glcast {

class DriverSizeQueries : public SizeQueries {
public:
    int64_t driver_count(uint32_t pname) override;
    int64_t tex_level(uint32_t target, int32_t level, uint32_t pname) override;
    bool client_pointer(const void* pointer) override;
    bool enabled(uint32_t cap) override;
    bool read_buffer(uint32_t target, int64_t offset, int64_t bytes, void* out) override;
};

// The real driver's glGetIntegerv for one value, 0 when there is no such function.
int32_t real_get_integer(uint32_t pname);

}  // namespace glcast
