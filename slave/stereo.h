// A stereo tile (docs/immersive.md): both of the viewer's eyes in one output. Two replayers, one
// per eye, each with its own contexts and its eye's camera: every message is read (and unpacked)
// once and replayed by both eyes at once, the left on the caller's thread, the right on a thread
// of its own where its contexts stay current. Each eye reads the frames it draws into frames of
// its own; once both have replayed the message, the frames both drew are composed into the
// tile's one: side by side, top and bottom, or as a red-cyan anaglyph; for quad-buffer stereo
// both go on, as they are, to a window with GL_BACK_LEFT and GL_BACK_RIGHT
// (slave/backends/stereo_window.h).
#pragma once

#include <atomic>
#include <cstdint>
#include <deque>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "common/image.h"
#include "slave/replayer.h"

namespace glcast::slave {

// The size each eye renders at for a tile of width x height: half the width side by side, half
// the height top and bottom, the whole tile otherwise.
void eye_size(StereoMode mode, int width, int height, int& eye_width, int& eye_height);

class StereoPair {
public:
    // `options` are the tile's (options.stereo set, its view and viewer those of the head's
    // centre): each eye gets them with its own eye. False from valid() when a backend could not
    // be made (`error`).
    StereoPair(const std::function<std::unique_ptr<Backend>(std::string& error)>& make_backend, const ReplayOptions& options);
    ~StereoPair();
    bool valid() const { return left_ && right_; }
    const std::string& error() const { return error_; }

    // Both eyes of each frame, once both have it: the composed tile image, and for quad-buffer
    // each eye's (the tile image is then the left eye's); the other modes give empty ones (each
    // eye was read straight into the composition).
    std::function<void(uint64_t frame, const Image& tile, const Image& left, const Image& right)> on_frame;
    // Before each frame is shown, once per frame (the swap barrier waits here).
    std::function<void(uint64_t frame)> before_present;
    // The head pose that holds at a frame (a recorded track, the barrier's GO); false: none. Each
    // eye asks it at the start of its own frame, from its own thread (both may ask at once; it is
    // not changed while a message is replayed).
    std::function<bool(uint64_t frame, HeadPose& out)> head_for;

    void replay(MessageSource& source);  // throws DecodeError on a bad stream
    bool replay_message(const Message& m);
    Replayer& left() { return *left_; }
    Replayer& right() { return *right_; }  // (its contexts are current on the right eye's thread)
    void reset();
    void set_frame(uint64_t frame);

    class EyeThread;  // (stereo.cpp)

private:
    // A frame one eye drew: rows bottom to top as GL reads them, or (quad-buffer) the replayer's
    // image, top to bottom.
    struct EyeFrame {
        uint64_t frame = 0;
        int width = 0, height = 0;
        std::vector<uint8_t> pixels;
    };
    EyeFrame& next_slot(int eye, uint64_t frame, int width, int height);
    void compose_ready();  // the frames both eyes drew, in order
    void compose(EyeFrame& left, EyeFrame& right);
    void retire(int eye);  // its oldest frame: composed or dropped, its buffer kept

    StereoMode mode_ = StereoMode::none;
    std::unique_ptr<Replayer> left_, right_;
    std::unique_ptr<EyeThread> right_thread_;
    std::string error_;
    std::deque<EyeFrame> drawn_[2];         // per eye, not yet composed
    std::vector<std::vector<uint8_t>> spare_[2];  // per eye, buffers of retired frames, reused
    Image composed_, left_image_, right_image_;  // kept from frame to frame
    std::atomic<bool> said_refused_{false};
};

}  // namespace glcast::slave
