// Contexts, frames and the core's own rules on the recording driver: which context a call runs
// on, what a swap ends, what the observers see, and what is refused before the driver.
#include "tests/unit/replay_harness.h"

#include "glcast_synthetic_encode.h"
#include "keeper/kept_calls.h"
#include "slave/tile_adapter.h"

using namespace glcast;
using testing_support::ReplayHarness;

#define GL(fn, ...) encode_##fn(h.stream.e, h.stream.sz, __VA_ARGS__)
#define GL0(fn) encode_##fn(h.stream.e, h.stream.sz)

TEST(ReplayContexts, EachCallRunsOnTheContextItsTupleNames) {
    ReplayHarness h;
    testing_support::open_window(h.stream, ReplayHarness::handle(2), 0, 320, 200, 2, 8);
    GL(glClearColor, 0.0f, 0.0f, 1.0f, 1.0f);  // context 2's
    h.stream.context(1);                       // the program's other thread
    GL(glClearColor, 1.0f, 0.0f, 0.0f, 1.0f);
    h.replay();
    std::vector<uint32_t> on;
    for (const auto& c : h.gl->calls)
        if (c.opcode == OP_glClearColor) on.push_back(c.context);
    EXPECT_EQ(on, (std::vector<uint32_t>{2, 1}));
}

TEST(ReplayContexts, AContextsWindowHasItsDrawablesSize) {
    ReplayHarness h(320, 200);
    h.replay();
    const slave::SlaveContext& ctx = *h.replayer->contexts().at(1);
    EXPECT_EQ(ctx.width, 320);
    EXPECT_EQ(ctx.height, 200);
    EXPECT_EQ(ctx.master_width, 320);
}

TEST(ReplayContexts, ATilesWindowHasTheTilesSize) {
    ReplayHarness h;
    h.tile(0, 0, 2, 2);
    h.replay();
    const slave::SlaveContext& ctx = *h.replayer->contexts().at(1);
    EXPECT_EQ(ctx.width, 320);
    EXPECT_EQ(ctx.height, 240);
    EXPECT_EQ(ctx.master_width, 640);
}

TEST(ReplayContexts, EverySwapEndsAFrameAndHandsItOn) {
    ReplayHarness h(64, 32);
    for (int i = 0; i < 3; ++i) h.swap();
    std::vector<uint64_t> frames;
    h.replay();
    EXPECT_EQ(h.replayer->stats().frames, 3u);
    EXPECT_EQ(h.replayer->frame(), 3u);
    EXPECT_EQ(h.calls("glReadPixels").size(), 0u);  // nobody asked for the picture
}

TEST(ReplayContexts, TheFramesAskedForAreReadBack) {
    ReplayHarness h(64, 32);
    for (int i = 0; i < 3; ++i) h.swap();
    h.replayer = nullptr;
    std::vector<uint64_t> frames;
    h.options.first_frame = 1;
    // (on_frame is set on the Replayer: replay by hand)
    auto replayer = std::make_unique<slave::Replayer>(slave::make_recording_backend(h.gl), h.options);
    replayer->on_frame = [&frames](uint64_t frame, int w, int, const std::vector<uint8_t>& rgba) {
        frames.push_back(frame);
        EXPECT_EQ(rgba.size(), size_t(w) * 32 * 4);
    };
    const std::vector<uint8_t> file = h.stream.file();
    CaptureReader reader(memory_source(file.data(), file.size()));
    replayer->replay(reader);
    EXPECT_EQ(frames, (std::vector<uint64_t>{1, 2}));
    EXPECT_EQ(h.gl->texts("glReadPixels").size(), 2u);
}

TEST(ReplayContexts, ADestroyedContextIsGoneAndItsCallsRefused) {
    ReplayHarness h;
    testing_support::open_window(h.stream, ReplayHarness::handle(2), 0, 320, 200, 2, 8);
    h.stream.context(0);
    encode_glXDestroyContext(h.stream.e, h.stream.sz, nullptr, ReplayHarness::handle(2));
    h.stream.context(2);
    GL(glClear, GL_COLOR_BUFFER_BIT);
    h.replay();
    EXPECT_EQ(h.replayer->contexts().count(2), 0u);
    EXPECT_EQ(h.replayer->contexts().count(1), 1u);
    EXPECT_TRUE(h.calls("glClear(").empty());
}

TEST(ReplayContexts, AMakeCurrentOfAContextNeverCreatedIsRefused) {
    ReplayHarness h;
    h.stream.context(5);
    encode_glXMakeCurrent(h.stream.e, h.stream.sz, nullptr, 9, ReplayHarness::handle(42), True);
    h.replay();
    EXPECT_EQ(h.replayer->stats().errors, 1u);
    EXPECT_NE(h.log.find("does not exist"), std::string::npos) << h.log;
}

TEST(ReplayContexts, LiveContextsAreBounded) {
    ReplayHarness h;
    h.options.limits.contexts = 2;
    testing_support::open_window(h.stream, ReplayHarness::handle(2), 0, 64, 64, 2, 8);
    testing_support::open_window(h.stream, ReplayHarness::handle(3), 0, 64, 64, 3, 9);
    h.replay();
    EXPECT_EQ(h.replayer->contexts().size(), 2u);
    EXPECT_GE(h.replayer->stats().errors, 1u);
    EXPECT_NE(h.log.find("contexts"), std::string::npos) << h.log;
}

TEST(ReplayCore, ADrawOverAClientArrayNeverSentIsRefusedBeforeTheDriver) {
    ReplayHarness h;
    h.stream.client_array_never_sent();
    GL(glDrawArrays, GL_TRIANGLES, 0, 3);
    h.replay();
    EXPECT_TRUE(h.calls("glDrawArrays").empty());
    EXPECT_GE(h.replayer->stats().errors, 1u);
    EXPECT_NE(h.log.find("never sent"), std::string::npos) << h.log;
}

TEST(ReplayCore, WithVerifyAReplyOnlyQueryIsAskedAndCompared) {
    ReplayHarness h;
    h.options.verify = true;
    GLint viewport[4] = {0, 0, 640, 480};
    GL(glGetIntegerv, GL_VIEWPORT, viewport);
    h.replay();
    EXPECT_EQ(h.calls("glGetIntegerv(GL_VIEWPORT").size(), 1u);
    EXPECT_EQ(h.replayer->stats().verified, 1u);
    // The recording driver writes nothing: the slave's output keeps what the master's reply holds
    // (what a query leaves unwritten is the program's memory), so the answers agree.
    EXPECT_EQ(h.replayer->stats().mismatches, 0u);
}

TEST(ReplayCore, AnUnserializedCallIsCountedAndSaidOnce) {
    ReplayHarness h;
    for (int i = 0; i < 3; ++i)
        h.stream.synthetic(kSynthUnserialized,
                           [](Encoder& e) { encode_synth_unserialized(e, OP_glFeedbackBuffer, "a test's reason"); });
    h.replay();
    EXPECT_EQ(h.replayer->stats().unserialized, 3u);
    size_t said = 0;
    for (size_t at = h.log.find("could not serialize"); at != std::string::npos; at = h.log.find("could not serialize", at + 1))
        said++;
    EXPECT_EQ(said, 1u) << h.log;
}

TEST(ReplayCore, AReplayStopsAfterItsLastFrame) {
    ReplayHarness h;
    h.swap();
    GL(glClear, GL_COLOR_BUFFER_BIT);  // frame 1
    h.swap();
    h.options.last_frame = 0;
    h.replay();
    EXPECT_TRUE(h.calls("glClear(").empty());
    EXPECT_EQ(h.replayer->stats().frames, 1u);
}

namespace {
struct Watching final : slave::ReplayObserver {
    bool wants(uint32_t, const CommandInfo*) const override { return true; }
};
}  // namespace

TEST(ReplayCore, ANinthObserverIsRefusedLoudly) {
    ReplayHarness h;
    h.options.verify = true;  // window system, tile adapter, verifier
    h.replay();
    Watching w[8];
    int added = 0;
    try {
        for (Watching& o : w) h.replayer->watch(&o), added++;
        FAIL() << "a ninth observer was taken";
    } catch (const std::logic_error& e) {
        EXPECT_EQ(added, 5);
        EXPECT_NE(std::string(e.what()).find("at most 8 observers"), std::string::npos) << e.what();
    }
}

TEST(ReplayCore, ARedrawnCallGoesThroughTheObserversThatAdaptRedraws) {
    ReplayHarness h;
    h.tile(1, 0, 2, 2);
    GL(glViewport, 0, 0, 640, 480);
    h.replay();
    // The injected passes' redraw of a recorded call: the tuple decoded again and redispatched.
    ByteVector tuple;
    Encoder e(tuple);
    e.set_context(1);
    encode_glViewport(e, h.stream.sz, 0, 0, 320, 240);
    ByteReader r(tuple.data(), tuple.size(), 0);
    Call c;
    decode_tuple(r, c);
    h.gl->clear();
    h.replayer->redispatch(c);
    EXPECT_EQ(h.calls("glViewport"), std::vector<std::string>{"glViewport(-320, -240, 320, 240)"});
}

TEST(KeptCalls, AListsBodyIsKeptUntilItIsDeleted) {
    ReplayHarness h;
    GL(glGenLists, 1, 10);
    GL(glNewList, 10u, GLenum(GL_COMPILE));
    GL(glClearColor, 1.0f, 1.0f, 0.0f, 1.0f);
    GL0(glEndList);
    h.replayer = std::make_unique<slave::Replayer>(slave::make_recording_backend(h.gl), h.options);
    keeper::KeptCalls kept(*h.replayer);
    h.replayer->watch(&kept);
    std::vector<uint8_t> file = h.stream.file();
    {
        CaptureReader reader(memory_source(file.data(), file.size()));
        h.replayer->replay(reader);
    }
    ASSERT_EQ(kept.contexts().size(), 1u);
    const slave::ShareGroup* group = h.replayer->contexts().at(1)->names.shared.get();
    const keeper::ListBodies* lists = kept.lists(group);
    ASSERT_NE(lists, nullptr);
    ASSERT_EQ(lists->count(10), 1u);
    EXPECT_GT(lists->at(10).size(), 0u);
    const uint64_t held = kept.bytes();
    // The list deleted: its body goes.
    h.stream.payload.clear();
    GL(glDeleteLists, 10u, 1);
    file = h.stream.file();
    CaptureReader reader(memory_source(file.data(), file.size()));
    h.replayer->replay(reader);
    lists = kept.lists(group);
    EXPECT_TRUE(!lists || lists->count(10) == 0);
    EXPECT_LT(kept.bytes(), held);
}

// Each drawable's size is bounded, and so is how many the slave keeps: a stream naming millions
// of distinct drawables (a few bytes each on the wire) grew the slave without limit.
TEST(ReplayContexts, WhatObserversKeepFollowsTheLiveContexts) {
    // A stream that makes and destroys contexts one after another, each drawing once on a tile:
    // the tile adapter's per-context and per-share-group state grew with every context ever made.
    ReplayHarness h;
    h.tile(1, 0, 2, 2);
    for (uint32_t k = 0; k < 200; ++k) {
        const uint32_t id = 10 + k;
        testing_support::open_window(h.stream, ReplayHarness::handle(id), 0, 64, 64, id, 8);
        GL(glViewport, 0, 0, 64, 64);
        GL(glDrawArrays, GL_TRIANGLES, 0, 3);
        h.stream.context(0);
        encode_glXDestroyContext(h.stream.e, h.stream.sz, nullptr, ReplayHarness::handle(id));
    }
    h.replay();
    EXPECT_EQ(h.replayer->contexts().size(), 1u);  // the harness's own window
    EXPECT_LE(h.replayer->tile_adapter().states_kept(), 2u) << "kept " << h.replayer->tile_adapter().states_kept();  // that context's, its share group's
}

TEST(ReplayContexts, TheDrawablesKeptAreBounded) {
    ReplayHarness h;
    h.options.limits.drawables = 64;
    for (uint64_t d = 100; d < 100 + 1000; ++d)
        h.stream.synthetic(kSynthDrawableSize, [d](Encoder& e) {
            e.value<uint64_t>(d);
            e.value<int32_t>(32);
            e.value<int32_t>(32);
        });
    h.swap();  // the window's own drawable (7) is still known: its frame is shown at its size
    h.replay();
    EXPECT_EQ(h.replayer->stats().frames, 1u);
    EXPECT_GT(h.replayer->stats().errors, 900u);  // refused, each said: the bound holds
    EXPECT_NE(h.log.find("limit drawables=64"), std::string::npos) << h.log.substr(0, 400);
    const slave::SlaveContext* ctx = h.replayer->context(1);
    ASSERT_NE(ctx, nullptr);
    EXPECT_EQ(ctx->width, 640);
}
