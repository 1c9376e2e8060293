#include "slave/replayer.h"

#include <algorithm>
#include <cinttypes>
#include <cstdio>

#include "common/gl_headers.h"
#include "common/window_readback.h"
#include "slave/effects_runner.h"
#include "slave/replay_sizes.h"
#include "slave/tile_adapter.h"
#include "slave/verifier.h"
#include "slave/window_system.h"

namespace glcast::slave {

void* Replayer::resolve(void* self, uint32_t opcode) {
    return static_cast<Replayer*>(self)->backend_->proc_address(command_info(opcode)->name);
}

Replayer::Replayer(std::unique_ptr<Backend> backend, ReplayOptions options)
    : backend_(std::move(backend)), options_(options), api_(&Replayer::resolve, this),
      scratch_(options_.limits.arena_retain_bytes),
      interest_(kOpcodeCount, 0), synth_interest_(kSynthCount, 0) {
    sizes_ = std::make_unique<ReplaySizeQueries>(api_);
    window_system_ = std::make_unique<WindowSystem>(*this);
    tile_ = std::make_unique<TileAdapter>(*this);
    add_observer(window_system_.get());
    add_observer(tile_.get());
    if (options_.effects.followed()) {
        effects_ = std::make_unique<EffectsRunner>(*this, *tile_);
        add_observer(effects_.get());
    }
    if (options_.projector && options_.projector->any()) {  // after the passes: the last step
        projector_ = std::make_unique<ProjectorWarp>(*this, options_.projector);
        add_observer(projector_.get());
    }
    if (options_.verify) {
        verifier_ = std::make_unique<Verifier>(*this);
        add_observer(verifier_.get());
    }
}

Replayer::~Replayer() {
    std::string ignored;
    if (current_) backend_->make_current(0, 0, 0, ignored);
    for (auto& [id, ctx] : contexts_) backend_->destroy_context(id);
}

void Replayer::set_effects(const effects::EffectsSettings& settings) {
    if (!effects_) throw std::logic_error("passes switched on a replay that does not follow the scene (effects.live)");
    const bool live = options_.effects.live;
    options_.effects = settings;
    options_.effects.live = live;
    effects_->settings_changed();
}

bool Replayer::read_shown(Image& out) {
    SlaveContext* ctx = current_or_null();
    if (!ctx || ctx->width <= 0 || ctx->height <= 0) return false;
    read_window_into(api_, ctx->double_buffered ? GL_BACK : GL_FRONT, ctx->width, ctx->height, out.rgba, frame_scratch_);
    out.width = ctx->width, out.height = ctx->height;
    return true;
}

void Replayer::add_observer(ReplayObserver* o) {
    if (observers_.size() >= kMaxObservers)
        throw std::logic_error("a replay takes at most " + std::to_string(kMaxObservers) +
                               " observers (an opcode's interest is a mask of that many bits)");
    const uint8_t bit = uint8_t(1u << observers_.size());
    observers_.push_back(o);
    if (o->adapts_redraws()) redraw_observers_ |= bit;
    for (uint32_t op = 0; op < kOpcodeCount; ++op)
        if (o->wants(op, command_info(op))) interest_[op] |= bit;
    for (uint32_t k = 0; k < kSynthCount; ++k)
        if (o->wants(kSynthBase + k, nullptr)) synth_interest_[k] |= bit;
}

void* Replayer::proc(uint32_t opcode) {
    void* p = api_.proc(opcode);
    if (!p) throw ReplayError(std::string("the slave's driver has no ") + command_info(opcode)->name);
    return p;
}

ShaderPatch Replayer::shader_patch(uint64_t master_shader) { return tile_->shader_patch(master_shader); }

void Replayer::report(const std::string& what) {
    stats_.errors++;
    std::fprintf(stderr, "glcast replay: frame %" PRIu64 ", call %" PRIu64 ": %s\n", frame_, call_index_, what.c_str());
}

SlaveContext& Replayer::current() {
    if (!current_) throw ReplayError("no context is current");
    return *current_;
}

// --- contexts --------------------------------------------------------------------------

SlaveContext* Replayer::context(uint32_t id) {
    auto it = contexts_.find(id);
    return it == contexts_.end() ? nullptr : it->second.get();
}

SlaveContext& Replayer::add_context(uint32_t id, uint64_t handle, uint32_t share_id, const ContextRequest& request) {
    if (share_id && !contexts_.count(share_id))
        throw ReplayError("context " + std::to_string(id) + " shares with context " + std::to_string(share_id) +
                          ", which does not exist");
    if (contexts_.size() >= options_.limits.contexts && !contexts_.count(id))
        throw ReplayError("context " + std::to_string(id) + " would be one more than the limit contexts=" +
                          std::to_string(options_.limits.contexts));
    std::string error;
    if (!backend_->create_context(id, share_id, request, error)) throw ReplayError(error);
    auto ctx = std::make_unique<SlaveContext>();
    ctx->id = id;
    ctx->handle = handle;
    ctx->names.shared = share_id ? contexts_[share_id]->names.shared : std::make_shared<ShareGroup>();
    SlaveContext& added = *ctx;
    contexts_[id] = std::move(ctx);
    return added;
}

void Replayer::remove_context(uint32_t id) {
    std::string ignored;
    if (current_ && current_->id == id) {
        backend_->make_current(0, 0, 0, ignored);
        current_ = nullptr;
    }
    backend_->destroy_context(id);
    contexts_.erase(id);
    for (ReplayObserver* o : observers_) o->context_removed(id);
}

void Replayer::make_current(uint32_t id, uint64_t drawable, int width, int height) {
    std::string error;
    if (id == 0) {
        backend_->make_current(0, 0, 0, error);
        current_ = nullptr;
        return;
    }
    SlaveContext* ctx = context(id);
    if (!ctx) throw ReplayError("make-current of context " + std::to_string(id) + ", which does not exist");
    ctx->drawable = drawable;
    if (!backend_->make_current(id, width, height, error)) throw ReplayError(error);
    current_ = ctx;
    ctx->width = width;
    ctx->height = height;
    const bool first = !ctx->made_current;
    if (first) {
        ctx->made_current = true;
        ctx->es_version = gles_version(reinterpret_cast<const char*>(api_.glGetString(GL_VERSION)));
        GLboolean db = GL_TRUE;  // an ES window surface draws to its back buffer, and cannot say so
        if (!ctx->es_version) api_.glGetBooleanv(GL_DOUBLEBUFFER, &db);
        ctx->double_buffered = db;
    }
    sizes_->set_es_version(ctx->es_version);
    for (ReplayObserver* o : observers_) o->made_current(*ctx, first);
    if (!first_context_done_) {
        first_context_done_ = true;
        if (on_first_context) on_first_context(*this);
    }
}

void Replayer::finish_frame() {
    SlaveContext& ctx = current();
    for (ReplayObserver* o : observers_) o->end_frame(ctx);
    const GLenum shown = ctx.double_buffered ? GL_BACK : GL_FRONT;
    if (frame_ >= options_.first_frame && frame_ <= options_.last_frame && ctx.width > 0 && ctx.height > 0) {
        if (on_frame_drawn) {
            on_frame_drawn(frame_, ctx.width, ctx.height, shown);
        } else if (on_frame) {
            read_window_into(api_, shown, ctx.width, ctx.height, frame_rgba_, frame_scratch_);
            on_frame(frame_, ctx.width, ctx.height, frame_rgba_);
        }
    }
    if (before_present) before_present(frame_);
    backend_->present();
    if (after_present) after_present(frame_);
    for (ReplayObserver* o : observers_) o->presented(ctx);
    frame_++;
    stats_.frames++;
}

// --- the loop ------------------------------------------------------------------------

void Replayer::reset() {
    for (ReplayObserver* o : observers_) o->reset();
    std::string ignored;
    if (current_) backend_->make_current(0, 0, 0, ignored);
    current_ = nullptr;
    for (auto& [id, ctx] : contexts_) backend_->destroy_context(id);
    contexts_.clear();
    api_.forget();
    frame_ = 0;
    call_index_ = 0;
    frame_begun_ = UINT64_MAX;
}

bool Replayer::set_viewer(const Viewer& viewer) {
    if (!options_.view.set_eye(eye_position(viewer))) return false;
    options_.viewer = viewer;
    tile_->view_changed();
    return true;
}

bool Replayer::move_head(const HeadPose& head) {
    const Viewer moved = with_head(options_.viewer, head);
    if (moved.head.position == options_.viewer.head.position && moved.head.orientation == options_.viewer.head.orientation &&
        moved.eye_separation == options_.viewer.eye_separation)
        return true;
    return set_viewer(moved);
}

void Replayer::replay(MessageSource& reader) {
    Message m;
    while (frame_ <= options_.last_frame && reader.next(m)) replay_message(m);
}

bool Replayer::replay_message(const Message& m) {
    Call c;
    DecodeLimits decode_limits;
    decode_limits.list_entries = uint32_t(std::min<uint64_t>(options_.limits.list_entries, UINT32_MAX));
    ByteReader r(m.payload.data(), m.payload.size(), 0);
    while (r.remaining() && frame_ <= options_.last_frame) {
        const uint64_t tuple_start = r.offset();
        try {
            decode_tuple(r, c, decode_limits);
        } catch (const DecodeError& e) {
            throw DecodeError(m.offset, "message " + std::to_string(m.header.sequence) + ", payload byte " +
                                            std::to_string(e.offset()) + ": " + e.what());
        }
        if (frame_ != frame_begun_) {
            frame_begun_ = frame_;
            if (before_frame) before_frame(frame_);
        }
        try {
            dispatch(c, m.payload.data() + tuple_start, size_t(r.offset() - tuple_start));
        } catch (const ReplayError& e) {
            const char* name = c.info ? c.info->name : synthetic_name(c.opcode);
            report(std::string(name ? name : "?") + ": " + e.what());
        } catch (const GlMissing& e) {
            report(std::string("the slave's ") + e.what());  // "driver has no glX"
        }
        scratch_.end_call();
        call_index_++;
        stats_.calls++;
    }
    return frame_ <= options_.last_frame;
}

void Replayer::resume() {
    if (!current_) return;
    std::string error;
    if (!backend_->make_current(current_->id, current_->width, current_->height, error))
        throw std::runtime_error("cannot make the context current again: " + error);
}

// Tuples name the context their call was made in: the master's threads each have their own
// current context, the slave's one thread switches to it.
void Replayer::follow_context(const Call& c) {
    if (!c.context || (current_ && current_->id == c.context)) return;
    SlaveContext* ctx = context(c.context);
    if (ctx && ctx->made_current) window_system_->switch_to(*ctx);
}

void Replayer::dispatch(const Call& c, const uint8_t* tuple, size_t bytes) {
    const bool synthetic_tuple = c.opcode >= kSynthBase;
    const uint8_t mask = synthetic_tuple ? synth_interest_[c.opcode - kSynthBase] : interest_[c.opcode];
    // Window-system calls name contexts themselves; only a swap acts on the calling thread's.
    const bool follows = synthetic_tuple ? c.opcode != kSynthContext
                                         : kReplayKind[c.opcode] != ReplayKind::WindowSystem ||
                                               c.info->sem.context == ContextOp::Swap;
    if (follows) follow_context(c);
    observe(c, tuple, bytes, mask, [this, &c] { run_default(c); });
}

template <class Run>
void Replayer::observe(const Call& c, const uint8_t* tuple, size_t bytes, uint8_t mask, Run&& run) {
    if (!mask) {
        run();
        return;
    }
    for (size_t i = 0; i < observers_.size(); ++i)
        if (mask & (1u << i)) observers_[i]->before_call(c, tuple, bytes);
    bool replaced = false;
    for (size_t i = 0; i < observers_.size() && !replaced; ++i)
        if (mask & (1u << i)) replaced = observers_[i]->replace_call(c);
    if (!replaced) run();
    for (size_t i = 0; i < observers_.size(); ++i)
        if (mask & (1u << i)) observers_[i]->after_call(c);
}

void Replayer::redispatch(const Call& c) {
    scratch_.end_call();
    if (c.opcode >= kSynthBase) {
        synthetic(c);
        return;
    }
    if (!kReplay[c.opcode]) return;  // recorded inside glBegin/glEnd, but not repeated by a slave
    // (every call, whatever they asked for: a redraw changes what a call means to them)
    // A name the frame deleted since is refused here (the redraw skips the call), not given to
    // the driver as no object: the error would be left for the program's next glGetError.
    redrawing_ = true;
    struct Done {
        bool& flag;
        ~Done() { flag = false; }
    } done{redrawing_};
    observe(c, nullptr, 0, redraw_observers_, [this, &c] {
        kReplay[c.opcode](*this, c);
        if (c.info->sem.program_use >= 0) current().current_program = c.args[size_t(c.info->sem.program_use)].bits;
    });
}

void Replayer::run_default(const Call& c) {
    if (c.opcode >= kSynthBase) {
        synthetic(c);
        return;
    }
    switch (kReplayKind[c.opcode]) {
    case ReplayKind::Generated:
    case ReplayKind::Handwritten:
        current();  // a GL call needs a current context
        kReplay[c.opcode](*this, c);
        stats_.replayed++;
        if (c.info->sem.program_use >= 0) used_program(c.args[size_t(c.info->sem.program_use)].bits);
        break;
    case ReplayKind::ReplyOnly: {
        stats_.reply_only++;
        // An answer written into a buffer object (glReadPixels into a pixel-pack buffer) is state
        // the slave needs; every other answer is only compared, by the Verifier.
        // Whether the offset may be one, and lies in a bound buffer, is Replayer::out's check.
        bool into_buffer = false;
        for (uint16_t i = 0; i < c.info->param_count; ++i)
            into_buffer |= (c.info->params[i].kind == ArgKind::Out || c.info->params[i].kind == ArgKind::OutString) &&
                           c.args[i].ptr.tag == PtrTag::Offset;
        if (into_buffer && !kVerify[c.opcode])
            throw ReplayError("the call's output is a buffer offset, which the slave cannot repeat");
        if (into_buffer) {
            current();
            kVerify[c.opcode](*this, c);
        }
        break;
    }
    case ReplayKind::WindowSystem:  // the WindowSystem follows those it needs
    case ReplayKind::Skip:
    case ReplayKind::Unserializable: break;
    }
}

// --- synthetic tuples the core handles (the WindowSystem takes contexts and drawables) ----

void Replayer::synthetic(const Call& c) {
    switch (c.opcode) {
    case kSynthClientArrays: client_arrays(c); break;
    case kSynthBufferWrite: buffer_write(c); break;
    case kSynthUnserialized: {
        SynthUnserialized t;
        read_synthetic(c, t);
        const uint32_t op = t.command;
        stats_.unserialized++;
        if (unserialized_seen_[op]++ == 0 && command_info(op))
            std::fprintf(stderr, "glcast replay: the master could not serialize %s: this frame may differ\n",
                         command_info(op)->name);
        break;
    }
    default:
        break;
    }
}

void Replayer::check_reply(const Call& c, int i, const void* slave_output, int64_t slave_elements) {
    if (verifier_) verifier_->check_reply(c, i, slave_output, slave_elements);
}
void Replayer::check_return(const Call& c, uint64_t slave_value) {
    if (verifier_) verifier_->check_return(c, slave_value);
}
void Replayer::check_return_string(const Call& c, const char* slave_value) {
    if (verifier_) verifier_->check_return_string(c, slave_value);
}

}  // namespace glcast::slave
