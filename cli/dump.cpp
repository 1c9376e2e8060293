// `glcast dump FILE [--frames A:B] [--summary]`: a capture as text, one call per line with its
// arguments and replies, and a summary per frame.
#include <cstdio>
#include <memory>

#include "cli/commands.h"
#include "cli/options.h"
#include "protocol/decoder.h"
#include "protocol/dump.h"

namespace glcast::cli {

namespace {

struct DumpArgs {
    std::string path;
    bool summary = false;
    DumpOptions options;
};

int dump(DumpArgs& a) {
    a.options.calls = !a.summary;
    try {
        CaptureReader reader(open_file_source(a.path));
        dump_capture(reader, a.options, stdout);
    } catch (const DecodeError& e) {
        std::fflush(stdout);
        std::fprintf(stderr, "glcast: %s: %s\n", a.path.c_str(), e.what());
        return 1;
    } catch (const std::exception& e) {
        std::fflush(stdout);
        std::fprintf(stderr, "glcast: %s\n", e.what());
        return 1;
    }
    return 0;
}

}  // namespace

Command add_dump(CLI::App& glcast) {
    auto a = std::make_shared<DumpArgs>();
    CLI::App* app = glcast.add_subcommand("dump", "print a capture: one call per line with arguments and replies");
    app->add_option("FILE", a->path, "the capture file")->required();
    add_frame_range(*app, "--frames", LoneFrame::only_that_frame, a->options.first_frame, a->options.last_frame,
                    "only frames A through B (either may be omitted; N alone: frame N)");
    app->add_flag("--summary", a->summary, "only the summary of each frame (calls, bytes, cache hits)");
    return {app, [a](const std::vector<std::string>&) { return dump(*a); }};
}

}  // namespace glcast::cli
