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
    Image out;
    compose_eyes_into(mode, left, right, out);
    return out;
}

void compose_eyes_into(StereoMode mode, const Image& left, const Image& right, Image& out) {
    if (left.width != right.width || left.height != right.height)
        throw std::logic_error("the eyes' images differ in size");
    const int w = left.width, h = left.height;
    const size_t row = size_t(w) * 4, bytes = row * size_t(h);
    switch (mode) {
    case StereoMode::side_by_side:
        out.width = 2 * w, out.height = h;
        out.rgba.resize(2 * bytes);
        for (int y = 0; y < h; ++y) {
            std::memcpy(&out.rgba[y * 2 * row], &left.rgba[y * row], row);
            std::memcpy(&out.rgba[y * 2 * row + row], &right.rgba[y * row], row);
        }
        return;
    case StereoMode::top_bottom:
        out.width = w, out.height = 2 * h;
        out.rgba.resize(2 * bytes);
        std::memcpy(out.rgba.data(), left.rgba.data(), bytes);
        std::memcpy(out.rgba.data() + bytes, right.rgba.data(), bytes);
        return;
    case StereoMode::anaglyph: {  // red-cyan: the left eye's red, the right eye's green and blue
        out.width = w, out.height = h;
        out.rgba.resize(bytes);
        uint8_t* o = out.rgba.data();
        const uint8_t *l = left.rgba.data(), *r = right.rgba.data();
        for (size_t i = 0; i < bytes; i += 4) o[i] = l[i], o[i + 1] = r[i + 1], o[i + 2] = r[i + 2], o[i + 3] = r[i + 3];
        return;
    }
    default:  // quad-buffer (shown as two images), none
        out.width = w, out.height = h;
        out.rgba.assign(left.rgba.begin(), left.rgba.end());
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
    // (the eyes' buffers are swapped with the replayers', not copied)
    left_->on_frame = [this](uint64_t frame, int w, int h, std::vector<uint8_t>& rgba) {
        left_image_.width = w, left_image_.height = h;
        left_image_.rgba.swap(rgba);
        left_frame_ = frame;
    };
    right_->on_frame = [this](uint64_t frame, int w, int h, std::vector<uint8_t>& rgba) {
        if (left_frame_ != frame || left_image_.width != w || left_image_.height != h) return;  // an eye alone
        right_image_.width = w, right_image_.height = h;
        right_image_.rgba.swap(rgba);
        if (before_present) before_present(frame);
        const StereoMode mode = right_->options().stereo;
        if (mode == StereoMode::anaglyph) {  // the left eye's red into the right eye's image: no copy
            uint8_t* r = right_image_.rgba.data();
            const uint8_t* l = left_image_.rgba.data();
            for (size_t i = 0, n = right_image_.rgba.size(); i < n; i += 4) r[i] = l[i];
            if (on_frame) on_frame(frame, right_image_, left_image_, right_image_);
            return;
        }
        if (mode != StereoMode::quad_buffer) compose_eyes_into(mode, left_image_, right_image_, composed_);
        if (on_frame) on_frame(frame, mode == StereoMode::quad_buffer ? left_image_ : composed_, left_image_, right_image_);
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
