// A stereo tile (docs/immersive.md): both of the viewer's eyes in one output. Two replayers, one
// per eye, each with its own contexts and its eye's camera, take turns on one thread: every
// message is read (and unpacked) once and replayed by the left eye, then by the right. When both
// eyes have finished a frame, the two images are composed into the tile's one: side by side,
// top and bottom, or as a red-cyan anaglyph, each eye read straight into its place; for
// quad-buffer stereo both go on, as they are, to a window with GL_BACK_LEFT and GL_BACK_RIGHT
// (slave/backends/stereo_window.h).
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <string>

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
    // eye asks it at the start of its own frame: the eyes take turns over a message, so the left
    // eye may start frame N while the right eye still has frame N - 1 to replay.
    std::function<bool(uint64_t frame, HeadPose& out)> head_for;

    void replay(MessageSource& source);  // throws DecodeError on a bad stream
    bool replay_message(const Message& m);
    Replayer& left() { return *left_; }
    Replayer& right() { return *right_; }
    void reset();
    void set_frame(uint64_t frame);

private:
    std::unique_ptr<Replayer> left_, right_;
    std::string error_;
    Image left_image_, right_image_, composed_;  // kept from frame to frame
    std::vector<uint8_t> halves_;      // side by side, top and bottom: both eyes, rows bottom to top
    std::vector<uint8_t> right_rows_;  // an anaglyph's right eye, rows bottom to top (its left: halves_)
    uint64_t left_frame_ = UINT64_MAX;
    bool said_refused_ = false;
};

}  // namespace glcast::slave
