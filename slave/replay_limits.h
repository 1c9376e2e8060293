// The limits of one stream on a slave, and --limit's parser.
#pragma once

#include <cstdint>
#include <string>

namespace glcast::slave {

// What one stream may make the slave allocate or loop over (docs/slave.md "Limits of a
// stream", docs/security.md). A call over a limit is refused like any bad call: reported,
// counted, skipped. The defaults are far above what the committed captures and the test
// programs use, and far below what exhausts a slave.
struct ReplayLimits {
    uint64_t list_range = 1u << 20;          // glGenLists / glDeleteLists range
    uint64_t texture_dimension = 16384;      // width, height, depth of one texture image
    uint64_t buffer_bytes = 1ull << 30;      // size of one buffer's data store
    uint64_t client_array_bytes = 256u << 20;  // client-array copies kept per context
    uint64_t arena_retain_bytes = 16u << 20; // scratch blocks above this are freed after their call
    uint64_t drawable_dimension = 16384;     // width, height of a window framebuffer
    uint64_t contexts = 256;                 // contexts alive at once
    uint64_t list_entries = 1u << 20;        // pointer records of one string or index-array list
    uint64_t object_bytes = 4ull << 30;      // data stores of all live textures, buffers, renderbuffers
    uint64_t names = 1u << 22;               // live names of one kind in one share group (or context)
    uint64_t drawables = 4096;               // drawables whose size the slave keeps
};

// The image of a texture a call replaces (commands.yaml slave.stores `image`), or its whole store.
constexpr uint64_t kWholeStore = ~0ull;
inline uint64_t store_key(uint32_t target, int32_t level) { return uint64_t(target) << 32 | uint32_t(level); }

// Sets one limit from "NAME=VALUE" (--limit); false with a message naming the limits, or the
// closest name, on an unknown NAME or a bad VALUE.
bool set_replay_limit(ReplayLimits& limits, const std::string& spec, std::string& error);
std::string replay_limit_names();  // "list_range=1048576, ..." with the current values' defaults

}  // namespace glcast::slave
