#include "cli/options.h"

#include <cinttypes>
#include <climits>
#include <functional>

#include "cli/paths.h"
#include "common/environment.h"
#include "net/security.h"
#include "slave/effects/effect_params.h"
#include "slave/replayer.h"

namespace glcast::cli {

namespace {

std::string quoted(const std::string& s) { return "'" + s + "'"; }

std::vector<std::string> split(const std::string& s, char separator) {
    std::vector<std::string> parts;
    size_t start = 0;
    for (;;) {
        const size_t at = s.find(separator, start);
        parts.push_back(s.substr(start, at == std::string::npos ? std::string::npos : at - start));
        if (at == std::string::npos) return parts;
        start = at + 1;
    }
}

// Digits only, at most UINT64_MAX; false on anything else.
bool digits_u64(const std::string& s, uint64_t& out) {
    if (s.empty() || s.find_first_not_of("0123456789") != std::string::npos) return false;
    uint64_t v = 0;
    for (const char c : s) {
        const uint64_t d = uint64_t(c - '0');
        if (v > (UINT64_MAX - d) / 10) return false;
        v = v * 10 + d;
    }
    out = v;
    return true;
}

bool digits_int(const std::string& s, int64_t& out) {
    const bool negative = !s.empty() && s[0] == '-';
    uint64_t magnitude = 0;
    if (!digits_u64(negative ? s.substr(1) : s, magnitude) || magnitude > uint64_t(INT64_MAX)) return false;
    out = negative ? -int64_t(magnitude) : int64_t(magnitude);
    return true;
}

std::string range_text(int64_t min, int64_t max) { return std::to_string(min) + ".." + std::to_string(max); }

}  // namespace

bool parse_u64(const std::string& s, uint64_t min, uint64_t max, uint64_t& out, std::string& error) {
    uint64_t v = 0;
    if (!digits_u64(s, v) || v < min || v > max) {
        error = "expected a whole number in " + std::to_string(min) + ".." + std::to_string(max) + ", got " + quoted(s);
        return false;
    }
    out = v;
    return true;
}

bool parse_int(const std::string& s, int min, int max, int& out, std::string& error) {
    int64_t v = 0;
    if (!digits_int(s, v) || v < min || v > max) {
        error = "expected a whole number in " + range_text(min, max) + ", got " + quoted(s);
        return false;
    }
    out = int(v);
    return true;
}

bool parse_frame_range(const std::string& s, LoneFrame lone, FrameRange& out, std::string& error) {
    const size_t colon = s.find(':');
    FrameRange r;
    bool ok = true;
    if (colon == std::string::npos) {
        ok = digits_u64(s, r.first);
        if (lone == LoneFrame::only_that_frame) r.last = r.first;
    } else {
        const std::string a = s.substr(0, colon), b = s.substr(colon + 1);
        ok = (a.empty() || digits_u64(a, r.first)) && (b.empty() || digits_u64(b, r.last)) && !(a.empty() && b.empty());
    }
    if (!ok) {
        error = "expected A:B, got " + quoted(s);
        return false;
    }
    if (r.first > r.last) {
        error = "expected A:B with A <= B, got " + quoted(s);
        return false;
    }
    out = r;
    return true;
}

bool parse_size(const std::string& s, int max, int& width, int& height, std::string& error) {
    const std::vector<std::string> parts = split(s, 'x');
    int64_t w = 0, h = 0;
    if (parts.size() != 2 || !digits_int(parts[0], w) || !digits_int(parts[1], h) || w < 1 || h < 1 || w > max ||
        h > max) {
        error = "expected WxH with W and H in 1.." + std::to_string(max) + ", got " + quoted(s);
        return false;
    }
    width = int(w), height = int(h);
    return true;
}

bool parse_ints(const std::string& s, size_t count, int min, int max, const std::string& what, std::vector<int>& out,
                std::string& error) {
    const std::vector<std::string> parts = split(s, ',');
    std::vector<int> values;
    for (const std::string& p : parts) {
        int64_t v = 0;
        if (!digits_int(p, v) || v < min || v > max) break;
        values.push_back(int(v));
    }
    if (parts.size() != count || values.size() != count) {
        error = "expected " + what + " (whole numbers in " + range_text(min, max) + "), got " + quoted(s);
        return false;
    }
    out = values;
    return true;
}

std::string option_display_name(const std::string& names) {
    const size_t comma = names.rfind(',');
    return comma == std::string::npos ? names : names.substr(comma + 1);
}

void usage_error(const std::string& option, const std::string& message) {
    if (message.rfind(option, 0) == 0) throw CLI::ValidationError(message);
    throw CLI::ValidationError(option, message);
}

namespace {

// An option whose every value, repeated or not, goes through `set` (which throws usage_error on a
// bad one); the last value wins. One value per occurrence: a positional after it stays one.
CLI::Option* add_checked(CLI::App& app, const std::string& names, const std::string& type_name, const std::string& help,
                         std::function<void(const std::string& name, const std::string& value)> set) {
    const std::string name = option_display_name(names);
    return app
        .add_option_function<std::vector<std::string>>(
            names,
            [name, set](const std::vector<std::string>& values) {
                for (const std::string& v : values) set(name, v);
            },
            help)
        ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll)
        ->allow_extra_args(false)
        ->expected(1)
        ->type_name(type_name);
}

}  // namespace

CLI::Option* add_u64(CLI::App& app, const std::string& names, uint64_t& out, uint64_t min, uint64_t max,
                     const std::string& help) {
    return add_checked(app, names, "N", help, [&out, min, max](const std::string& name, const std::string& v) {
        std::string error;
        if (!parse_u64(v, min, max, out, error)) usage_error(name, error);
    });
}

CLI::Option* add_int(CLI::App& app, const std::string& names, int& out, int min, int max, const std::string& help) {
    return add_checked(app, names, "N", help, [&out, min, max](const std::string& name, const std::string& v) {
        std::string error;
        if (!parse_int(v, min, max, out, error)) usage_error(name, error);
    });
}

CLI::Option* add_frame_range(CLI::App& app, const std::string& names, LoneFrame lone, uint64_t& first,
                             uint64_t& last, const std::string& help) {
    return add_checked(app, names, "A:B", help, [&first, &last, lone](const std::string& name, const std::string& v) {
        FrameRange r;
        std::string error;
        if (!parse_frame_range(v, lone, r, error)) usage_error(name, error);
        first = r.first, last = r.last;
    });
}

CLI::Option* add_size(CLI::App& app, const std::string& names, int max, int& width, int& height,
                      const std::string& help) {
    return add_checked(app, names, "WxH", help, [&width, &height, max](const std::string& name, const std::string& v) {
        std::string error;
        if (!parse_size(v, max, width, height, error)) usage_error(name, error);
    });
}

CLI::Option* add_ints(CLI::App& app, const std::string& names, size_t count, int min, int max,
                      const std::string& what, std::vector<int>& out, const std::string& help) {
    return add_checked(app, names, what, help, [&out, count, min, max, what](const std::string& name, const std::string& v) {
        std::string error;
        if (!parse_ints(v, count, min, max, what, out, error)) usage_error(name, error);
    });
}

void add_effect_options(CLI::App& app, slave::effects::EffectsSettings& effects, std::vector<std::string>* forwarded) {
    // Every occurrence counts (--effects snow --effects rain runs both).
    add_checked(app, "--effects", "LIST",
                "injected passes run before each present, comma-separated:\n"
                "snow, rain, cover, icicles, shadows (docs/effects.md)",
                [&effects, forwarded](const std::string& name, const std::string& list) {
                    std::string error;
                    if (!effects.enable(list, error)) usage_error(name, error);
                    if (forwarded) forwarded->insert(forwarded->end(), {name, list});
                });
    add_checked(app, "--effect-param", "NAME=VALUE", "one parameter of the passes, repeatable (glcast effects lists them)",
                [&effects, forwarded](const std::string& name, const std::string& assignment) {
                    std::string error;
                    if (!effects.params.set_assignment(assignment, error)) usage_error(name, error);
                    if (forwarded) forwarded->insert(forwarded->end(), {name, assignment});
                });
}

void add_limit_option(CLI::App& app, slave::ReplayLimits& limits) {
    add_checked(app, "--limit", "NAME=VALUE",
                "a bound on what the stream may make the slave allocate, repeatable\n(defaults: " +
                    slave::replay_limit_names() + ")",
                [&limits](const std::string& name, const std::string& assignment) {
                    std::string error;
                    if (!slave::set_replay_limit(limits, assignment, error)) usage_error(name, error);
                });
}

void add_security_options(CLI::App& app, std::string& keys, bool& insecure) {
    app.add_option("--keys", keys,
                   "a folder of CURVE keys (glcast keygen; docs/security.md): TCP is authenticated and\n"
                   "encrypted (default: the display config's \"keys\", else GLCAST_KEYS)")
        ->type_name("DIR");
    app.add_flag("--insecure", insecure,
                 "allow a network or multicast endpoint without keys: anyone who reaches it can read the\n"
                 "stream or pose as the master");
}

bool use_keys(const std::string& keys, bool insecure, const char* who, std::string& error) {
    try {
        // Given here or in the environment; set in it for the children (slaves, the program's shim).
        const Environment& env = environment();
        const std::string dir = keys.empty() ? env.keys : absolute_path(keys);
        if (!dir.empty()) setenv("GLCAST_KEYS", dir.c_str(), 1);
        if (insecure) setenv("GLCAST_INSECURE", "1", 1);
        net::use_process_keys(dir, insecure || env.insecure);
        (void)net::process_security();
        return true;
    } catch (const std::exception& e) {
        error = e.what();
        std::fprintf(stderr, "%s: %s\n", who, error.c_str());
        return false;
    }
}

}  // namespace glcast::cli
