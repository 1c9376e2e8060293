// Who may talk to whom on a wall (docs/security.md, "Keys"): ZeroMQ's CURVE on every TCP socket
// of the wall, the stream, the journal, the keeper's snapshots and the swap barrier, with the
// master's ZAP handler admitting only the public keys it was given.
//
// The keys of one machine live in one directory, named by GLCAST_KEYS (glcast run and glcast
// slave set it from --keys or the display config's "keys", so the shim, slaves and keepers they
// start find it too):
//
//   master.pub            the master's public key: on every machine of the wall
//   master.key            the master's key pair: on the machine that runs programs
//   slave.key             this display machine's key pair (a master uses master.key instead)
//   authorized/NAME.pub   on the master: the display machines it serves
//   operators/NAME.pub    on the master: who may switch the wall's passes live (glcast ctl);
//                         the master's own key may too
//   operator.key          an operator's key pair, on the machine glcast ctl runs on (else
//                         slave.key or master.key)
//
// `glcast keygen DIR/NAME` writes NAME.key (mode 0600) and NAME.pub. Without keys, a TCP endpoint
// on an address other than loopback is refused unless GLCAST_INSECURE=1 (--insecure); multicast
// (epgm://, pgm://) cannot carry CURVE at all and always needs it.
#pragma once

#include <map>
#include <memory>
#include <set>
#include <stdexcept>
#include <string>
#include <thread>
#include <atomic>

namespace zmq {
class context_t;
class socket_t;
}  // namespace zmq

namespace glcast::net {

struct KeyPair {
    std::string public_key, secret_key;  // Z85, 40 characters each
};

struct Security {
    std::string dir;                  // empty: no keys
    std::string master_public;        // master.pub
    bool has_master_pair = false;     // master.key: this machine can serve
    KeyPair master;                   // valid with has_master_pair
    KeyPair client;                   // slave.key, else master.key: what this machine connects with
    bool has_client_pair = false;
    std::set<std::string> authorized; // authorized/*.pub, operators/*.pub, and the master's own key
    std::set<std::string> operators;  // operators/*.pub, and the master's own key
    std::map<std::string, std::string> machines;  // authorized/NAME.pub: NAME -> its key (a tile of machine NAME speaks with it)
    KeyPair operator_pair;            // operator.key, else the client pair
    bool has_operator_pair = false;
    bool insecure = false;            // GLCAST_INSECURE=1: non-loopback endpoints without keys allowed
    bool keyed() const { return !dir.empty(); }
};

// Reads DIR as above. False with `error` naming the file and what is wrong with it (missing,
// malformed, a secret key readable by others).
bool load_security(const std::string& dir, bool insecure, Security& out, std::string& error);

// This process's keys: those given to use_process_keys, else read once from GLCAST_KEYS and
// GLCAST_INSECURE (common/environment.h). Throws std::runtime_error when the directory cannot be
// read as above. use_process_keys replaces them; it is called before any socket is made (the
// command line's --keys), so the references handed out before stay those of the process's start.
const Security& process_security();
void use_process_keys(const std::string& dir, bool insecure);

// Writes DIR/NAME.key (0600) and DIR/NAME.pub for a new CURVE key pair (`path` is DIR/NAME).
bool write_key_pair(const std::string& path, std::string& error);
// Reads a NAME.pub or NAME.key file; false with `error` naming the file.
bool read_key_file(const std::string& path, bool want_secret, KeyPair& out, std::string& error);

enum class Transport { local, loopback, network, multicast };
// inproc:// and ipc:// are local; tcp:// on 127.x, ::1 or localhost loopback; other tcp:// (and
// tcp://* , tcp://eth0) network; epgm:// and pgm:// multicast.
Transport transport_of(const std::string& endpoint);

// Throws std::runtime_error, naming the endpoint and what to do, unless `endpoint` may be bound
// (binding) or connected to as `s` allows; true: with CURVE. glcast run asks before it starts
// anything, so that a refusal is its error and exit status rather than a program that runs
// unseen.
bool check_endpoint(const std::string& endpoint, const Security& s, bool binding);

// Before a socket binds `endpoint`: with keys and a TCP endpoint, makes it a CURVE server
// (needs this machine's master.key) whose peers the context's Authenticator checks; without keys,
// refuses a network or multicast endpoint unless insecure. Throws std::runtime_error naming the
// endpoint and what to do.
void secure_server(zmq::socket_t& socket, const std::string& endpoint, const Security& s = process_security());
// Before a socket connects to `endpoint`: with keys and TCP, a CURVE client of the master's
// public key; the same refusal without keys.
void secure_client(zmq::socket_t& socket, const std::string& endpoint, const Security& s = process_security());

// ZeroMQ's ZAP handler (RFC 27) for one context: admits a CURVE peer only when its public key is
// in `authorized`. Bound before the context's server sockets, served from a thread of its own.
// Peers over ipc:// or loopback without CURVE (the NULL mechanism) are admitted: they come from
// this machine.
class Authenticator {
public:
    Authenticator(zmq::context_t& context, std::set<std::string> authorized, std::string who);
    ~Authenticator();
    uint64_t refused() const { return refused_; }

private:
    void serve();
    std::set<std::string> authorized_;
    std::string who_;  // "the shim", "the keeper": in the refusal's message
    std::unique_ptr<zmq::socket_t> socket_;
    std::atomic<bool> stopping_{false};
    std::atomic<uint64_t> refused_{0};
    std::thread thread_;
};

// An Authenticator for `context` when this process has keys, else nothing.
std::unique_ptr<Authenticator> authenticator_for(zmq::context_t& context, const std::string& who,
                                                 const Security& s = process_security());

}  // namespace glcast::net
