// The sizes a snapshot's encoders ask (`sz.`) answered for the slave that will replay it, not
// for the keeper: the snapshot uploads with alignment 1 and no row length, skip or unpack buffer
// (it sets them so first in each context), and knows which buffer it bound where.
#pragma once

#include <set>

#include "common/gl_headers.h"
#include "protocol/size_queries.h"

namespace glcast::keeper {

class SnapshotSizeQueries : public SizeQueries {
public:
    int64_t driver_count(uint32_t pname) override {
        if (pname == GL_UNPACK_ALIGNMENT || pname == GL_PACK_ALIGNMENT) return 1;
        return bound_.count(pname) ? 1 : 0;
    }
    int64_t tex_level(uint32_t, int32_t, uint32_t) override { return 0; }
    // True: a vertex-array pointer is an offset into the bound GL_ARRAY_BUFFER (the snapshot
    // writes only those; arrays in client memory come with the next draw's client_arrays tuple).
    bool client_pointer(const void*) override { return array_offsets_; }

    void set_bound(uint32_t binding_query, bool bound) {
        if (bound) bound_.insert(binding_query);
        else bound_.erase(binding_query);
    }
    void set_array_offsets(bool offsets) { array_offsets_ = offsets; }

private:
    std::set<uint32_t> bound_;
    bool array_offsets_ = false;
};

}  // namespace glcast::keeper
