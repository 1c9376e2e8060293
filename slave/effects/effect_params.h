// Parameters of the injected passes: every one has a name ("pass.parameter"), a default, a
// range and a line of documentation, declared by its pass (pipeline.h: *_param_specs()).
// Values come from `--effect-param name=value` and from a display config's "effect_params"
// object; names and ranges are checked there, so a pass only reads valid values.
#pragma once

#include <map>
#include <string>
#include <vector>

namespace glcast::slave::effects {

struct ParamSpec {
    std::string name;   // "snow.speed"
    double value = 0;   // default
    double min = 0, max = 0;
    std::string help;   // one line: meaning and unit
    bool text = false;  // a text parameter (a file name): `value`, `min`, `max` unused
};

// Every parameter of every pass, in documentation order.
const std::vector<ParamSpec>& all_param_specs();

class EffectParams {
public:
    // Sets `name` to `value` (text as given on the command line or in a config). False with
    // `error` naming the parameter for an unknown name, a non-number or a value out of range.
    bool set(const std::string& name, const std::string& value, std::string& error);
    bool set_assignment(const std::string& name_equals_value, std::string& error);  // "name=value"
    // The value, or the default; throws std::logic_error for an undeclared name (a bug).
    double number(const std::string& name) const;
    bool flag(const std::string& name) const { return number(name) != 0; }
    std::string text(const std::string& name) const;
    bool has(const std::string& name) const { return values_.count(name) != 0; }

private:
    std::map<std::string, std::string> values_;
};

// The effect names --effects and a display config's "effects" may list, in the order the
// documentation gives them.
const std::vector<std::string>& known_display_effects();

// The effects a slave runs: names from --effects (comma-separated) and a display config's
// "effects", plus parameters.
struct EffectsSettings {
    bool snow = false, rain = false, cover = false, icicles = false, shadows = false;
    // Passes may be switched on while the program runs (slave/live_effects.h): the scene is
    // followed and shaders patched from the start, as if every pass were on.
    bool live = false;
    EffectParams params;
    bool any() const { return snow || rain || cover || icicles || shadows; }
    bool followed() const { return any() || live; }  // the replay follows the scene for the passes
    // Passes that re-render the frame's draws (FrameView::redraw): shader programs' vertex
    // shaders are then patched so that a redraw can move their output (glcast_clip).
    bool redraws() const { return live || cover || icicles || shadows; }
    // Adds "snow,cover,..." (names from known_display_effects()). False with `error` naming
    // the unknown effect.
    bool enable(const std::string& comma_separated, std::string& error);
};

}  // namespace glcast::slave::effects
