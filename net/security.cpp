#include "net/security.h"

#include <dirent.h>
#include <fcntl.h>
#include <pthread.h>
#include <sys/stat.h>
#include <unistd.h>

#include <zmq.hpp>

#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <mutex>
#include <vector>

#include "common/environment.h"
#include "common/immortal.h"

namespace glcast::net {

namespace {

constexpr size_t kZ85KeyChars = 40;
constexpr size_t kMaxKeyFileBytes = 4096;
constexpr size_t kMaxAuthorizedKeys = 4096;

bool z85_key(const std::string& s) {
    if (s.size() != kZ85KeyChars) return false;
    uint8_t binary[32];
    return zmq_z85_decode(binary, s.c_str()) != nullptr;
}

std::string trim(const std::string& s) {
    size_t a = 0, b = s.size();
    while (a < b && (s[a] == ' ' || s[a] == '\t' || s[a] == '"')) a++;
    while (b > a && (s[b - 1] == ' ' || s[b - 1] == '\t' || s[b - 1] == '\r' || s[b - 1] == '"')) b--;
    return s.substr(a, b - a);
}

bool exists(const std::string& path) {
    struct stat st {};
    return stat(path.c_str(), &st) == 0;
}

// As ssh trusts authorized_keys and the folders above it: owned by this user or root, and no
// one else may write to it (who could, could put a key of theirs in its place).
bool trusted(const struct stat& st, const std::string& path, std::string& error) {
    if (st.st_uid != 0 && st.st_uid != geteuid()) {
        error = path + ": owned by another user (uid " + std::to_string(st.st_uid) + ")";
        return false;
    }
    if (st.st_mode & (S_IWGRP | S_IWOTH)) {
        char mode[8];
        std::snprintf(mode, sizeof mode, "%03o", unsigned(st.st_mode & 07777));
        error = path + ": others may write to it (mode " + mode + ")";
        return false;
    }
    return true;
}

bool trusted_folder(const std::string& dir, std::string& error) {
    struct stat st {};
    if (stat(dir.c_str(), &st) != 0) {
        error = dir + ": " + std::strerror(errno);
        return false;
    }
    return trusted(st, dir, error);
}

std::string folder_of(const std::string& path) {
    const size_t slash = path.rfind('/');
    return slash == std::string::npos ? "." : slash == 0 ? "/" : path.substr(0, slash);
}

}  // namespace

bool read_key_file(const std::string& path, bool want_secret, KeyPair& out, std::string& error) {
    // Without blocking: a FIFO in its place must not hang the reader.
    const int fd = open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NONBLOCK);
    if (fd < 0) {
        error = path + ": " + std::strerror(errno);
        return false;
    }
    struct stat st {};
    if (fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) {
        close(fd);
        error = path + ": not a regular file";
        return false;
    }
    if (!trusted(st, path, error)) {
        close(fd);
        return false;
    }
    if (want_secret && (st.st_mode & (S_IRWXG | S_IRWXO))) {
        close(fd);
        char mode[8];
        std::snprintf(mode, sizeof mode, "%03o", unsigned(st.st_mode & 0777));
        error = path + ": a secret key others may read (mode " + mode + "); chmod 600 it";
        return false;
    }
    std::string text(kMaxKeyFileBytes + 1, '\0');
    const ssize_t n = read(fd, text.data(), text.size());
    close(fd);
    if (n < 0 || size_t(n) > kMaxKeyFileBytes) {
        error = path + ": not a key file (larger than 4 KiB)";
        return false;
    }
    text.resize(size_t(n));
    KeyPair k;
    size_t at = 0, line_number = 0;
    while (at < text.size()) {
        size_t end = text.find('\n', at);
        if (end == std::string::npos) end = text.size();
        const std::string line = trim(text.substr(at, end - at));
        at = end + 1;
        line_number++;
        if (line.empty() || line[0] == '#') continue;
        const size_t eq = line.find('=');
        const std::string name = eq == std::string::npos ? "" : trim(line.substr(0, eq));
        const std::string value = eq == std::string::npos ? "" : trim(line.substr(eq + 1));
        if (name != "public-key" && name != "secret-key") {
            error = path + ":" + std::to_string(line_number) + ": expected public-key = KEY or secret-key = KEY";
            return false;
        }
        if (!z85_key(value)) {
            error = path + ":" + std::to_string(line_number) + ": " + name + " is not a Z85 CURVE key (40 characters)";
            return false;
        }
        (name == "public-key" ? k.public_key : k.secret_key) = value;
    }
    if (k.public_key.empty() || (want_secret && k.secret_key.empty())) {
        error = path + ": no " + std::string(k.public_key.empty() ? "public-key" : "secret-key") + " line";
        return false;
    }
    if (want_secret) {
        char derived[kZ85KeyChars + 1];
        if (zmq_curve_public(derived, k.secret_key.c_str()) != 0 || k.public_key != derived) {
            error = path + ": its public-key is not the secret-key's";
            return false;
        }
    }
    out = k;
    return true;
}

bool write_key_pair(const std::string& path, std::string& error) {
    char public_key[kZ85KeyChars + 1], secret_key[kZ85KeyChars + 1];
    if (zmq_curve_keypair(public_key, secret_key) != 0) {
        error = std::string("this libzmq has no CURVE: ") + zmq_strerror(zmq_errno());
        return false;
    }
    const std::string secret_path = path + ".key", public_path = path + ".pub";
    if (!trusted_folder(folder_of(path), error)) return false;
    for (const std::string& p : {secret_path, public_path})
        if (exists(p)) {
            error = p + " exists; keys are not overwritten";
            return false;
        }
    auto write = [&](const std::string& p, mode_t mode, const std::string& text) {
        const int fd = open(p.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, mode);
        if (fd < 0 || ::write(fd, text.data(), text.size()) != ssize_t(text.size()) || fsync(fd) != 0) {
            error = p + ": " + std::strerror(errno);
            if (fd >= 0) close(fd);
            return false;
        }
        fchmod(fd, mode);  // not widened by the umask, never narrowed below what is asked
        return close(fd) == 0;
    };
    const std::string pub = std::string("# glcast CURVE public key\npublic-key = \"") + public_key + "\"\n";
    return write(secret_path, 0600, pub + "secret-key = \"" + secret_key + "\"\n") && write(public_path, 0644, pub);
}

bool load_security(const std::string& dir, bool insecure, Security& out, std::string& error) {
    Security s;
    s.insecure = insecure;
    if (dir.empty()) {
        out = s;
        return true;
    }
    s.dir = dir;
    if (!trusted_folder(dir, error) || (exists(dir + "/authorized") && !trusted_folder(dir + "/authorized", error)) ||
        (exists(dir + "/operators") && !trusted_folder(dir + "/operators", error))) {
        error = "keys: " + error;
        return false;
    }
    KeyPair master_public;
    if (!read_key_file(dir + "/master.pub", false, master_public, error)) {
        error = "keys (GLCAST_KEYS " + dir + "): " + error;
        return false;
    }
    s.master_public = master_public.public_key;
    auto pair = [&](const char* name, KeyPair& k) {
        const std::string p = dir + "/" + name;
        if (!exists(p)) return false;
        if (!read_key_file(p, true, k, error)) throw std::runtime_error(error);
        return true;
    };
    try {
        s.has_master_pair = pair("master.key", s.master);
        if (s.has_master_pair && s.master.public_key != s.master_public) {
            error = "keys: " + dir + "/master.key is not the pair of " + dir + "/master.pub";
            return false;
        }
        s.has_client_pair = pair("slave.key", s.client);
        s.has_operator_pair = pair("operator.key", s.operator_pair);
    } catch (const std::runtime_error& e) {
        error = std::string("keys: ") + e.what();
        return false;
    }
    if (!s.has_client_pair && s.has_master_pair) {
        s.client = s.master;
        s.has_client_pair = true;
    }
    if (!s.has_operator_pair && s.has_client_pair) s.operator_pair = s.client, s.has_operator_pair = true;
    s.authorized.insert(s.master_public);
    s.operators.insert(s.master_public);
    if (s.has_client_pair) s.authorized.insert(s.client.public_key);
    // Every NAME.pub of a folder into `keys` (and the authorized, whom the ZAP handler admits).
    auto read_keys_in = [&](const std::string& folder, std::set<std::string>& keys, bool machines) {
        DIR* d = opendir(folder.c_str());
        if (!d) return true;
        while (dirent* e = readdir(d)) {
            const std::string name = e->d_name;
            if (name.size() < 5 || name.compare(name.size() - 4, 4, ".pub") != 0) continue;
            KeyPair k;
            if (!read_key_file(folder + "/" + name, false, k, error)) {
                closedir(d);
                error = "keys: " + error;
                return false;
            }
            if (s.authorized.size() >= kMaxAuthorizedKeys) {
                closedir(d);
                error = "keys: more than 4096 keys in " + folder;
                return false;
            }
            keys.insert(k.public_key);
            s.authorized.insert(k.public_key);
            if (machines) s.machines[name.substr(0, name.size() - 4)] = k.public_key;
        }
        closedir(d);
        return true;
    };
    if (!read_keys_in(dir + "/authorized", s.authorized, true) || !read_keys_in(dir + "/operators", s.operators, false))
        return false;
    out = s;
    return true;
}

namespace {

struct ProcessKeys {
    std::mutex mutex;
    bool read = false;
    Security security;
    std::string error;
};

ProcessKeys& process_keys() {
    static Immortal<ProcessKeys> keys;  // the shim's publisher may use it after static destruction
    return *keys;
}

}  // namespace

void use_process_keys(const std::string& dir, bool insecure) {
    ProcessKeys& k = process_keys();
    std::lock_guard lock(k.mutex);
    k.read = true;
    k.error.clear();
    k.security = Security{};
    if (!load_security(dir, insecure, k.security, k.error)) k.security.dir.clear();
}

const Security& process_security() {
    ProcessKeys& k = process_keys();
    bool read;
    {
        std::lock_guard lock(k.mutex);
        read = k.read;
    }
    if (!read) {
        const Environment& e = environment();  // throws on a bad GLCAST_INSECURE
        std::lock_guard lock(k.mutex);
        if (!k.read) {
            k.read = true;
            if (!load_security(e.keys, e.insecure, k.security, k.error)) k.security.dir.clear();
        }
    }
    if (!k.error.empty()) throw std::runtime_error(k.error);
    return k.security;
}

Transport transport_of(const std::string& endpoint) {
    if (endpoint.rfind("ipc://", 0) == 0 || endpoint.rfind("inproc://", 0) == 0) return Transport::local;
    if (endpoint.rfind("epgm://", 0) == 0 || endpoint.rfind("pgm://", 0) == 0 || endpoint.rfind("norm://", 0) == 0)
        return Transport::multicast;
    if (endpoint.rfind("tcp://", 0) == 0) {
        std::string host = endpoint.substr(6);
        if (const size_t semicolon = host.find(';'); semicolon != std::string::npos) host = host.substr(semicolon + 1);
        const size_t colon = host.rfind(':');
        if (colon != std::string::npos) host = host.substr(0, colon);
        if (host == "localhost" || host == "lo" || host == "[::1]" || host == "::1" || host.rfind("127.", 0) == 0)
            return Transport::loopback;
    }
    return Transport::network;  // any other tcp://, and transports glcast does not know
}

namespace {

// libzmq applies ZMQ_MAXMSGSIZE to CURVE's handshake too (HELLO is 200 bytes, INITIATE 257 and
// the metadata), and a request grows by CURVE's box: a socket that refuses larger frames before
// reading them (the journal's 64 bytes) takes kCurveFrameBytes under CURVE.
constexpr int64_t kCurveFrameBytes = 1024;

void raise_frame_limit(zmq::socket_t& socket) {
    const int64_t limit = socket.get(zmq::sockopt::maxmsgsize);
    if (limit >= 0 && limit < kCurveFrameBytes) socket.set(zmq::sockopt::maxmsgsize, kCurveFrameBytes);
}

}  // namespace

bool check_endpoint(const std::string& endpoint, const Security& s, bool binding) {
    const Transport t = transport_of(endpoint);
    const std::string verb = binding ? "publish on " : "connect to ";
    if (t == Transport::multicast) {
        if (s.insecure) return false;
        throw std::runtime_error("refusing to " + verb + endpoint +
                                 ": multicast cannot be authenticated or encrypted (CURVE needs a connection) and "
                                 "anyone on its network can read it; say --insecure (GLCAST_INSECURE=1) to use it");
    }
    if (t == Transport::local) return false;
    if (s.keyed()) return true;
    if (t == Transport::loopback || s.insecure) return false;
    throw std::runtime_error("refusing to " + verb + endpoint + " without keys: anyone on the network could " +
                             (binding ? "read the program's frames or ask for them" : "pose as the master") +
                             "; give keys (glcast keygen; --keys DIR or GLCAST_KEYS; docs/security.md) or say "
                             "--insecure (GLCAST_INSECURE=1)");
}

void secure_server(zmq::socket_t& socket, const std::string& endpoint, const Security& s) {
    if (!check_endpoint(endpoint, s, true)) {
        socket.set(zmq::sockopt::curve_server, 0);  // options are taken per bind: an ipc:// beside a tcp:// stays plain
        return;
    }
    if (!s.has_master_pair)
        throw std::runtime_error("cannot serve " + endpoint + ": " + s.dir +
                                 "/master.key is missing (only the master's machine serves the wall)");
    socket.set(zmq::sockopt::zap_domain, "glcast");
    socket.set(zmq::sockopt::curve_secretkey, s.master.secret_key);
    socket.set(zmq::sockopt::curve_server, 1);
    raise_frame_limit(socket);
}

void secure_client(zmq::socket_t& socket, const std::string& endpoint, const Security& s) {
    if (!check_endpoint(endpoint, s, false)) return;
    if (!s.has_client_pair)
        throw std::runtime_error("cannot connect to " + endpoint + ": " + s.dir +
                                 " has neither slave.key nor master.key (glcast keygen " + s.dir + "/slave)");
    socket.set(zmq::sockopt::curve_serverkey, s.master_public);
    socket.set(zmq::sockopt::curve_publickey, s.client.public_key);
    socket.set(zmq::sockopt::curve_secretkey, s.client.secret_key);
    raise_frame_limit(socket);
}

Authenticator::Authenticator(zmq::context_t& context, std::set<std::string> authorized, std::string who)
    : authorized_(std::move(authorized)), who_(std::move(who)) {
    socket_ = std::make_unique<zmq::socket_t>(context, zmq::socket_type::rep);
    socket_->set(zmq::sockopt::linger, 0);
    socket_->bind("inproc://zeromq.zap.01");
    thread_ = std::thread([this] {
        pthread_setname_np(pthread_self(), "glcast-zap");  // glcast's own (interceptor/lifetime.h)
        serve();
    });
}

Authenticator::~Authenticator() {
    stopping_ = true;
    if (thread_.joinable()) thread_.join();
}

// RFC 27: version, request id, domain, address, routing id, mechanism, credentials; the reply:
// version, request id, status code, status text, user id, metadata.
void Authenticator::serve() {
    uint64_t said = 0;
    while (!stopping_) {
        zmq::pollitem_t item{socket_->handle(), 0, ZMQ_POLLIN, 0};
        try {
            zmq::poll(&item, 1, std::chrono::milliseconds(100));
        } catch (const zmq::error_t&) {
            return;  // the context is shutting down
        }
        if (!(item.revents & ZMQ_POLLIN)) continue;
        std::vector<zmq::message_t> parts;
        do {
            parts.emplace_back();
            if (!socket_->recv(parts.back())) return;
        } while (socket_->get(zmq::sockopt::rcvmore) && parts.size() < 16);
        while (socket_->get(zmq::sockopt::rcvmore)) {  // more than RFC 27 sends: read and forget
            zmq::message_t rest;
            (void)socket_->recv(rest);
        }
        const std::string id = parts.size() > 1 ? parts[1].to_string() : "";
        const std::string address = parts.size() > 3 ? parts[3].to_string() : "?";
        const std::string mechanism = parts.size() > 5 ? parts[5].to_string() : "";
        bool ok = parts.size() >= 6 && parts[0].to_string() == "1.0";
        std::string key;
        if (ok && mechanism == "CURVE") {
            ok = parts.size() >= 7 && parts[6].size() == 32;
            if (ok) {
                char z85[41];
                zmq_z85_encode(z85, parts[6].data<uint8_t>(), 32);
                key = z85;
                ok = authorized_.count(key) > 0;
            }
        } else if (mechanism != "NULL") {
            ok = false;  // PLAIN, GSSAPI: not ours
        }
        if (!ok) {
            refused_++;
            if (said++ < 8)
                std::fprintf(stderr, "glcast: %s refused %s: %s\n", who_.c_str(), address.c_str(),
                             key.empty() ? ("mechanism " + mechanism).c_str() : ("unknown key " + key).c_str());
        }
        const std::string status = ok ? "200" : "400", text = ok ? "OK" : "unknown key";
        socket_->send(zmq::buffer(std::string("1.0")), zmq::send_flags::sndmore);
        socket_->send(zmq::buffer(id), zmq::send_flags::sndmore);
        socket_->send(zmq::buffer(status), zmq::send_flags::sndmore);
        socket_->send(zmq::buffer(text), zmq::send_flags::sndmore);
        socket_->send(zmq::buffer(key), zmq::send_flags::sndmore);
        socket_->send(zmq::str_buffer(""), zmq::send_flags::none);
    }
}

std::unique_ptr<Authenticator> authenticator_for(zmq::context_t& context, const std::string& who, const Security& s) {
    if (!s.keyed()) return nullptr;
    return std::make_unique<Authenticator>(context, s.authorized, who);
}

}  // namespace glcast::net
