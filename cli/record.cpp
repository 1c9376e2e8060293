// `glcast record`: a capture of a program that is already publishing (to a wall, or to nothing),
// from a frame on. It joins like a slave, from a keeper's snapshot (docs/keeper.md), and writes
// the snapshot and the messages after it to a capture file, which then replays on its own.
#include <cinttypes>
#include <cstdio>
#include <cstring>

#include "cli/commands.h"
#include "cli/options.h"
#include "keeper/trim.h"
#include "master/stream.h"
#include "protocol/decoder.h"
#include "protocol/format.h"
#include "slave/network_source.h"

namespace glcast::cli {

namespace {

struct RecordArgs {
    std::string endpoint, journal, keeper, output, keys;
    bool insecure = false;
    uint64_t start_frame = 0, frames = 0;
    int wait_seconds = 3600;
};

int record(const RecordArgs& a) {
    std::string error;
    if (!use_keys(a.keys, a.insecure, "glcast record", error)) return 1;
    try {
        slave::NetworkSource source(a.endpoint, a.journal, a.wait_seconds, a.keeper, a.start_frame);
        auto file = std::make_unique<CaptureFileSink>(a.output);
        const CaptureFileSink& written = *file;
        std::vector<std::unique_ptr<MessageSink>> sinks;
        sinks.push_back(std::move(file));
        Stream out(std::move(sinks), 1, 4);
        uint64_t frames = 0;
        Message m;
        // A write that fails (a full disk) stops the capture; the recording stops with it.
        while ((!a.frames || frames < a.frames) && !written.failed() && source.next(m)) {
            if (keeper::append_message(out, m)) frames++;
        }
        out.close();
        // Said as a capture's readers say it, and not a success: what the file holds replays to
        // its last whole message.
        if (const CaptureEnd end = capture_end(a.output); !end.complete) {
            std::fprintf(stderr, "glcast record: %s was %s\n", a.output.c_str(), end.why.c_str());
            return 1;
        }
        std::printf("%s: %" PRIu64 " frames from frame %" PRIu64 " of the program\n", a.output.c_str(), frames,
                    source.joined_frame());
        return 0;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "glcast record: %s\n", e.what());
        return 1;
    }
}

}  // namespace

Command add_record(CLI::App& glcast) {
    auto a = std::make_shared<RecordArgs>();
    CLI::App* app = glcast.add_subcommand("record", "capture a program that is already publishing, from a frame on");
    app->add_option("--connect", a->endpoint, "the master's stream")->required()->type_name("ENDPOINT");
    app->add_option("--journal", a->journal, "the master's journal")->required()->type_name("ENDPOINT");
    app->add_option("--keeper", a->keeper, "a keeper of the stream (glcast keeper)")->required()->type_name("ENDPOINT");
    app->add_option("-o,--output", a->output, "the capture file to write")->required()->type_name("FILE");
    add_u64(*app, "--start-frame", a->start_frame, 0, UINT32_MAX,
            "begin at this frame of the program (0: wherever the keeper is now); waits until then");
    add_u64(*app, "--frames", a->frames, 0, UINT32_MAX, "stop after N frames (0: when the program ends)");
    add_int(*app, "--wait", a->wait_seconds, 1, 86400, "how long to wait for the master and the keeper (default 3600)")
        ->type_name("SECONDS");
    add_security_options(*app, a->keys, a->insecure);
    return {app, [a](const std::vector<std::string>&) { return record(*a); }};
}

}  // namespace glcast::cli
