// `--limit NAME=VALUE`: the ReplayLimits of slave/replayer.h by name.
#include <cstdlib>
#include <string>

#include "common/edit_distance.h"
#include "slave/replay_limits.h"

namespace glcast::slave {

namespace {

struct LimitSpec {
    const char* name;
    uint64_t ReplayLimits::*field;
};

constexpr LimitSpec kLimits[] = {
    {"list_range", &ReplayLimits::list_range},
    {"texture_dimension", &ReplayLimits::texture_dimension},
    {"buffer_bytes", &ReplayLimits::buffer_bytes},
    {"client_array_bytes", &ReplayLimits::client_array_bytes},
    {"arena_retain_bytes", &ReplayLimits::arena_retain_bytes},
    {"drawable_dimension", &ReplayLimits::drawable_dimension},
    {"contexts", &ReplayLimits::contexts},
    {"list_entries", &ReplayLimits::list_entries},
    {"object_bytes", &ReplayLimits::object_bytes},
    {"names", &ReplayLimits::names},
    {"drawables", &ReplayLimits::drawables},
};

}  // namespace

std::string replay_limit_names() {
    const ReplayLimits defaults;
    std::string out;
    for (const LimitSpec& l : kLimits)
        out += (out.empty() ? "" : ", ") + std::string(l.name) + "=" + std::to_string(defaults.*l.field);
    return out;
}

bool set_replay_limit(ReplayLimits& limits, const std::string& spec, std::string& error) {
    const auto eq = spec.find('=');
    const std::string name = spec.substr(0, eq);
    const LimitSpec* found = nullptr;
    std::string suggestion;
    size_t best = 4;
    for (const LimitSpec& l : kLimits) {
        if (name == l.name) found = &l;
        if (size_t d = edit_distance(name, l.name); d < best) best = d, suggestion = l.name;
    }
    if (!found) {
        error = "unknown limit \"" + name + "\" (" + (suggestion.empty() ? "" : "did you mean \"" + suggestion + "\"? ") +
                "limits and their defaults: " + replay_limit_names() + ")";
        return false;
    }
    const std::string value = eq == std::string::npos ? "" : spec.substr(eq + 1);
    char* end = nullptr;
    const unsigned long long v = std::strtoull(value.c_str(), &end, 0);
    if (value.empty() || *end || value[0] == '-' || v == 0) {
        error = "limit " + name + " takes a positive integer, not \"" + value + "\"";
        return false;
    }
    limits.*found->field = uint64_t(v);
    return true;
}

}  // namespace glcast::slave
