#include "slave/stereo.h"

#include <algorithm>
#include <cstring>
#include <stdexcept>

namespace glcast::slave {

void eye_size(StereoMode mode, int width, int height, int& eye_width, int& eye_height) {
    eye_width = mode == StereoMode::side_by_side ? std::max(1, width / 2) : width;
    eye_height = mode == StereoMode::top_bottom ? std::max(1, height / 2) : height;
}

Image compose_eyes(StereoMode mode, const Image& left, const Image& right) {
    if (left.width != right.width || left.height != right.height)
        throw std::logic_error("the eyes' images differ in size");
    const int w = left.width, h = left.height;
    const size_t row = size_t(w) * 4;
    Image out;
    switch (mode) {
    case StereoMode::side_by_side:
        out.width = 2 * w, out.height = h;
        out.rgba.resize(size_t(out.width) * h * 4);
        for (int y = 0; y < h; ++y) {
            std::memcpy(&out.rgba[y * 2 * row], &left.rgba[y * row], row);
            std::memcpy(&out.rgba[y * 2 * row + row], &right.rgba[y * row], row);
        }
        return out;
    case StereoMode::top_bottom:
        out.width = w, out.height = 2 * h;
        out.rgba = left.rgba;
        out.rgba.insert(out.rgba.end(), right.rgba.begin(), right.rgba.end());
        return out;
    case StereoMode::anaglyph:  // red-cyan: the left eye's red, the right eye's green and blue
        out = right;
        for (size_t i = 0; i < out.rgba.size(); i += 4) out.rgba[i] = left.rgba[i];
        return out;
    default:  // quad-buffer (shown as two images), none
        return left;
    }
}

StereoPair::StereoPair(const std::function<std::unique_ptr<Backend>(std::string& error)>& make_backend,
                       const ReplayOptions& options) {
    for (Eye eye : {Eye::left, Eye::right}) {
        ReplayOptions o = options;
        o.viewer.eye = eye;
        o.view.set_eye(eye_position(o.viewer));
        std::unique_ptr<Backend> backend = make_backend(error_);
        if (!backend) return;
        (eye == Eye::left ? left_ : right_) = std::make_unique<Replayer>(std::move(backend), o);
    }
    // The left eye's frame waits for the right's; the right eye's frame shows both.
    left_->on_frame = [this](uint64_t frame, int w, int h, const std::vector<uint8_t>& rgba) {
        left_image_ = Image{w, h, rgba};
        left_frame_ = frame;
    };
    right_->on_frame = [this](uint64_t frame, int w, int h, const std::vector<uint8_t>& rgba) {
        const Image right{w, h, rgba};
        if (left_frame_ != frame || left_image_.width != w || left_image_.height != h) return;  // an eye alone
        if (before_present) before_present(frame);
        if (on_frame) on_frame(frame, compose_eyes(right_->options().stereo, left_image_, right), left_image_, right);
    };
}

StereoPair::~StereoPair() = default;

void StereoPair::replay(MessageSource& source) {
    Message m;
    while (source.next(m) && replay_message(m)) {
    }
}

bool StereoPair::replay_message(const Message& m) {
    left_->resume();
    const bool left_more = left_->replay_message(m);
    right_->resume();
    const bool right_more = right_->replay_message(m);
    return left_more || right_more;
}

bool StereoPair::set_viewer(const Viewer& viewer) {
    Viewer l = viewer, r = viewer;
    l.eye = Eye::left, r.eye = Eye::right;
    const Viewer old_left = left_->options().viewer;
    if (!left_->set_viewer(l)) return false;
    if (!right_->set_viewer(r)) {
        left_->set_viewer(old_left);
        return false;
    }
    return true;
}

void StereoPair::reset() {
    left_->reset();
    right_->reset();
    left_frame_ = UINT64_MAX;
}

void StereoPair::set_frame(uint64_t frame) {
    left_->set_frame(frame);
    right_->set_frame(frame);
}

}  // namespace glcast::slave
