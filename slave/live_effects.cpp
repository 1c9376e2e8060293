#include "slave/live_effects.h"

#include <cstdio>
#include <cstdlib>
#include <sstream>
#include <vector>

namespace glcast::slave {

namespace {

constexpr size_t kMaxLiveParams = 64;

bool* pass_flag(LiveEffects& e, const std::string& name) {
    if (name == "snow") return &e.snow;
    if (name == "rain") return &e.rain;
    if (name == "cover") return &e.cover;
    if (name == "icicles") return &e.icicles;
    if (name == "shadows") return &e.shadows;
    return nullptr;
}

std::string known_effects() {
    std::string list;
    for (const std::string& k : effects::known_display_effects()) list += (list.empty() ? "" : ", ") + k;
    return list;
}

bool text_param(const std::string& name) {
    for (const effects::ParamSpec& s : effects::all_param_specs())
        if (s.name == name) return s.text;
    return false;
}

// The shortest text that reads back as `v` (at most 24 characters): what a number is, however
// it was spelled ("0.5000...0" of 990 characters is 0.5).
std::string number_text(double v) {
    char text[32];
    for (int digits = 1; digits <= 17; digits++) {
        std::snprintf(text, sizeof text, "%.*g", digits, v);
        if (std::strtod(text, nullptr) == v) break;
    }
    return text;
}

// One NAME=VALUE, checked as --effect-param checks it, the value kept as the number it is; text
// parameters are refused.
bool check_param(const std::string& assignment, std::string& name, std::string& value, std::string& error) {
    const size_t eq = assignment.find('=');
    if (eq == std::string::npos || eq == 0) {
        error = "a parameter is NAME=VALUE, got \"" + assignment.substr(0, 64) + (assignment.size() > 64 ? "...\"" : "\"");
        return false;
    }
    name = assignment.substr(0, eq), value = assignment.substr(eq + 1);
    if (name.size() > 64) {
        error = "unknown effect parameter \"" + name.substr(0, 64) + "...\"";
        return false;
    }
    effects::EffectParams check;
    if (!check.set(name, value, error)) {
        if (error.size() > 256) error = error.substr(0, 256) + "...";
        return false;
    }
    if (text_param(name)) {
        error = "effect parameter " + name + " names a file: it is set when the tiles start, not live";
        return false;
    }
    value = number_text(std::strtod(value.c_str(), nullptr));
    return true;
}

}  // namespace

LiveEffects LiveEffects::from(const effects::EffectsSettings& s) {
    LiveEffects e;
    e.snow = s.snow, e.rain = s.rain, e.cover = s.cover, e.icicles = s.icicles, e.shadows = s.shadows;
    return e;
}

effects::EffectsSettings LiveEffects::applied_to(const effects::EffectsSettings& started) const {
    effects::EffectsSettings s = started;
    s.snow = snow, s.rain = rain, s.cover = cover, s.icicles = icicles, s.shadows = shadows;
    std::string ignored;
    for (const auto& [name, value] : params) (void)s.params.set(name, value, ignored);  // checked when taken
    return s;
}

std::string LiveEffects::enabled_list() const {
    std::string list;
    LiveEffects copy = *this;
    for (const std::string& k : effects::known_display_effects())
        if (*pass_flag(copy, k)) list += (list.empty() ? "" : ",") + k;
    return list.empty() ? "none" : list;
}

bool LiveEffects::change(const std::string& request, std::string& error) {
    std::istringstream in(request);
    std::string what, word;
    in >> what;
    LiveEffects next = *this;
    int changes = 0;
    if (what == "effects") {
        while (in >> word) {
            const bool on = word[0] != '-';
            const std::string name = (word[0] == '+' || word[0] == '-') ? word.substr(1) : word;
            bool* flag = pass_flag(next, name);
            if (!flag) {
                error = "unknown effect \"" + name.substr(0, 64) + "\" (effects: " + known_effects() + ")";
                return false;
            }
            *flag = on;
            changes++;
        }
        if (!changes) {
            error = "effects needs +NAME or -NAME (effects: " + known_effects() + ")";
            return false;
        }
    } else if (what == "param") {
        while (in >> word) {
            std::string name, value;
            if (!check_param(word, name, value, error)) return false;
            next.params[name] = value;
            changes++;
        }
        if (!changes) {
            error = "param needs NAME=VALUE (`glcast effects` lists the parameters)";
            return false;
        }
        if (next.params.size() > kMaxLiveParams) {
            error = "more than 64 parameters changed";
            return false;
        }
    } else {
        error = "unknown request \"" + what.substr(0, 64) + "\" (requests: effects +NAME -NAME, param NAME=VALUE)";
        return false;
    }
    // The state crosses the tile link whole: bounded here, whatever the requests add up to
    // (the largest version and frame numbers counted).
    LiveEffects widest = next;
    widest.version = widest.frame = UINT64_MAX;
    if (const size_t bytes = widest.words().size(); bytes > kMaxWordsBytes) {
        error = "the wall's live state would take " + std::to_string(bytes) + " bytes, over " +
                std::to_string(kMaxWordsBytes) + " (what the tiles' link carries): set fewer parameters";
        return false;
    }
    *this = next;
    return true;
}

std::string LiveEffects::words() const {
    std::string w = "EFFECTS " + std::to_string(version) + " " + std::to_string(frame) + " " + enabled_list();
    for (const auto& [name, value] : params) w += " " + name + "=" + value;
    return w;
}

bool LiveEffects::parse(const std::string& words, LiveEffects& out) {
    if (words.size() > kMaxWordsBytes) return false;
    std::istringstream in(words);
    std::string verb, list, word;
    LiveEffects e;
    if (!(in >> verb >> e.version >> e.frame >> list) || verb != "EFFECTS") return false;
    if (list != "none") {
        size_t start = 0;
        while (start <= list.size()) {
            size_t comma = list.find(',', start);
            if (comma == std::string::npos) comma = list.size();
            bool* flag = pass_flag(e, list.substr(start, comma - start));
            if (!flag) return false;
            *flag = true;
            start = comma + 1;
        }
    }
    while (in >> word) {
        std::string name, value, error;
        if (!check_param(word, name, value, error) || e.params.size() >= kMaxLiveParams) return false;
        e.params[name] = value;
    }
    out = e;
    return true;
}

}  // namespace glcast::slave
