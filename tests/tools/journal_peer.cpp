// A hostile or careless peer of the shim's journal channel, for tests/e2e/journal_guard_test.py:
//
//   journal_peer snapshot ENDPOINT REQUESTS SOCKETS HOLD_S   ask REQUESTS times for the journal
//                                                           over SOCKETS connections, never read
//                                                           the answers, stay connected HOLD_S
//   journal_peer garbage ENDPOINT                           random frames, oversized frames,
//                                                           many-part messages, near-miss forms,
//                                                           a SNAPSHOT flood; raw bytes on tcp://
//   journal_peer done ENDPOINT COUNT                        "DONE n" for COUNT distinct frames
//
// Loopback endpoints only (ipc:// or tcp://127.0.0.1:PORT): the tests never leave the machine.
#include <zmq.h>

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <random>
#include <string>
#include <thread>
#include <vector>

namespace {

void* dealer(void* ctx, const std::string& endpoint, int rcvhwm) {
    void* s = zmq_socket(ctx, ZMQ_DEALER);
    // A small receive mark: libzmq stops reading the connection, so the master's side fills
    // as it would for a peer that is stopped.
    zmq_setsockopt(s, ZMQ_RCVHWM, &rcvhwm, sizeof rcvhwm);
    int hwm = 0;  // never drop what this peer means to send
    zmq_setsockopt(s, ZMQ_SNDHWM, &hwm, sizeof hwm);
    int rcvbuf = 4096;  // and a small kernel buffer: the stall shows sooner
    zmq_setsockopt(s, ZMQ_RCVBUF, &rcvbuf, sizeof rcvbuf);
    if (zmq_connect(s, endpoint.c_str()) != 0) {
        std::fprintf(stderr, "journal_peer: cannot connect to %s: %s\n", endpoint.c_str(), zmq_strerror(zmq_errno()));
        std::exit(2);
    }
    return s;
}

void send(void* s, const std::string& body, int flags = 0) { zmq_send(s, body.data(), body.size(), flags); }

void close_all(std::vector<void*>& sockets, int linger_ms) {
    for (void* s : sockets) {
        zmq_setsockopt(s, ZMQ_LINGER, &linger_ms, sizeof linger_ms);
        zmq_close(s);
    }
    sockets.clear();
}

// Raw bytes on the journal's TCP port: not ZMTP at all.
void raw_tcp(const std::string& endpoint, std::mt19937& rng) {
    const std::string prefix = "tcp://127.0.0.1:";
    if (endpoint.rfind(prefix, 0) != 0) return;
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_port = htons(uint16_t(std::atoi(endpoint.c_str() + prefix.size())));
    a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    for (int i = 0; i < 20; i++) {
        int fd = ::socket(AF_INET, SOCK_STREAM, 0);
        if (::connect(fd, reinterpret_cast<sockaddr*>(&a), sizeof a) == 0) {
            std::vector<unsigned char> junk(1 + rng() % 4096);
            for (auto& c : junk) c = (unsigned char)rng();
            if (i % 2) junk[0] = 0xff;  // a ZMTP signature's first byte, then nonsense
            (void)!::write(fd, junk.data(), junk.size());
        }
        ::close(fd);
    }
}

}  // namespace

int main(int argc, char** argv) {
    if (argc < 3) {
        std::fprintf(stderr, "usage: journal_peer snapshot|garbage|done ENDPOINT ...\n");
        return 2;
    }
    const std::string mode = argv[1], endpoint = argv[2];
    void* ctx = zmq_ctx_new();
    std::vector<void*> sockets;
    if (mode == "snapshot" && argc == 6) {
        const int requests = std::atoi(argv[3]), count = std::atoi(argv[4]), hold = std::atoi(argv[5]);
        for (int i = 0; i < count; i++) sockets.push_back(dealer(ctx, endpoint, 1));
        for (int i = 0; i < requests; i++) send(sockets[i % count], "SNAPSHOT");
        std::printf("sent %d requests on %d connections; not reading for %d s\n", requests, count, hold);
        std::fflush(stdout);
        std::this_thread::sleep_for(std::chrono::seconds(hold));
        close_all(sockets, 0);
    } else if (mode == "garbage") {
        std::mt19937 rng(20240611);
        void* s = dealer(ctx, endpoint, 1000);
        sockets.push_back(s);
        int sent = 0;
        for (int i = 0; i < 5000; i++, sent++) {  // random frames within the size limit
            std::string junk(rng() % 40, '\0');
            for (auto& c : junk) c = char(rng());
            send(s, junk);
        }
        for (const char* near : {"SNAPSHOT ", "snapshot", "SNAPSHOT\n", "DONE", "DONE ", "DONE -1", "DONE 01",
                                 "DONE 99999999999", "DONE 4294967296", "DONE 12x", "DONE  1", "END", "GONE", ""}) {
            send(s, near);
            sent++;
        }
        for (int i = 0; i < 20; i++, sent++) {  // many parts
            for (int p = 0; p < 1000; p++) send(s, "SNAPSHOT", ZMQ_SNDMORE);
            send(s, "SNAPSHOT");
        }
        for (int i = 0; i < 20000; i++, sent++) send(s, "SNAPSHOT");  // a flood from one identity
        for (int i = 0; i < 200; i++) {  // and from many
            void* t = dealer(ctx, endpoint, 1);
            sockets.push_back(t);
            for (int k = 0; k < 10; k++, sent++) send(t, "SNAPSHOT");
        }
        void* big = dealer(ctx, endpoint, 1);  // oversized frames: libzmq hangs up on this peer
        for (int i = 0; i < 10; i++, sent++) send(big, std::string(1 << 20, 'S'));
        sockets.push_back(big);
        raw_tcp(endpoint, rng);
        std::this_thread::sleep_for(std::chrono::seconds(2));
        close_all(sockets, 2000);
        std::printf("sent %d garbage requests\n", sent);
    } else if (mode == "done" && argc == 4) {
        const long count = std::atol(argv[3]);
        void* s = dealer(ctx, endpoint, 1000);
        sockets.push_back(s);
        for (long i = 0; i < count; i++) send(s, "DONE " + std::to_string(1000000 + i));
        close_all(sockets, 30000);
        std::printf("sent %ld DONE reports\n", count);
    } else {
        std::fprintf(stderr, "journal_peer: bad arguments\n");
        return 2;
    }
    zmq_ctx_term(ctx);
    return 0;
}
