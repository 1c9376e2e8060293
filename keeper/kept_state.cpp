#include "keeper/kept_state.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>
#include <zlib.h>

#include <cerrno>
#include <cinttypes>
#include <cstdio>
#include <cstring>
#include <new>
#include <stdexcept>

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
    // Read as it is taken, one message at a time into its own buffer (never the file whole and
    // a copy), and only after the header's count and total agree with the file's size: a file
    // that says less than it is, or is mostly holes, is refused before anything is held.
    auto read_exactly = [&](void* into, size_t n) {
        size_t got = 0;
        while (got < n) {
            const ssize_t r = read(fd, static_cast<char*>(into) + got, n - got);
            if (r < 0 && errno == EINTR) continue;
            if (r < 0) throw std::runtime_error("cannot be read: " + std::string(std::strerror(errno)));
            if (r == 0) return false;
            got += size_t(r);
        }
        return true;
    };
    std::string head(std::min<size_t>(size_t(st.st_size), kMaxHeaderBytes), '\0');
    slave::NetworkSource::State s;
    try {
        if (!read_exactly(head.data(), head.size())) return refuse("it shrank while read");
        if (head.rfind(kMagicLine, 0) != 0)
            return refuse("not a keeper's state (its first line is not \"glcast keeper state 1\")");
        const size_t state_end = head.find('\n', sizeof kMagicLine - 1);
        const size_t check_end = state_end == std::string::npos ? std::string::npos : head.find('\n', state_end + 1);
        if (check_end == std::string::npos) return refuse("its header is cut");
        const std::string state_line = head.substr(sizeof kMagicLine - 1, state_end - (sizeof kMagicLine - 1));
        if (!slave::parse_keeper_state(state_line, s.sequence, s.frame))
            return refuse("\"" + state_line.substr(0, 64) + "\" is no STATE <sequence> <frame>");
        unsigned boundary = 0, crc = 0;
        unsigned long long count = 0, bytes = 0;
        char tail = 0;
        const std::string check_line = head.substr(state_end + 1, check_end - state_end - 1);
        if (std::sscanf(check_line.c_str(), "CHECK %10u %10llu %16llu %10u%c", &boundary, &count, &bytes, &crc, &tail) != 4 ||
            check_line.find_first_not_of("CHECK 0123456789") != std::string::npos)
            return refuse("\"" + check_line.substr(0, 64) + "\" is no CHECK <crc> <messages> <bytes> <crc>");
        s.boundary_crc = boundary;
        const uint64_t body_at = check_end + 1;
        const std::string says = std::to_string(count) + " messages of " + std::to_string(bytes) + " bytes";
        if (bytes > max_bytes || count > bytes / sizeof(MessageHeader))
            return refuse("its header says " + says + ": no messages, or more than a catching up may take (" +
                          std::to_string(max_bytes) + ")");
        const uint64_t expected = body_at + 4 * uint64_t(count) + bytes;
        if (uint64_t(st.st_size) < expected)
            return refuse("its header says " + says + ", more than the file holds (" + std::to_string(st.st_size) + " bytes)");
        if (uint64_t(st.st_size) > expected)
            return refuse("more messages than its header says (" + says + ", in a file of " + std::to_string(st.st_size) + " bytes)");
        if (lseek(fd, off_t(body_at), SEEK_SET) != off_t(body_at)) return refuse("cannot be read: " + std::string(std::strerror(errno)));
        uint64_t total = 0;
        uint32_t sum = uint32_t(crc32(0, nullptr, 0));
        for (unsigned long long i = 0; i < count; i++) {
            uint8_t length[4];
            if (!read_exactly(length, 4)) return refuse("cut inside message " + std::to_string(i) + "'s length");
            const uint64_t n = uint64_t(length[0]) | uint64_t(length[1]) << 8 | uint64_t(length[2]) << 16 |
                               uint64_t(length[3]) << 24;
            if (n < sizeof(MessageHeader) || n > sizeof(MessageHeader) + kMaxMessageBytes || n > bytes - total)
                return refuse("message " + std::to_string(i) + " claims " + std::to_string(n) +
                              " bytes, which is no message or more than the file holds");
            std::vector<uint8_t> m(n);
            if (!read_exactly(m.data(), n)) return refuse("message " + std::to_string(i) + " claims more than the file holds");
            uint32_t magic = 0;
            std::memcpy(&magic, m.data(), sizeof magic);
            if (magic != kMessageMagic) return refuse("message " + std::to_string(i) + " is no framed message");
            sum = crc_of(sum, m);
            total += n;
            s.messages.push_back(std::move(m));
        }
        if (total != bytes || sum != crc)
            return refuse("holds " + std::to_string(s.messages.size()) + " messages of " + std::to_string(total) +
                          " bytes, its header says " + std::to_string(count) + " of " + std::to_string(bytes) +
                          (sum != crc ? ", and their checksum differs" : ""));
    } catch (const std::bad_alloc&) {
        return refuse("cannot be held in memory (" + std::to_string(st.st_size) + " bytes): left for the journal");
    } catch (const std::runtime_error& e) {
        return refuse(e.what());
    }
    close(fd);
    state = std::move(s);
    return true;
}

}  // namespace glcast::keeper
