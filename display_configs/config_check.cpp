// Message helpers of the display config loader (config_check.h).
#include "display_configs/config_check.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cctype>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>

namespace glcast::slave::config_check {

// A string for a message: in double quotes, printable ASCII kept, everything else \xNN, and
// cut to about `max` characters.
std::string quote(const std::string& s, size_t max) {
    std::string out = "\"";
    size_t shown = 0;
    for (unsigned char c : s) {
        if (shown >= max) {
            out += "...";
            break;
        }
        if (c == '"' || c == '\\') {
            out += '\\';
            out += static_cast<char>(c);
        } else if (c >= 0x20 && c < 0x7f) {
            out += static_cast<char>(c);
        } else {
            char buf[8];
            std::snprintf(buf, sizeof buf, "\\x%02x", c);
            out += buf;
        }
        ++shown;
    }
    return out + "\"";
}

// The shortest text that reads back as `v`: 30, 120.5, 1e+300.
std::string format_double(double v) {
    if (std::isnan(v)) return "nan";
    if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
    char buf[40];
    if (std::floor(v) == v && std::fabs(v) < 1e15) {
        std::snprintf(buf, sizeof buf, "%.0f", v);
        return buf;
    }
    for (int precision = 1; precision <= 17; ++precision) {
        std::snprintf(buf, sizeof buf, "%.*g", precision, v);
        if (std::strtod(buf, nullptr) == v) break;
    }
    return buf;
}

// What a JSON value is, for "got ..." in messages.
std::string describe(const json& v) {
    switch (v.type()) {
    case json::value_t::null: return "null";
    case json::value_t::boolean: return v.get<bool>() ? "true" : "false";
    case json::value_t::number_integer: return std::to_string(v.get<int64_t>());
    case json::value_t::number_unsigned: return std::to_string(v.get<uint64_t>());
    case json::value_t::number_float: return format_double(v.get<double>());
    case json::value_t::string: return quote(v.get_ref<const std::string&>());
    case json::value_t::array: return "an array";
    case json::value_t::object: return "an object";
    default: return "a value of an unexpected kind";
    }
}

// A key in a JSON path: as it is if it is a plain word, else quoted ("tiles[0].\"wid th\"").
std::string join_key(const std::string& path, const std::string& key) {
    bool plain = !key.empty() && key.size() <= 64 &&
                 std::all_of(key.begin(), key.end(), [](unsigned char c) { return std::isalnum(c) || c == '_' || c == '-'; });
    std::string shown = plain ? key : quote(key);
    return path.empty() ? shown : path + "." + shown;
}

std::string join_index(const std::string& path, size_t index) {
    return path + "[" + std::to_string(index) + "]";
}

FileProblem read_regular_file(const std::string& path, size_t max_bytes, std::string& text, int& error_number,
                              std::string& kind) {
    text.clear();
    const int fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
    if (fd < 0) {
        error_number = errno;
        return FileProblem::cannot_open;
    }
    struct stat st {};
    if (::fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) {
        kind = S_ISDIR(st.st_mode) ? "a directory" : S_ISFIFO(st.st_mode) ? "a FIFO" : "not a plain file";
        ::close(fd);
        return FileProblem::not_regular;
    }
    char buf[65536];
    ssize_t n;
    FileProblem problem = FileProblem::none;
    while ((n = ::read(fd, buf, sizeof buf)) != 0) {
        if (n < 0) {
            if (errno == EINTR) continue;
            error_number = errno;
            problem = FileProblem::cannot_read;
            break;
        }
        text.append(buf, size_t(n));
        if (text.size() > max_bytes) {
            problem = FileProblem::too_large;
            break;
        }
    }
    ::close(fd);
    if (problem != FileProblem::none) text.clear();
    return problem;
}

}  // namespace glcast::slave::config_check
