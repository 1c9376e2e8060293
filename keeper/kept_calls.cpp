#include "keeper/kept_calls.h"

#include <algorithm>
#include <cstring>

#include "common/gl_headers.h"

#include "protocol/decoder.h"
#include "protocol/format.h"
#include "slave/replayer.h"

namespace glcast::keeper {

// Every tuple: one compiled into a display list can be any call.
bool KeptCalls::wants(uint32_t, const CommandInfo*) const { return true; }

void KeptCalls::before_call(const Call& c, const uint8_t* tuple, size_t bytes) {
    last_tuple_ = tuple;
    last_bytes_ = bytes;
    const CommandInfo* info = c.info;
    if (c.opcode == kSynthContext) {
        SynthContext t;
        read_synthetic(c, t);
        ContextCalls& calls = contexts_[t.id];
        auto create = pending_create_.find(t.handle);
        if (create != pending_create_.end()) {
            calls.create = std::move(create->second);
            pending_create_.erase(create);
        }
        calls.format.clear();
        for (auto* pending : {&pending_format_, &pending_bits_}) {
            auto kept = pending->find(t.handle);
            if (kept == pending->end()) continue;
            calls.format.insert(calls.format.end(), kept->second.begin(), kept->second.end());
            pending->erase(kept);
        }
        calls.context.assign(tuple, tuple + bytes);
        calls.handle = t.handle;
        return;
    }
    if (c.opcode == kSynthContextFormat || c.opcode == kSynthContextBits) {  // kept together, in order
        uint64_t handle = 0;
        if (c.opcode == kSynthContextFormat) {
            SynthContextFormat t;
            read_synthetic(c, t);
            handle = t.handle;
        } else {
            SynthContextBits t;
            read_synthetic(c, t);
            handle = t.handle;
        }
        if (pending_create_.count(handle))
            (c.opcode == kSynthContextFormat ? pending_format_ : pending_bits_)[handle].assign(tuple, tuple + bytes);
        return;
    }
    if (c.opcode == kSynthDrawableSize) {
        SynthDrawableSize t;
        read_synthetic(c, t);
        drawable_sizes_[t.drawable].assign(tuple, tuple + bytes);
        // Drawables are never said to be destroyed: past a few, those no live context is on go
        // (a program that makes a pbuffer a frame would otherwise grow this forever).
        if (drawable_sizes_.size() > kDrawablesKept) {
            for (auto it = drawable_sizes_.begin(); it != drawable_sizes_.end();) {
                bool used = it->first == t.drawable;
                for (const auto& [id, ctx] : core_.contexts()) used = used || ctx->drawable == it->first;
                it = used ? std::next(it) : drawable_sizes_.erase(it);
            }
        }
        return;
    }
    if (info && info->sem.context == ContextOp::Create) {
        // As many wait for their glcast.context tuple as the window system lets wait (limit
        // contexts); it refuses the ones past that.
        const bool room = pending_create_.size() < core_.options().limits.contexts || pending_create_.count(c.ret.bits);
        if (c.ret.bits && room) pending_create_[c.ret.bits].assign(tuple, tuple + bytes);
        return;
    }
    auto rec = recording_.find(c.context);
    if (rec == recording_.end()) return;
    if (info && info->sem.redraw == RedrawKind::EndList) return;  // after_call files the body
    rec->second.body.insert(rec->second.body.end(), tuple, tuple + bytes);
}

LinkedShader read_shader(const GlApi& gl, uint32_t shader) {
    GLint type = 0, length = 0;
    gl.glGetShaderiv(shader, GL_SHADER_TYPE, &type);
    gl.glGetShaderiv(shader, GL_SHADER_SOURCE_LENGTH, &length);
    std::string source(size_t(std::max(length, 1)), '\0');
    gl.glGetShaderSource(shader, GLsizei(source.size()), nullptr, source.data());
    source.resize(std::strlen(source.c_str()));
    return {uint32_t(type), std::move(source)};
}

namespace {

constexpr size_t kMaxRecipeBytes = 4096;  // a stack entry built by more calls is read back instead

// Whether the tuples of a list body change a matrix when the list is called.
bool touches_matrices(const Tuple& body) {
    for (size_t at = 0; at + kTupleHeaderBytes <= body.size();) {
        uint32_t opcode = 0, bytes = 0;
        std::memcpy(&opcode, body.data() + at, 4);
        std::memcpy(&bytes, body.data() + at + 8, 4);
        const CommandInfo* info = command_info(opcode);
        if (info && info->sem.matrix != MatrixOp::Nothing) return true;
        at += kTupleHeaderBytes + bytes;
    }
    return false;
}

}  // namespace

void KeptCalls::follow_matrices(const Call& c, uint32_t context) {
    Matrices& m = matrices_[context];
    const MatrixOp op = c.info->sem.matrix;
    if (op == MatrixOp::Mode) {
        m.mode = uint32_t(c.args[size_t(c.info->sem.subject_params[0])].bits);
        return;
    }
    std::vector<MatrixRecipe>* stack = m.stack();
    if (!stack || stack->empty()) return;
    switch (op) {
    case MatrixOp::Push:
        if (stack->size() < 64) stack->push_back(stack->back());
        break;
    case MatrixOp::Pop:
        if (stack->size() > 1) stack->pop_back();
        break;
    case MatrixOp::Load:
        stack->back() = MatrixRecipe{};
        stack->back().calls.assign(last_tuple_, last_tuple_ + last_bytes_);
        break;
    case MatrixOp::Multiply: {
        MatrixRecipe& r = stack->back();
        if (!r.known) break;
        if (r.calls.size() + last_bytes_ > kMaxRecipeBytes) {
            r = MatrixRecipe{{}, false};
            break;
        }
        r.calls.insert(r.calls.end(), last_tuple_, last_tuple_ + last_bytes_);
        break;
    }
    default: break;
    }
}

void KeptCalls::after_call(const Call& c) {
    const CommandInfo* info = c.info;
    if (!info) return;
    if (info->sem.matrix != MatrixOp::Nothing) {
        slave::SlaveContext* ctx = core_.current_or_null();
        auto rec = ctx ? recording_.find(ctx->id) : recording_.end();
        if (ctx && (rec == recording_.end() || rec->second.execute)) follow_matrices(c, ctx->id);
        return;
    }
    if (info->sem.list == ListOp::Call || info->sem.list == ListOp::CallMany) {
        slave::SlaveContext* ctx = core_.current_or_null();
        if (!ctx) return;
        const auto& touching = list_matrices_[ctx->names.shared];
        bool touches = false;
        if (info->sem.list == ListOp::Call) {
            auto it = touching.find(c.args[size_t(info->sem.subject_params[0])].bits);
            touches = it != touching.end() && it->second;
        } else {
            for (const auto& [name, t] : touching) touches |= t;
        }
        if (touches) {
            Matrices& m = matrices_[ctx->id];
            m.modelview.back() = MatrixRecipe{{}, false};
            m.projection.back() = MatrixRecipe{{}, false};
        }
        return;
    }
    if (info->sem.context == ContextOp::MakeCurrent) {
        slave::SlaveContext* ctx = core_.current_or_null();
        if (ctx && contexts_.count(ctx->id)) contexts_[ctx->id].make_current.assign(last_tuple_, last_tuple_ + last_bytes_);
        return;
    }
    if (info->sem.context == ContextOp::Destroy) {
        for (auto it = contexts_.begin(); it != contexts_.end();)
            it = core_.context(it->first) ? std::next(it) : contexts_.erase(it);
        for (auto it = lists_.begin(); it != lists_.end();)
            it = it->first.use_count() == 1 ? lists_.erase(it) : std::next(it);
        for (auto it = list_matrices_.begin(); it != list_matrices_.end();)
            it = it->first.use_count() == 1 ? list_matrices_.erase(it) : std::next(it);
        for (auto it = matrices_.begin(); it != matrices_.end();)
            it = core_.context(it->first) ? std::next(it) : matrices_.erase(it);
        for (auto it = linked_.begin(); it != linked_.end();)
            it = it->first.use_count() == 1 ? linked_.erase(it) : std::next(it);
        for (auto it = recording_.begin(); it != recording_.end();)
            it = core_.context(it->first) ? std::next(it) : recording_.erase(it);
        return;
    }
    slave::SlaveContext* ctx = core_.current_or_null();
    if (!ctx) return;
    if (info->sem.list == ListOp::New) {
        const int8_t* p = info->sem.subject_params;
        recording_[ctx->id] = Recording{c.args[size_t(p[0])].bits, c.args[size_t(p[1])].bits == GL_COMPILE_AND_EXECUTE, {}};
    } else if (info->sem.redraw == RedrawKind::EndList) {
        auto rec = recording_.find(ctx->id);
        if (rec == recording_.end()) return;
        uint64_t slave_name = 0;
        if (ctx->names.map(Ns::display_list).find(rec->second.list, slave_name)) {
            list_matrices_[ctx->names.shared][rec->second.list] = touches_matrices(rec->second.body);
            lists_[ctx->names.shared][rec->second.list] = std::move(rec->second.body);
        }
        recording_.erase(rec);
    } else if (info->sem.flags & kSemLinksProgram) {
        uint64_t program = 0;
        const uint64_t linked = c.args[size_t(info->sem.subject_params[0])].bits;
        if (!ctx->names.map(Ns::program).find(linked, program)) return;
        const GlApi& gl = core_.api();
        GLint count = 0;
        gl.glGetProgramiv(GLuint(program), GL_ATTACHED_SHADERS, &count);
        std::vector<GLuint> shaders(size_t(std::clamp(count, 0, 64)));
        if (!shaders.empty()) gl.glGetAttachedShaders(GLuint(program), GLsizei(shaders.size()), nullptr, shaders.data());
        std::vector<LinkedShader>& kept = linked_[ctx->names.shared][linked];
        kept.clear();
        for (GLuint s : shaders) kept.push_back(read_shader(gl, s));
    } else if (info->sem.flags & kSemDeletes) {
        uint64_t ignored = 0;
        auto group = lists_.find(ctx->names.shared);
        if (group != lists_.end()) {
            const slave::NameMap& live = ctx->names.map(Ns::display_list);
            for (auto it = group->second.begin(); it != group->second.end();)
                it = live.find(it->first, ignored) ? std::next(it) : group->second.erase(it);
            auto& touching = list_matrices_[ctx->names.shared];
            for (auto it = touching.begin(); it != touching.end();)
                it = live.find(it->first, ignored) ? std::next(it) : touching.erase(it);
        }
        auto programs = linked_.find(ctx->names.shared);
        if (programs != linked_.end()) {
            const slave::NameMap& live = ctx->names.map(Ns::program);
            for (auto it = programs->second.begin(); it != programs->second.end();)
                it = live.find(it->first, ignored) ? std::next(it) : programs->second.erase(it);
        }
    }
}

void KeptCalls::reset() {
    contexts_.clear();
    pending_create_.clear();
    pending_format_.clear();
    pending_bits_.clear();
    drawable_sizes_.clear();
    lists_.clear();
    list_matrices_.clear();
    matrices_.clear();
    linked_.clear();
    recording_.clear();
}

const ListBodies* KeptCalls::lists(const slave::ShareGroup* group) const {
    for (const auto& [g, bodies] : lists_)
        if (g.get() == group) return &bodies;
    return nullptr;
}

const std::vector<LinkedShader>* KeptCalls::linked(const slave::ShareGroup* group, uint64_t program) const {
    for (const auto& [g, programs] : linked_) {
        if (g.get() != group) continue;
        auto it = programs.find(program);
        return it == programs.end() ? nullptr : &it->second;
    }
    return nullptr;
}

const std::vector<MatrixRecipe>* KeptCalls::matrices(uint32_t context, uint32_t mode) const {
    auto it = matrices_.find(context);
    if (it == matrices_.end()) return nullptr;
    return mode == GL_MODELVIEW ? &it->second.modelview : mode == GL_PROJECTION ? &it->second.projection : nullptr;
}

uint64_t KeptCalls::bytes() const {
    uint64_t n = 0;
    for (const auto& [id, c] : contexts_) n += c.create.size() + c.format.size() + c.context.size() + c.make_current.size();
    for (const auto& [d, t] : drawable_sizes_) n += t.size();
    for (const auto& [g, bodies] : lists_)
        for (const auto& [name, body] : bodies) n += body.size();
    for (const auto& [id, r] : recording_) n += r.body.size();
    for (const auto& [id, m] : matrices_)
        for (const auto* stack : {&m.modelview, &m.projection})
            for (const MatrixRecipe& r : *stack) n += r.calls.size();
    for (const auto& [g, programs] : linked_)
        for (const auto& [name, shaders] : programs)
            for (const LinkedShader& s : shaders) n += s.source.size();
    return n;
}

}  // namespace glcast::keeper
