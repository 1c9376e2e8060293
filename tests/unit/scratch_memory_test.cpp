// The per-call scratch memory of the replay (slave/scratch_memory.h), without a driver.
#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>

#include "slave/scratch_memory.h"

namespace glcast::slave {
namespace {

TEST(ScratchMemory, BlocksAreAlignedZeroedAndDistinctWithinACall) {
    ScratchMemory scratch(1 << 20);
    auto* a = static_cast<uint8_t*>(scratch.take(13));
    auto* b = static_cast<uint8_t*>(scratch.take(100));
    EXPECT_EQ(reinterpret_cast<uintptr_t>(a) % 8, 0u);
    EXPECT_EQ(reinterpret_cast<uintptr_t>(b) % 8, 0u);
    EXPECT_NE(a, b);
    for (int i = 0; i < 100; ++i) EXPECT_EQ(b[i], 0) << i;
    std::memset(a, 0xff, 13);
    EXPECT_EQ(b[0], 0);  // writing one block leaves the other alone
    scratch.end_call();
    auto* again = static_cast<uint8_t*>(scratch.take(13));
    for (int i = 0; i < 13; ++i) EXPECT_EQ(again[i], 0) << "a block taken again is zeroed: byte " << i;
    EXPECT_EQ(scratch.blocks(), 2u);  // kept from call to call
}

TEST(ScratchMemory, ALargeBlockIsGivenBackAfterItsCall) {
    ScratchMemory scratch(64 << 10);
    scratch.take(1000);
    scratch.take(8 << 20);  // one large upload
    EXPECT_GE(scratch.retained_bytes(), size_t(8) << 20);
    scratch.end_call();
    EXPECT_LT(scratch.retained_bytes(), size_t(64) << 10) << "the large block outlived its call";
    scratch.take(1000);
    scratch.end_call();
    EXPECT_GE(scratch.retained_bytes(), 1000u) << "small blocks are kept";
}

}  // namespace
}  // namespace glcast::slave
