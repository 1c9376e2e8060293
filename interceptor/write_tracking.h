// Page-granular write tracking of memory the program writes outside any GL call (persistent buffer
// mappings): the pages are write-protected, and the first write to each faults into glcast's
// SIGSEGV handler, which marks the page written and lets the write through. Finding what changed
// then costs the pages written, not the size of the memory.
//  - The handler is installed with the first tracked range and coexists with the program's own:
//    a fault outside every tracked range goes to the program's disposition, whether the program
//    set it before glcast's handler or after (the shim interposes sigaction and signal for SIGSEGV
//    and keeps the program's disposition aside). A program that replaces the handler some other
//    way (a raw system call) is noticed at the next check_handler(): every range is released and
//    the caller compares instead, which is said once on stderr.
//  - Faults may come from any thread, the driver's included; the handler is async-signal-safe
//    (fixed slots, atomics, mprotect).
//  - The kernel does not fault into handlers: a system call that writes into a protected page
//    (read(2) into a mapping) fails with EFAULT. GLCAST_MAP_TRACKING=0 turns tracking off.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace glcast {

constexpr size_t kTrackedPage = 4096;

// Starts tracking writes to [begin, begin + bytes), both page-aligned: the pages become read-only.
// Returns a slot, or -1 when it cannot (tracking off, no free slot, mprotect refused); the first
// refusal of each kind is said on stderr.
int track_writes(uint8_t* begin, size_t bytes);

// Makes the range writable again and frees its slot. After it returns no handler refers to it.
void untrack_writes(int slot);

// The runs of pages of `slot` the caller must compare, as [first, end) page indices: those written
// since the last call and those still writable since an earlier one (a few are left writable, so
// that a page written at each draw costs no system call at each draw). Pages re-protected are
// protected before they are returned (so a write that lands after the protection faults again,
// and one that lands before is in the memory the caller reads next). `close_all` (at a frame's
// end) re-protects every page returned, so that an idle mapping costs nothing.
// Calls are serialized by the caller (one lock over every tracked range's takes).
void take_written_pages(int slot, std::vector<std::pair<size_t, size_t>>& runs, bool close_all);

// False once the program has replaced glcast's SIGSEGV handler without sigaction or signal;
// the caller then releases its ranges and compares. Costs one system call.
bool check_handler();

}  // namespace glcast
