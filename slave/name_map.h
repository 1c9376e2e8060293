// The master's object names -> the slave's (docs/slave.md). Shareable objects live in a map per
// share group; container objects (framebuffers, vertex arrays, queries, transform feedbacks,
// program pipelines) in a map per context, as GL itself scopes them.
#pragma once

#include <algorithm>
#include <cstdint>
#include <vector>
#include <memory>
#include <map>
#include <unordered_map>

#include "glcast_slave_dispatch.h"

namespace glcast::slave {

class NameMap {
public:
    bool find(uint64_t master, uint64_t& slave) const {
        auto it = map_.find(master);
        if (it == map_.end()) return false;
        slave = it->second;
        return true;
    }
    void set(uint64_t master, uint64_t slave) { map_[master] = slave; }
    void erase(uint64_t master) { map_.erase(master); }
    size_t size() const { return map_.size(); }
    template <class F>
    void each(F&& f) const {  // f(master, slave), by master name (a snapshot is the same every time)
        std::vector<std::pair<uint64_t, uint64_t>> sorted(map_.begin(), map_.end());
        std::sort(sorted.begin(), sorted.end());
        for (const auto& [master, slave] : sorted) f(master, slave);
    }

private:
    std::unordered_map<uint64_t, uint64_t> map_;
};

struct ShareGroup {
    NameMap maps[kNamespaceCount];
    // uniform locations: master program -> (master location -> slave location)
    std::unordered_map<uint64_t, std::unordered_map<int32_t, int32_t>> uniform_locations;
    // The data stores of its textures, buffers and renderbuffers, for the limit object_bytes
    // (Replayer::store): (namespace, slave name) -> (image key -> bytes), and their sum.
    std::map<std::pair<int, uint64_t>, std::unordered_map<uint64_t, uint64_t>> stores;
    uint64_t store_bytes = 0;
};

struct ContextNames {
    std::shared_ptr<ShareGroup> shared;
    NameMap own[kNamespaceCount];

    NameMap& map(Ns ns) {
        return kNamespaces[int(ns)].per_context ? own[int(ns)] : shared->maps[int(ns)];
    }
};

}  // namespace glcast::slave
