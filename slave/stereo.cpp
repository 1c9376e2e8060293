#include "slave/stereo.h"

#include "common/window_readback.h"

#include <algorithm>
#include <condition_variable>
#include <cstdio>
#include <cstring>
#include <exception>
#include <mutex>
#include <thread>
#include <utility>

namespace glcast::slave {

// One job at a time on a thread of its own: the right eye's replays (GL contexts are current on
// one thread, so every call on the right eye's runs here).
class StereoPair::EyeThread {
public:
    EyeThread() : thread_([this] { loop(); }) {}
    ~EyeThread() {
        {
            std::lock_guard<std::mutex> lock(mutex_);
            stop_ = true;
        }
        wake_.notify_all();
        thread_.join();
    }
    void start(std::function<void()> job) {
        {
            std::lock_guard<std::mutex> lock(mutex_);
            job_ = std::move(job);
            done_ = false;
            error_ = nullptr;
        }
        wake_.notify_all();
    }
    void wait() {  // rethrows what the job threw
        std::unique_lock<std::mutex> lock(mutex_);
        finished_.wait(lock, [this] { return done_; });
        if (std::exception_ptr e = std::exchange(error_, nullptr)) std::rethrow_exception(e);
    }
    void run(std::function<void()> job) {
        start(std::move(job));
        wait();
    }

private:
    void loop() {
        for (;;) {
            std::function<void()> job;
            {
                std::unique_lock<std::mutex> lock(mutex_);
                wake_.wait(lock, [this] { return stop_ || job_; });
                if (!job_) return;
                job = std::move(job_);
                job_ = nullptr;
            }
            std::exception_ptr error;
            try {
                job();
            } catch (...) {
                error = std::current_exception();
            }
            {
                std::lock_guard<std::mutex> lock(mutex_);
                error_ = error;
                done_ = true;
            }
            finished_.notify_all();
        }
    }

    std::mutex mutex_;
    std::condition_variable wake_, finished_;
    std::function<void()> job_;
    bool done_ = true, stop_ = false;
    std::exception_ptr error_;
    std::thread thread_;  // (last: it starts once the rest is made)
};

void eye_size(StereoMode mode, int width, int height, int& eye_width, int& eye_height) {
    eye_width = mode == StereoMode::side_by_side ? std::max(1, width / 2) : width;
    eye_height = mode == StereoMode::top_bottom ? std::max(1, height / 2) : height;
}

StereoPair::StereoPair(const std::function<std::unique_ptr<Backend>(std::string& error)>& make_backend,
                       const ReplayOptions& options)
    : mode_(options.stereo) {
    for (Eye eye : {Eye::left, Eye::right}) {
        ReplayOptions o = options;
        o.viewer.eye = eye;
        o.view.set_eye(eye_position(o.viewer));
        std::unique_ptr<Backend> backend = make_backend(error_);
        if (!backend) return;
        (eye == Eye::left ? left_ : right_) = std::make_unique<Replayer>(std::move(backend), o);
    }
    right_thread_ = std::make_unique<EyeThread>();
    for (Replayer* eye : {left_.get(), right_.get()})
        eye->before_frame = [this, eye](uint64_t frame) {
            HeadPose head;
            if (!head_for || !head_for(frame, head)) return;
            if (!eye->move_head(head) && !said_refused_.exchange(true))
                std::fprintf(stderr, "glcast: frame %llu: the head pose puts an eye behind this tile's screen or on "
                                     "it; that eye keeps its last place (said once)\n", (unsigned long long)frame);
        };
    for (int e = 0; e < 2; ++e) {
        Replayer& eye = e == 0 ? *left_ : *right_;
        if (mode_ == StereoMode::quad_buffer) {
            // Both eyes' images as they are (the buffers are swapped with the replayers', not copied).
            eye.on_frame = [this, e](uint64_t frame, int w, int h, std::vector<uint8_t>& rgba) {
                next_slot(e, frame, w, h).pixels.swap(rgba);
            };
        } else {
            // Rows bottom to top, as GL gives them: the composition flips them once.
            eye.on_frame_drawn = [this, e, &eye](uint64_t frame, int w, int h, GLenum buffer) {
                EyeFrame& f = next_slot(e, frame, w, h);
                f.pixels.resize(size_t(w) * h * 4);
                read_window_rows(eye.api(), buffer, w, h, f.pixels.data(), w);
            };
        }
    }
}

StereoPair::~StereoPair() {
    if (!right_thread_) return;
    try {  // the right eye's contexts are released and destroyed on the thread they are current on
        right_thread_->run([this] { right_->reset(); });
    } catch (const std::exception& e) {
        std::fprintf(stderr, "glcast: stereo: the right eye's contexts: %s\n", e.what());
    }
}

// (each eye's thread writes its own queue only; both are read once both eyes are idle)
StereoPair::EyeFrame& StereoPair::next_slot(int eye, uint64_t frame, int width, int height) {
    EyeFrame& f = drawn_[eye].emplace_back();
    f.frame = frame, f.width = width, f.height = height;
    if (!spare_[eye].empty()) {  // (a tile's frames are megabytes: no fresh buffer each frame)
        f.pixels.swap(spare_[eye].back());
        spare_[eye].pop_back();
    }
    return f;
}

void StereoPair::retire(int eye) {
    spare_[eye].push_back(std::move(drawn_[eye].front().pixels));
    drawn_[eye].pop_front();
}

void StereoPair::replay(MessageSource& source) {
    Message m;
    while (source.next(m) && replay_message(m)) {
    }
}

bool StereoPair::replay_message(const Message& m) {
    bool right_more = false, left_more = false;
    right_thread_->start([this, &m, &right_more] {
        right_->resume();
        right_more = right_->replay_message(m);
    });
    std::exception_ptr left_error;
    try {
        left_->resume();
        left_more = left_->replay_message(m);
    } catch (...) {
        left_error = std::current_exception();
    }
    right_thread_->wait();
    if (left_error) std::rethrow_exception(left_error);
    compose_ready();
    return left_more || right_more;
}

// An eye may draw a frame the other does not (the frame's size changed for one): such a frame is
// dropped, as is the other eye's older one.
void StereoPair::compose_ready() {
    std::deque<EyeFrame>& left = drawn_[0];
    std::deque<EyeFrame>& right = drawn_[1];
    while (!left.empty() && !right.empty()) {
        EyeFrame& l = left.front();
        EyeFrame& r = right.front();
        if (l.frame == r.frame && l.width == r.width && l.height == r.height) {
            if (before_present) before_present(l.frame);
            compose(l, r);
            retire(0), retire(1);
        } else {
            retire(l.frame <= r.frame ? 0 : 1);  // an eye alone
        }
    }
}

void StereoPair::compose(EyeFrame& l, EyeFrame& r) {
    const int w = l.width, h = l.height;
    if (mode_ == StereoMode::quad_buffer) {
        left_image_.width = right_image_.width = w;
        left_image_.height = right_image_.height = h;
        left_image_.rgba.swap(l.pixels);
        right_image_.rgba.swap(r.pixels);
        if (on_frame) on_frame(l.frame, left_image_, left_image_, right_image_);
        return;
    }
    const size_t eye_row = size_t(w) * 4;
    if (mode_ == StereoMode::anaglyph) {
        // The left eye's red and the right eye's green and blue.
        composed_.width = w, composed_.height = h;
        composed_.rgba.resize(eye_row * h);
        for (int y = 0; y < h; ++y) {
            uint8_t* o = &composed_.rgba[size_t(y) * eye_row];
            const uint8_t* a = &l.pixels[size_t(h - 1 - y) * eye_row];
            const uint8_t* b = &r.pixels[size_t(h - 1 - y) * eye_row];
            for (size_t i = 0; i < eye_row; i += 4) o[i] = a[i], o[i + 1] = b[i + 1], o[i + 2] = b[i + 2], o[i + 3] = 255;
        }
    } else {
        // Side by side: the left eye in the left half; top and bottom: the left eye on top.
        const bool wide = mode_ == StereoMode::side_by_side;
        composed_.width = wide ? 2 * w : w, composed_.height = wide ? h : 2 * h;
        const size_t row = size_t(composed_.width) * 4;
        composed_.rgba.resize(row * composed_.height);
        for (int y = 0; y < h; ++y) {
            const uint8_t* a = &l.pixels[size_t(h - 1 - y) * eye_row];
            const uint8_t* b = &r.pixels[size_t(h - 1 - y) * eye_row];
            if (wide) {
                std::memcpy(&composed_.rgba[size_t(y) * row], a, eye_row);
                std::memcpy(&composed_.rgba[size_t(y) * row + eye_row], b, eye_row);
            } else {
                std::memcpy(&composed_.rgba[size_t(y) * row], a, eye_row);
                std::memcpy(&composed_.rgba[size_t(y + h) * row], b, eye_row);
            }
        }
        for (size_t i = 3; i < composed_.rgba.size(); i += 4) composed_.rgba[i] = 255;  // a window shows no alpha
    }
    if (on_frame) on_frame(l.frame, composed_, Image{}, Image{});
}

void StereoPair::reset() {
    left_->reset();
    right_thread_->run([this] { right_->reset(); });
    drawn_[0].clear(), drawn_[1].clear();
}

void StereoPair::set_frame(uint64_t frame) {
    left_->set_frame(frame);
    right_thread_->run([this, frame] { right_->set_frame(frame); });
}

}  // namespace glcast::slave
