// The glcast command: one binary with subcommands, like git and apitrace. Each
// subcommand is a file of cli/ that declares its options on CLI11; this file dispatches, prints
// help (exit 0), and turns every command-line error into one line on stderr and exit 2.
#include <CLI/CLI.hpp>

#include <algorithm>
#include <cstdio>
#include <set>
#include <string>
#include <vector>

#include "cli/commands.h"
#include "protocol/format.h"
#include "common/environment.h"

using namespace glcast::cli;

namespace {

// CLI11's help, with "-- PROGRAM [ARGS...]" on the usage line of the commands that run one.
class Formatter : public CLI::Formatter {
public:
    std::set<const CLI::App*> runs_program;

    std::string make_usage(const CLI::App* app, std::string name) const override {
        std::string usage = CLI::Formatter::make_usage(app, name);
        if (runs_program.count(app) && !usage.empty() && usage.back() == '\n')
            usage.insert(usage.size() - 1, " -- PROGRAM [ARGS...]");
        return usage;
    }
};

// "Commands" rather than CLI11's "Subcommands", and positionals without CLI11's type "TEXT":
// their names (FILE, OUT, ...) say what they are.
void tidy_help(CLI::App& app) {
    for (CLI::App* sub : app.get_subcommands([](CLI::App*) { return true; })) {
        sub->group("Commands");
        tidy_help(*sub);
    }
    for (CLI::Option* o : app.get_options([](const CLI::Option* o) { return o->get_positional(); }))
        if (o->get_type_name() == "TEXT") o->type_name("");
}

int usage_failure(const std::string& who, const std::string& message) {
    std::fprintf(stderr, "%s: %s\n", who.c_str(), message.c_str());
    return 2;
}

// The subcommand that was being parsed: the one whose leftover arguments are unknown to it.
const CLI::App* innermost(const CLI::App& app) {
    const CLI::App* a = &app;
    while (!a->get_subcommands().empty()) a = a->get_subcommands().front();
    return a;
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"glcast puts unmodified OpenGL programs on display walls: a preloaded shim publishes\n"
                 "every GL call with its reply, and slaves replay them per tile.",
                 "glcast"};
    auto formatter = std::make_shared<Formatter>();
    formatter->column_width(32);
    formatter->label("SUBCOMMAND", "COMMAND");
    app.formatter(formatter);  // before the subcommands: they share it
    app.option_defaults()->multi_option_policy(CLI::MultiOptionPolicy::TakeLast);  // the last one wins
    app.set_help_flag("-h,--help", "print this help and exit");
    app.add_flag("--version", "print glcast's version and the stream format's, and exit");  // answered before parsing, below
    app.require_subcommand(1);  // exactly one: no later argument is taken for another command

    const std::vector<Command> commands = {add_capture(app), add_dump(app),  add_replay(app), add_run(app),
                                           add_slave(app),   add_image(app), add_effects(app), add_trim(app), add_keeper(app), add_record(app),
                                           add_keygen(app), add_doctor(app), add_config(app), add_ctl(app), add_calibrate(app)};
    CLI::App* help = app.add_subcommand("help", "this text, or a command's options");
    std::string topic;
    help->add_option("COMMAND", topic, "the command");
    for (const Command& c : commands)
        if (c.runs_program) formatter->runs_program.insert(c.app);
    tidy_help(app);
    app.footer("glcast COMMAND --help (or glcast help COMMAND) lists a command's options.\n"
               "The shim reads GLCAST_* variables; see docs/environment.md.");  // after the subcommands: not theirs

    std::vector<std::string> args(argv + 1, argv + argc);
    if (args.empty()) return usage_failure("glcast", "which command? (glcast --help lists them)");
    const auto named = [&](const std::string& name) -> const Command* {
        for (const Command& c : commands)
            if (c.app->get_name() == name) return &c;
        return nullptr;
    };
    const Command* command = named(args[0]);
    if (args[0] == "--version") {
        // (the stream format it writes, and the oldest it reads: what decides whether a capture
        // or a wall's machines go together, docs/stream-format.md)
        std::printf("glcast %s\nstream format %u (reads %u to %u)\n", GLCAST_VERSION, glcast::kFormatVersion,
                    glcast::kOldestReadableFormatVersion, glcast::kFormatVersion);
        return 0;
    }
    if (!command && args[0] != "help" && args[0] != "-h" && args[0] != "--help")
        return usage_failure("glcast", std::string(args[0][0] == '-' ? "unknown option '" : "unknown command '") +
                                           args[0] + "' (glcast --help lists the commands)");
    const std::string who = command || args[0] == "help" ? "glcast " + args[0] : "glcast";

    // A program's command line is split off at the first "--" and never reaches CLI11.
    std::vector<std::string> program;
    bool has_program = false;
    if (command && command->runs_program) {
        const auto dashes = std::find(args.begin() + 1, args.end(), "--");
        has_program = dashes != args.end();
        if (has_program) {
            program.assign(dashes + 1, args.end());
            args.erase(dashes, args.end());
        }
    }
    try {
        std::vector<const char*> cli_argv{argv[0]};
        for (const std::string& a : args) cli_argv.push_back(a.c_str());
        app.parse(int(cli_argv.size()), cli_argv.data());
        if (help->parsed()) {
            if (topic.empty() || topic == "help") {
                std::fputs(formatter->make_help(&app, "glcast", CLI::AppFormatMode::Normal).c_str(), stdout);
                return 0;
            }
            const Command* about = named(topic);
            if (!about) return usage_failure(who, "unknown command '" + topic + "'");
            std::fputs(formatter->make_help(about->app, "glcast " + topic, CLI::AppFormatMode::Normal).c_str(), stdout);
            return 0;
        }
        if (command->runs_program && program.empty())
            throw CLI::ValidationError(std::string(has_program ? "which program? (after '--')"
                                                               : "the program to run follows '--'"));
        (void)glcast::environment();  // every GLCAST_* variable checked before the command does anything
        return command->run(program);
    } catch (const glcast::EnvironmentError& e) {
        std::fprintf(stderr, "%s: %s (docs/environment.md)\n", who.c_str(), e.what());
        return 2;
    } catch (const CLI::CallForHelp&) {
        std::fputs(app.help().c_str(), stdout);  // the help of the command that asked for it
        return 0;
    } catch (const CLI::ParseError& e) {
        // An unknown option or a stray argument is what went wrong first, whatever else CLI11 found.
        const std::vector<std::string> extra = innermost(app)->remaining();
        if (!extra.empty())
            return usage_failure(who, std::string(extra[0][0] == '-' ? "unknown option '" : "unexpected argument '") +
                                          extra[0] + "'");
        return usage_failure(who, e.what());
    }
}
