// `glcast keeper`: the state server slaves join from (keeper/keeper_service.h, docs/keeper.md).
#include "cli/commands.h"
#include "cli/options.h"
#include "keeper/keeper_service.h"

namespace glcast::cli {

Command add_keeper(CLI::App& glcast) {
    auto o = std::make_shared<keeper::KeeperOptions>();
    struct Security {
        std::string keys;
        bool insecure = false;
    };
    auto security = std::make_shared<Security>();
    CLI::App* app = glcast.add_subcommand("keeper", "keep the live state of a master's stream, for slaves that join late");
    app->footer("Start it while the master's journal still holds the stream's start (GLCAST_JOURNAL_MB);\n"
                "slaves then join at any time with glcast slave --keeper ENDPOINT.");
    app->add_option("--connect", o->connect, "the master's stream (tcp://HOST:PORT, ipc://PATH, epgm://...)")
        ->required()
        ->type_name("ENDPOINT");
    app->add_option("--journal", o->journal, "the master's journal")->required()->type_name("ENDPOINT");
    app->add_option("--bind", o->bind, "where slaves ask for snapshots (tcp://*:PORT, ipc://PATH)")
        ->required()
        ->type_name("ENDPOINT");
    app->add_option("--backend", o->backend, "the keeper's context: egl (headless, the default) or osmesa")
        ->type_name("egl|osmesa");
    add_int(*app, "--wait", o->wait_seconds, 1, 86400, "how long to wait for the master (default 86400)")
        ->type_name("SECONDS");
    app->add_option("--state", o->state_path,
                    "keep its state in FILE every few seconds, and start from it when it is there (a keeper\n"
                    "started again then replays the journal's messages since, not the stream's start)")
        ->type_name("FILE");
    add_int(*app, "--state-every", o->state_every_seconds, 1, 3600, "how often the state is kept (default 10)")
        ->type_name("SECONDS");
    app->add_flag("--verbose", o->verbose, "a line per snapshot served and per state kept");
    add_security_options(*app, security->keys, security->insecure);
    return {app, [o, security](const std::vector<std::string>&) {
                std::string error;
                if (!use_keys(security->keys, security->insecure, "glcast keeper", error)) return 1;
                return keeper::run_keeper(*o);
            }};
}

}  // namespace glcast::cli
