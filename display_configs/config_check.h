// The display config loader's checks (display_config.cpp, immersive_config.cpp): messages that
// name the file, the JSON path and what is wrong, and the field readers that make them.
#pragma once

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>

#include "common/edit_distance.h"
#include "display_configs/display_config.h"

namespace glcast::slave::config_check {

using json = nlohmann::json;

// A string for a message: in double quotes, printable ASCII kept, everything else \xNN, and
// cut to about `max` characters.
std::string quote(const std::string& s, size_t max = 64);
// The shortest text that reads back as `v`: 30, 120.5, 1e+300.
std::string format_double(double v);
// What a JSON value is, for "got ..." in messages.
std::string describe(const json& v);
// A key in a JSON path: as it is if it is a plain word, else quoted ("tiles[0].\"wid th\"").
std::string join_key(const std::string& path, const std::string& key);
std::string join_index(const std::string& path, size_t index);

// Reads `path` whole into `text` when it is a regular file of at most `max_bytes`. Opened without
// blocking and read only if it is a regular file: a FIFO (or a device) named as a config would
// hang the reader until something wrote to it, or forever; and no more than max_bytes + 1 is
// ever read. Otherwise false, with what stopped it; `error_number` is errno's for cannot_open and
// cannot_read, and `kind` what the path is for not_regular ("a directory", "a FIFO", ...).
enum class FileProblem { none, cannot_open, not_regular, too_large, cannot_read };
FileProblem read_regular_file(const std::string& path, size_t max_bytes, std::string& text, int& error_number,
                              std::string& kind);

class Validator {
public:
    Validator(const std::string& origin, std::string& error) : origin_(origin), error_(error) {}

    bool fail(const std::string& path, const std::string& what) {
        error_ = origin_ + ": " + (path.empty() ? std::string() : path + ": ") + what;
        return false;
    }

    // Every key of `object` must be one of `known`.
    template <size_t N>
    bool check_keys(const json& object, const std::string& path, const char* const (&known)[N]) {
        for (const auto& item : object.items()) {
            const std::string& key = item.key();
            if (std::find_if(known, known + N, [&](const char* k) { return key == k; }) != known + N) continue;
            std::string list, suggestion;
            // Suggest the nearest known key if it is 1 edit away (2 for keys of 5 letters or more).
            size_t best = key.size() >= 5 ? 3 : 2;
            for (const char* k : known) {
                list += (list.empty() ? "" : ", ") + std::string(k);
                size_t d = edit_distance(key, k);
                if (d < best) {
                    best = d;
                    suggestion = k;
                }
            }
            std::string hint = suggestion.empty() ? "" : "did you mean \"" + suggestion + "\"? ";
            return fail(join_key(path, key), "unknown key (" + hint + "known keys: " + list + ")");
        }
        return true;
    }

    // An integer field with min <= value <= kMaxDisplaySize. Absent: `present` false, `out` kept,
    // an error only if `required`.
    bool int_field(const json& object, const std::string& path, const char* key, bool required, int min,
                   int& out, bool* present = nullptr) {
        std::string field = join_key(path, key);
        auto it = object.find(key);
        if (present) *present = it != object.end();
        if (it == object.end()) return required ? fail(field, "missing required key") : true;
        const json& v = *it;
        const char* must = min > 0 ? "must be a positive integer" : "must be a non-negative integer";
        int64_t n = 0;
        if (!as_integer(v, n) || n < min) return fail(field, std::string(must) + ", got " + describe(v));
        if (n > kMaxDisplaySize) return fail(field, "must be at most " + std::to_string(kMaxDisplaySize) + ", got " + describe(v));
        out = static_cast<int>(n);
        return true;
    }

    bool number_field(const json& object, const std::string& path, const char* key, double& out) {
        auto it = object.find(key);
        if (it == object.end()) return true;
        std::string field = join_key(path, key);
        if (!it->is_number()) return fail(field, "must be a number (degrees), got " + describe(*it));
        double v = it->get<double>();
        if (!std::isfinite(v)) return fail(field, "must be a finite number, got " + describe(*it));
        out = v;
        return true;
    }

    bool name_field(const json& object, const std::string& path, std::string& out) {
        std::string field = join_key(path, "name");
        auto it = object.find("name");
        if (it == object.end()) return fail(field, "missing required key");
        if (!it->is_string()) return fail(field, "must be a string, got " + describe(*it));
        const std::string& name = it->get_ref<const std::string&>();
        if (name.empty()) return fail(field, "must not be empty");
        if (!is_valid_display_name(name))
            return fail(field, "must contain only letters, digits, '_', '.' and '-', and start with a letter, a digit or "
                               "'_' ([A-Za-z0-9_][A-Za-z0-9_.-]*: a name becomes a folder and a command-line word), got " +
                               quote(name));
        out = name;
        return true;
    }

private:
    // Integral JSON numbers (also 1e3 or 640.0) as int64; huge values clamp so that range checks
    // reject them with the original value in the message.
    static bool as_integer(const json& v, int64_t& out) {
        if (v.is_number_unsigned()) {
            uint64_t u = v.get<uint64_t>();
            out = u > static_cast<uint64_t>(std::numeric_limits<int64_t>::max()) ? std::numeric_limits<int64_t>::max()
                                                                                  : static_cast<int64_t>(u);
            return true;
        }
        if (v.is_number_integer()) {
            out = v.get<int64_t>();
            return true;
        }
        if (v.is_number_float()) {
            double d = v.get<double>();
            if (!std::isfinite(d) || std::floor(d) != d) return false;
            if (d > 1e15) out = std::numeric_limits<int64_t>::max();
            else if (d < -1e15) out = std::numeric_limits<int64_t>::min();
            else out = static_cast<int64_t>(d);
            return true;
        }
        return false;
    }

    const std::string& origin_;
    std::string& error_;
};

}  // namespace glcast::slave::config_check
