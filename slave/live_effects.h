// The injected passes as the operator sets them while a program runs (docs/wall.md, "Live
// control"): which passes are on and the parameters changed, from one master frame on. glcast
// run keeps the wall's one LiveEffects, changed by `glcast ctl` and the dashboard, and hands it
// to every tile over the control channel; a tile applies it when it reaches `frame`, so every
// tile switches at the same frame and the wall never shows a seam. Pure, for tests.
#pragma once

#include <cstdint>
#include <map>
#include <string>

#include "slave/effects/effect_params.h"

namespace glcast::slave {

struct LiveEffects {
    uint64_t version = 0;  // 0: the passes the tiles started with; each change adds one
    uint64_t frame = 0;    // the first master frame it holds for
    bool snow = false, rain = false, cover = false, icicles = false, shadows = false;
    std::map<std::string, std::string> params;  // changed while running; the rest as started

    // The most words() may hold: it crosses the tile link in one message of at most 4,096
    // bytes, and glcast ctl's answer (the same, with some words before it) in one of 4,096.
    static constexpr size_t kMaxWordsBytes = 2048;

    // The wall's state at start: the passes and parameters every tile was started with.
    static LiveEffects from(const effects::EffectsSettings& started);
    // The settings a tile runs: its own as started, with this state's passes and parameters.
    effects::EffectsSettings applied_to(const effects::EffectsSettings& started) const;
    std::string enabled_list() const;  // "snow,cover", or "none"

    // An operator's request, in `glcast ctl`'s words: "effects +snow -shadows" (or a bare name:
    // on) or "param snow.density=0.4 ...". Changes nothing and returns false with `error` saying
    // what is wrong and what exists (the effects, or `glcast effects` for parameters) for an
    // unknown name, a value out of range or a text parameter (a file name is not set live).
    bool change(const std::string& request, std::string& error);

    // The control channel's words: "EFFECTS VERSION FRAME LIST [NAME=VALUE ...]".
    std::string words() const;
    // False for anything malformed or out of range (a message from the channel is not trusted).
    static bool parse(const std::string& words, LiveEffects& out);
};

}  // namespace glcast::slave
