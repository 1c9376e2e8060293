#include "slave/stereo.h"

#include "common/window_readback.h"

#include <algorithm>
#include <cstdio>
#include <cstring>

namespace glcast::slave {

void eye_size(StereoMode mode, int width, int height, int& eye_width, int& eye_height) {
    eye_width = mode == StereoMode::side_by_side ? std::max(1, width / 2) : width;
    eye_height = mode == StereoMode::top_bottom ? std::max(1, height / 2) : height;
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
    for (Replayer* eye : {left_.get(), right_.get()})
        eye->before_frame = [this, eye](uint64_t frame) {
            HeadPose head;
            if (!head_for || !head_for(frame, head)) return;
            if (!eye->move_head(head) && !said_refused_) {
                said_refused_ = true;
                std::fprintf(stderr, "glcast: frame %llu: the head pose puts an eye behind this tile's screen or on "
                                     "it; that eye keeps its last place (said once)\n", (unsigned long long)frame);
            }
        };
    // The left eye's frame waits for the right's; the right eye's frame shows both.
    const StereoMode mode = options.stereo;
    if (mode == StereoMode::side_by_side || mode == StereoMode::top_bottom) {
        // Each eye reads its frame straight into its half of the tile's image (rows bottom to
        // top, as GL gives them); the right eye's frame then flips the whole once.
        auto read_half = [this, mode](Replayer& eye, bool left, int w, int h, GLenum buffer) {
            const bool wide = mode == StereoMode::side_by_side;
            const int tile_w = wide ? 2 * w : w, tile_h = wide ? h : 2 * h;
            halves_.resize(size_t(tile_w) * tile_h * 4);
            // side by side: the left eye at x 0; top and bottom: the left eye on top, which is
            // the upper rows, stored last when rows go bottom to top
            const size_t offset = wide ? (left ? 0 : size_t(w) * 4) : (left ? size_t(w) * h * 4 : 0);
            read_window_rows(eye.api(), buffer, w, h, halves_.data() + offset, tile_w);
            return std::pair<int, int>(tile_w, tile_h);
        };
        left_->on_frame_drawn = [this, read_half](uint64_t frame, int w, int h, GLenum buffer) {
            read_half(*left_, true, w, h, buffer);
            left_frame_ = frame;
            left_image_.width = w, left_image_.height = h;
        };
        right_->on_frame_drawn = [this, read_half](uint64_t frame, int w, int h, GLenum buffer) {
            if (left_frame_ != frame || left_image_.width != w || left_image_.height != h) return;  // an eye alone
            const auto [tile_w, tile_h] = read_half(*right_, false, w, h, buffer);
            if (before_present) before_present(frame);
            composed_.width = tile_w, composed_.height = tile_h;
            composed_.rgba.resize(halves_.size());
            const size_t row = size_t(tile_w) * 4;
            for (int y = 0; y < tile_h; ++y)
                std::memcpy(&composed_.rgba[size_t(y) * row], &halves_[size_t(tile_h - 1 - y) * row], row);
            for (size_t i = 3; i < composed_.rgba.size(); i += 4) composed_.rgba[i] = 255;  // a window shows no alpha
            if (on_frame) on_frame(frame, composed_, Image{}, Image{});
        };
        return;
    }
    if (mode == StereoMode::anaglyph) {
        // Each eye's rows as GL gives them; one pass then flips them and takes the left eye's red
        // and the right eye's green and blue.
        left_->on_frame_drawn = [this](uint64_t frame, int w, int h, GLenum buffer) {
            halves_.resize(size_t(w) * h * 4);
            read_window_rows(left_->api(), buffer, w, h, halves_.data(), w);
            left_frame_ = frame;
            left_image_.width = w, left_image_.height = h;
        };
        right_->on_frame_drawn = [this](uint64_t frame, int w, int h, GLenum buffer) {
            if (left_frame_ != frame || left_image_.width != w || left_image_.height != h) return;  // an eye alone
            right_rows_.resize(size_t(w) * h * 4);
            read_window_rows(right_->api(), buffer, w, h, right_rows_.data(), w);
            if (before_present) before_present(frame);
            composed_.width = w, composed_.height = h;
            composed_.rgba.resize(right_rows_.size());
            const size_t row = size_t(w) * 4;
            for (int y = 0; y < h; ++y) {
                uint8_t* o = &composed_.rgba[size_t(y) * row];
                const uint8_t* l = &halves_[size_t(h - 1 - y) * row];
                const uint8_t* r = &right_rows_[size_t(h - 1 - y) * row];
                for (size_t i = 0; i < row; i += 4) o[i] = l[i], o[i + 1] = r[i + 1], o[i + 2] = r[i + 2], o[i + 3] = 255;
            }
            if (on_frame) on_frame(frame, composed_, Image{}, Image{});
        };
        return;
    }
    // Quad-buffer: both eyes' images as they are (the buffers are swapped with the replayers',
    // not copied).
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
        if (on_frame) on_frame(frame, left_image_, left_image_, right_image_);
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
