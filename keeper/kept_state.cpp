#include "keeper/kept_state.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>
#include <zlib.h>

#include <cerrno>
#include <cinttypes>
#include <cstdio>
#include <cstring>

#include "protocol/format.h"

namespace glcast::keeper {

namespace {

// "glcast keeper state 1\n", "STATE <sequence> <frame>\n", "CHECK <boundary crc> <messages>
// <bytes> <crc of the messages>\n", then each message as a 4-byte little-endian length and its
// bytes.
constexpr char kMagicLine[] = "glcast keeper state 1\n";
constexpr size_t kMaxHeaderBytes = 256;

uint32_t crc_of(uint32_t crc, const std::vector<uint8_t>& bytes) {
    return uint32_t(crc32(crc, bytes.data(), uInt(bytes.size())));
}

bool write_all(int fd, const void* data, size_t n) {
    const char* p = static_cast<const char*>(data);
    while (n > 0) {
        const ssize_t w = write(fd, p, n);
        if (w < 0 && errno == EINTR) continue;
        if (w <= 0) return false;
        p += w;
        n -= size_t(w);
    }
    return true;
}

}  // namespace

bool save_kept_state(const std::string& path, const slave::NetworkSource::State& state, std::string& error) {
    uint64_t bytes = 0;
    uint32_t crc = uint32_t(crc32(0, nullptr, 0));
    for (const auto& m : state.messages) {
        bytes += m.size();
        crc = crc_of(crc, m);
    }
    char header[kMaxHeaderBytes];
    const int n = std::snprintf(header, sizeof header, "%sSTATE %" PRIu64 " %" PRIu64 "\nCHECK %u %zu %" PRIu64 " %u\n",
                                kMagicLine, state.sequence, state.frame, unsigned(state.boundary_crc),
                                state.messages.size(), bytes, unsigned(crc));
    const std::string temporary = path + ".new";
    const int fd = open(temporary.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC | O_NOFOLLOW, 0600);
    if (fd < 0) {
        error = temporary + ": " + std::strerror(errno);
        return false;
    }
    bool ok = write_all(fd, header, size_t(n));
    for (const auto& m : state.messages) {
        const uint8_t length[4] = {uint8_t(m.size()), uint8_t(m.size() >> 8), uint8_t(m.size() >> 16),
                                   uint8_t(m.size() >> 24)};
        ok = ok && write_all(fd, length, 4) && write_all(fd, m.data(), m.size());
    }
    ok = ok && fsync(fd) == 0;
    const int why = ok ? 0 : errno ? errno : ENOSPC;  // (a write of 0 bytes sets none: a full disk)
    close(fd);
    if (!ok || rename(temporary.c_str(), path.c_str()) != 0) {
        error = temporary + ": " + std::strerror(ok ? errno : why);
        unlink(temporary.c_str());
        return false;
    }
    return true;
}

bool load_kept_state(const std::string& path, uint64_t max_bytes, slave::NetworkSource::State& state,
                     std::string& error) {
    error.clear();
    // Without blocking or following a link: a FIFO in its place must not hang the keeper.
    const int fd = open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NONBLOCK | O_NOFOLLOW);
    if (fd < 0) {
        if (errno != ENOENT) error = path + ": " + std::strerror(errno);
        return false;
    }
    struct stat st {};
    auto refuse = [&](const std::string& why) {
        close(fd);
        error = path + ": " + why;
        return false;
    };
    if (fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) return refuse("not a regular file");
    if (st.st_uid != geteuid()) return refuse("owned by another user (uid " + std::to_string(st.st_uid) + ")");
    if (st.st_mode & (S_IWGRP | S_IWOTH)) return refuse("others may write to it");
    if (uint64_t(st.st_size) > max_bytes + kMaxHeaderBytes)
        return refuse("larger (" + std::to_string(st.st_size) + " bytes) than a catching up may take (" +
                      std::to_string(max_bytes) + ", GLCAST_CATCH_UP_MB)");
    std::vector<uint8_t> file(size_t(st.st_size));
    size_t got = 0;
    while (got < file.size()) {
        const ssize_t r = read(fd, file.data() + got, file.size() - got);
        if (r < 0 && errno == EINTR) continue;
        if (r <= 0) return refuse("cannot be read whole: " + std::string(r < 0 ? std::strerror(errno) : "it shrank"));
        got += size_t(r);
    }
    close(fd);
    auto fail = [&](const std::string& why) {
        error = path + ": " + why;
        return false;
    };
    // The header: three lines, within its first kMaxHeaderBytes.
    const std::string head(file.begin(), file.begin() + std::ptrdiff_t(std::min(file.size(), kMaxHeaderBytes)));
    if (head.rfind(kMagicLine, 0) != 0) return fail("not a keeper's state (its first line is not \"glcast keeper state 1\")");
    const size_t state_end = head.find('\n', sizeof kMagicLine - 1);
    const size_t check_end = state_end == std::string::npos ? std::string::npos : head.find('\n', state_end + 1);
    if (check_end == std::string::npos) return fail("its header is cut");
    const std::string state_line = head.substr(sizeof kMagicLine - 1, state_end - (sizeof kMagicLine - 1));
    slave::NetworkSource::State s;
    if (!slave::parse_keeper_state(state_line, s.sequence, s.frame))
        return fail("\"" + state_line.substr(0, 64) + "\" is no STATE <sequence> <frame>");
    unsigned boundary = 0, crc = 0;
    unsigned long long count = 0, bytes = 0;
    char tail = 0;
    const std::string check_line = head.substr(state_end + 1, check_end - state_end - 1);
    if (std::sscanf(check_line.c_str(), "CHECK %10u %10llu %16llu %10u%c", &boundary, &count, &bytes, &crc, &tail) != 4 ||
        check_line.find_first_not_of("CHECK 0123456789") != std::string::npos)
        return fail("\"" + check_line.substr(0, 64) + "\" is no CHECK <crc> <messages> <bytes> <crc>");
    s.boundary_crc = boundary;
    size_t at = check_end + 1;
    uint64_t total = 0;
    uint32_t sum = uint32_t(crc32(0, nullptr, 0));
    while (at < file.size()) {
        if (file.size() - at < 4) return fail("cut inside message " + std::to_string(s.messages.size()) + "'s length");
        const uint64_t n = uint64_t(file[at]) | uint64_t(file[at + 1]) << 8 | uint64_t(file[at + 2]) << 16 |
                           uint64_t(file[at + 3]) << 24;
        at += 4;
        if (n < sizeof(MessageHeader) || n > sizeof(MessageHeader) + kMaxMessageBytes || n > file.size() - at)
            return fail("message " + std::to_string(s.messages.size()) + " claims " + std::to_string(n) +
                        " bytes, which is no message or more than the file holds");
        uint32_t magic = 0;
        std::memcpy(&magic, file.data() + at, sizeof magic);
        if (magic != kMessageMagic) return fail("message " + std::to_string(s.messages.size()) + " is no framed message");
        if (s.messages.size() >= count) return fail("more messages than its header says (" + std::to_string(count) + ")");
        s.messages.emplace_back(file.begin() + std::ptrdiff_t(at), file.begin() + std::ptrdiff_t(at + n));
        sum = crc_of(sum, s.messages.back());
        total += n;
        at += n;
    }
    if (s.messages.size() != count || total != bytes || sum != crc)
        return fail("holds " + std::to_string(s.messages.size()) + " messages of " + std::to_string(total) +
                    " bytes, its header says " + std::to_string(count) + " of " + std::to_string(bytes) +
                    (sum != crc ? ", and their checksum differs" : ""));
    state = std::move(s);
    return true;
}

}  // namespace glcast::keeper
