// `glcast trim IN --frames A:B -o OUT`: a capture of frames A..B that replays on its own; it
// begins with a snapshot of the live state at frame A (keeper/trim.h, docs/keeper.md).
#include <cinttypes>
#include <cstdio>

#include "cli/commands.h"
#include "cli/options.h"
#include "keeper/trim.h"
#include "protocol/decoder.h"
#include "slave/backend.h"

namespace glcast::cli {

namespace {

struct TrimArgs {
    std::string in, out, backend_kind = "egl";
    uint64_t first = 0, last = UINT64_MAX;
    bool frames_given = false;
};

int trim(const TrimArgs& a) {
    std::string error;
    std::unique_ptr<slave::Backend> backend = slave::make_backend(a.backend_kind, error);
    if (!backend) {
        std::fprintf(stderr, "glcast trim: %s\n", error.c_str());
        return 1;
    }
    keeper::TrimResult r;
    try {
        CaptureReader reader(open_file_source(a.in));
        r = keeper::trim_capture(reader, a.first, a.last, std::move(backend), a.out);
    } catch (const DecodeError& e) {
        std::fprintf(stderr, "glcast trim: %s: %s\n", a.in.c_str(), e.what());
        return 1;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "glcast trim: %s\n", e.what());
        return 1;
    }
    if (r.replayed_frames < a.first) {
        std::fprintf(stderr, "glcast trim: %s has %" PRIu64 " frames, fewer than the first one asked for (%" PRIu64 ")\n",
                     a.in.c_str(), r.replayed_frames, a.first);
        return 1;
    }
    std::printf("%s: snapshot of frame %" PRIu64 " (%" PRIu64 " contexts, %" PRIu64 " objects, %" PRIu64
                " display lists: %" PRIu64 " tuples, %" PRIu64 " bytes, %.1f ms), then %" PRIu64 " frames\n",
                a.out.c_str(), a.first, r.snapshot.contexts, r.snapshot.objects, r.snapshot.lists, r.snapshot.tuples,
                r.snapshot.bytes, r.snapshot_seconds * 1e3, r.frames);
    for (const std::string& m : r.snapshot.missing) std::printf("not in the snapshot: %s\n", m.c_str());
    if (r.keeper_errors)
        std::printf("the keeper refused %" PRIu64 " calls before frame %" PRIu64 " (see above)\n", r.keeper_errors, a.first);
    return 0;
}

}  // namespace

Command add_trim(CLI::App& glcast) {
    auto a = std::make_shared<TrimArgs>();
    CLI::App* app = glcast.add_subcommand("trim", "cut frames A..B out of a capture; the cut replays on its own");
    app->add_option("IN", a->in, "the capture file")->required();
    add_frame_range(*app, "--frames", LoneFrame::only_that_frame, a->first, a->last,
                    "frames A through B (either may be omitted; N alone: frame N)")
        ->required();
    app->add_option("-o,--output", a->out, "the capture to write")->required()->type_name("FILE");
    app->add_option("--backend", a->backend_kind, "the keeper's context: egl (headless, the default) or osmesa")
        ->type_name("egl|osmesa");
    return {app, [a](const std::vector<std::string>&) { return trim(*a); }};
}

}  // namespace glcast::cli
