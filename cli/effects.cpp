// `glcast effects`: the injected passes' parameters (name, default, range, meaning) as the
// markdown table of docs/effects.md.
#include <cstdio>

#include "cli/commands.h"
#include "slave/effects/effect_params.h"

namespace glcast::cli {

namespace {

int effects() {
    std::printf("| parameter | default | range | meaning |\n|---|---|---|---|\n");
    for (const auto& p : slave::effects::all_param_specs()) {
        if (p.text) std::printf("| `%s` | (none) | text | %s |\n", p.name.c_str(), p.help.c_str());
        else std::printf("| `%s` | %g | %g .. %g | %s |\n", p.name.c_str(), p.value, p.min, p.max, p.help.c_str());
    }
    return 0;
}

}  // namespace

Command add_effects(CLI::App& glcast) {
    CLI::App* app = glcast.add_subcommand("effects", "the injected passes' parameters as a markdown table");
    app->footer("Set them with --effect-param NAME=VALUE on replay, slave and run (docs/effects.md).");
    return {app, [](const std::vector<std::string>&) { return effects(); }};
}

}  // namespace glcast::cli
