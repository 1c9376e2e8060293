// The journal channel's request forms and admission (master/journal_requests.h): what a network peer
// may ask of the shim, and how often.
#include <gtest/gtest.h>

#include <string>
#include <string_view>
#include <vector>

#include "master/journal_requests.h"
#include "slave/network_source.h"

using namespace glcast;

namespace {

JournalRequest classify(std::vector<std::string_view> parts) { return classify_journal_request(parts.data(), parts.size()); }

}  // namespace

TEST(JournalRequest, TheDocumentedForms) {
    EXPECT_EQ(classify({"id", "SNAPSHOT"}).kind, JournalRequestKind::snapshot);
    const JournalRequest d = classify({"id", "DONE 42"});
    EXPECT_EQ(d.kind, JournalRequestKind::done);
    EXPECT_EQ(d.frame, 42u);
    EXPECT_EQ(classify({"id", "DONE 0"}).frame, 0u);
    EXPECT_EQ(classify({"id", "DONE 4294967295"}).frame, 4294967295u);
    const JournalRequest since = classify({"id", "SINCE 7"});
    EXPECT_EQ(since.kind, JournalRequestKind::since);
    EXPECT_EQ(since.sequence, 7u);
    EXPECT_EQ(classify({"id", "SINCE 0"}).sequence, 0u);
    EXPECT_EQ(classify({"id", "SINCE 18446744073709551615"}).sequence, UINT64_MAX);
}

TEST(JournalRequest, EverythingElseIsDroppedWithItsReason) {
    EXPECT_EQ(classify({"id"}).drop, JournalDrop::parts);
    EXPECT_EQ(classify({"id", "SNAPSHOT", "SNAPSHOT"}).drop, JournalDrop::parts);
    EXPECT_EQ(classify({}).drop, JournalDrop::parts);
    EXPECT_EQ(classify({"", "SNAPSHOT"}).drop, JournalDrop::identity);
    EXPECT_EQ(classify({std::string(256, 'i'), "SNAPSHOT"}).drop, JournalDrop::identity);
    const std::string big = "SNAPSHOT" + std::string(100, ' ');
    EXPECT_EQ(classify({"id", big}).drop, JournalDrop::size);
    for (const char* bad : {"snapshot", "SNAPSHOT ", "SNAPSHO", "", "DONE", "DONE ", "DONE -1", "DONE +1", "DONE 01",
                            "DONE 1 ", "DONE  1", "DONE 4294967296", "DONE 99999999999", "DONE 1x", "END", "SINCE",
                            "SINCE ", "SINCE 01", "SINCE -1", "SINCE 18446744073709551616", "SINCE 99999999999999999999",
                            "SINCE 1 ", "since 1"})
        EXPECT_EQ(classify({"id", bad}).kind, JournalRequestKind::invalid) << bad;
    const std::string nul("SNAPSHOT\0", 9);
    EXPECT_EQ(classify({"id", nul}).kind, JournalRequestKind::invalid);
}

TEST(JournalAdmission, PerPeerAndTotalBuckets) {
    using namespace journal_limits;
    JournalAdmission a;
    int admitted = 0;
    for (int i = 0; i < 100; i++) admitted += a.admit("flood", JournalRequestKind::snapshot, 0.0);
    EXPECT_EQ(admitted, int(kSnapshotBurstPerPeer));
    EXPECT_TRUE(a.admit("flood", JournalRequestKind::snapshot, 1.0 / kSnapshotRatePerPeer));  // refilled one
    // Many identities: the total bucket holds.
    admitted = 0;
    for (int i = 0; i < 200; i++) admitted += a.admit("peer" + std::to_string(i), JournalRequestKind::snapshot, 1.0);
    EXPECT_LE(admitted, int(kSnapshotBurstTotal));
    EXPECT_LE(a.peers(), kMaxPeers);
}

TEST(JournalAdmission, PeerTableStaysBounded) {
    using namespace journal_limits;
    JournalAdmission a;
    for (int i = 0; i < 10000; i++) a.admit("peer" + std::to_string(i), JournalRequestKind::done, i * 1e-4);
    EXPECT_LE(a.peers(), kMaxPeers);
    // Later, idle peers are forgotten and new ones are admitted again.
    EXPECT_TRUE(a.admit("newcomer", JournalRequestKind::done, 100.0));
}

// A keeper's STATE line: a peer's huge, negative or malformed counts are refused, not wrapped.
TEST(KeeperState, OnlyDecimalCountsWithinTheBoundAreTaken) {
    uint64_t sequence = 0, frame = 0;
    EXPECT_TRUE(glcast::slave::parse_keeper_state("STATE 120 37", sequence, frame));
    EXPECT_EQ(sequence, 120u);
    EXPECT_EQ(frame, 37u);
    EXPECT_TRUE(glcast::slave::parse_keeper_state("STATE 0 0", sequence, frame));
    for (const char* bad : {"STATE 1 18446744073709551615", "STATE 1 -1", "STATE -1 1", "STATE 1", "STATE 1 2 3",
                            "STATE 1  2", "STATE 1 2x", "STATE  1 2", "STATE 0x10 1", "STATE 1 281474976710657",
                            "STATE 99999999999999999999 1", "NONE", "", "STATE"})
        EXPECT_FALSE(glcast::slave::parse_keeper_state(bad, sequence, frame)) << bad;
    EXPECT_TRUE(glcast::slave::parse_keeper_state("STATE 1 281474976710656", sequence, frame));  // 2^48
}
