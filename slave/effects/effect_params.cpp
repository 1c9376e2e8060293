#include "slave/effects/effect_params.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>

#include "common/edit_distance.h"
#include "slave/effects/pipeline.h"

namespace glcast::slave::effects {

const std::vector<ParamSpec>& all_param_specs() {
    static const std::vector<ParamSpec> specs = [] {
        std::vector<ParamSpec> all;
        for (auto part : {precipitation_param_specs(), winter_surfaces_param_specs(), shadow_param_specs()})
            all.insert(all.end(), part.begin(), part.end());
        return all;
    }();
    return specs;
}

static const ParamSpec* find_spec(const std::string& name) {
    for (const ParamSpec& s : all_param_specs())
        if (s.name == name) return &s;
    return nullptr;
}

bool EffectParams::set(const std::string& name, const std::string& value, std::string& error) {
    const ParamSpec* spec = find_spec(name);
    if (!spec) {
        std::string suggestion;
        size_t best = 3;
        for (const ParamSpec& s : all_param_specs())
            if (size_t d = edit_distance(name, s.name); d < best) best = d, suggestion = s.name;
        error = "unknown effect parameter \"" + name + "\" (" +
                (suggestion.empty() ? "" : "did you mean \"" + suggestion + "\"? ") +
                "`glcast effects` lists them all)";
        return false;
    }
    if (!spec->text) {
        char* end = nullptr;
        const double v = std::strtod(value.c_str(), &end);
        if (value.empty() || *end || !std::isfinite(v)) {
            error = "effect parameter " + name + ": expected a number, got \"" + value + "\"";
            return false;
        }
        if (v < spec->min || v > spec->max) {
            char range[64];
            std::snprintf(range, sizeof range, "[%g, %g]", spec->min, spec->max);
            error = "effect parameter " + name + " = " + value + " is out of range " + range;
            return false;
        }
    }
    values_[name] = value;
    return true;
}

bool EffectParams::set_assignment(const std::string& assignment, std::string& error) {
    const size_t eq = assignment.find('=');
    if (eq == std::string::npos || eq == 0) {
        error = "--effect-param takes NAME=VALUE, got \"" + assignment + "\"";
        return false;
    }
    return set(assignment.substr(0, eq), assignment.substr(eq + 1), error);
}

double EffectParams::number(const std::string& name) const {
    const ParamSpec* spec = find_spec(name);
    if (!spec || spec->text) throw std::logic_error("undeclared numeric effect parameter " + name);
    auto it = values_.find(name);
    return it == values_.end() ? spec->value : std::strtod(it->second.c_str(), nullptr);
}

std::string EffectParams::text(const std::string& name) const {
    const ParamSpec* spec = find_spec(name);
    if (!spec || !spec->text) throw std::logic_error("undeclared text effect parameter " + name);
    auto it = values_.find(name);
    return it == values_.end() ? std::string() : it->second;
}

const std::vector<std::string>& known_display_effects() {
    static const std::vector<std::string> names = {"snow", "rain", "cover", "icicles", "shadows"};
    return names;
}

bool EffectsSettings::enable(const std::string& list, std::string& error) {
    size_t start = 0;
    while (start <= list.size()) {
        size_t comma = list.find(',', start);
        if (comma == std::string::npos) comma = list.size();
        const std::string name = list.substr(start, comma - start);
        if (name == "snow") snow = true;
        else if (name == "rain") rain = true;
        else if (name == "cover") cover = true;
        else if (name == "icicles") icicles = true;
        else if (name == "shadows") shadows = true;
        else {
            error = "unknown effect \"" + name + "\" (known:";
            for (const std::string& k : known_display_effects()) error += " " + k;
            error += ")";
            return false;
        }
        start = comma + 1;
    }
    return true;
}

}  // namespace glcast::slave::effects
