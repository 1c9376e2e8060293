#include "slave/replayer.h"

#include <algorithm>
#include <cinttypes>
#include <cstdio>

#include "common/gl_headers.h"
#include "slave/effects_frame.h"

namespace glcast::slave {

Replayer::Replayer(std::unique_ptr<Backend> backend, ReplayOptions options)
    : backend_(std::move(backend)), options_(options), procs_(kOpcodeCount, nullptr) {}

Replayer::~Replayer() {
    std::string ignored;
    if (current_) backend_->make_current(0, 0, 0, ignored);
    for (auto& [id, ctx] : contexts_) backend_->destroy_context(id);
}

void* Replayer::proc(uint32_t opcode) {
    void* p = procs_[opcode];
    if (!p) {
        p = backend_->proc_address(command_info(opcode)->name);
        if (!p) throw ReplayError(std::string("the slave's driver has no ") + command_info(opcode)->name);
        procs_[opcode] = p;
    }
    return p;
}

void Replayer::report(const std::string& what) {
    stats_.errors++;
    std::fprintf(stderr, "glcast replay: frame %" PRIu64 ", call %" PRIu64 ": %s\n", frame_, call_index_, what.c_str());
}

SlaveContext& Replayer::current() {
    if (!current_) throw ReplayError("no context is current");
    return *current_;
}

// --- argument helpers ----------------------------------------------------------------

void* Replayer::arena(size_t bytes) {
    if (arena_used_ == arena_.size()) arena_.emplace_back();
    std::vector<uint64_t>& block = arena_[arena_used_++];
    block.assign(bytes / 8 + 2, 0);
    return block.data();
}

static size_t element_bytes(const Call& c, int i) { return wire_bytes(c.info->params[i].wire); }

const void* Replayer::in(const Call& c, int i) {
    const PtrRecord& r = c.args[size_t(i)].ptr;
    switch (r.tag) {
    case PtrTag::Data: {
        const size_t bytes = r.count * element_bytes(c, i);
        void* p = arena(bytes + 1);  // + NUL: text arrays are used as C strings by some calls
        std::memcpy(p, r.data, bytes);
        return p;
    }
    case PtrTag::Offset: return reinterpret_cast<const void*>(uintptr_t(r.value));
    default: return nullptr;
    }
}

void* Replayer::out(const Call& c, int i) {
    const Arg& a = c.args[size_t(i)];
    switch (a.ptr.tag) {
    case PtrTag::Reply: {
        const ArgKind kind = c.info->params[i].kind;
        const size_t bytes = a.reply.count * (kind == ArgKind::OutString ? 1 : element_bytes(c, i));
        return arena(bytes + 4096);  // outputs the master sized by its own state: some slack
    }
    case PtrTag::Offset: return reinterpret_cast<void*>(uintptr_t(a.ptr.value));
    default: return nullptr;
    }
}

const char* Replayer::string(const Call& c, int i) {
    const PtrRecord& r = c.args[size_t(i)].ptr;
    if (r.tag != PtrTag::Data) return nullptr;
    char* p = static_cast<char*>(arena(r.count + 1));
    std::memcpy(p, r.data, r.count);
    p[r.count] = 0;
    return p;
}

const char* const* Replayer::strings(const Call& c, int i) {
    const auto& list = c.args[size_t(i)].strings;
    auto out = static_cast<const char**>(arena(sizeof(char*) * (list.size() + 1)));
    for (size_t k = 0; k < list.size(); ++k) {
        if (list[k].tag != PtrTag::Data) continue;
        char* p = static_cast<char*>(arena(list[k].count + 1));
        std::memcpy(p, list[k].data, list[k].count);
        out[k] = p;
    }
    return out;
}

const void* const* Replayer::index_arrays(const Call& c, int i) {
    const auto& list = c.args[size_t(i)].strings;
    auto out = static_cast<const void**>(arena(sizeof(void*) * (list.size() + 1)));
    for (size_t k = 0; k < list.size(); ++k) {
        if (list[k].tag == PtrTag::Offset) {
            out[k] = reinterpret_cast<const void*>(uintptr_t(list[k].value));
        } else if (list[k].tag == PtrTag::Data) {
            void* p = arena(list[k].count);
            std::memcpy(p, list[k].data, list[k].count);
            out[k] = p;
        }
    }
    return out;
}

const void* Replayer::deferred(const Call& c, int i) {
    const PtrRecord& r = c.args[size_t(i)].ptr;
    // Client memory is set up by the glcast.client_arrays tuple before each draw.
    return r.tag == PtrTag::Offset ? reinterpret_cast<const void*>(uintptr_t(r.value)) : nullptr;
}

// --- names ---------------------------------------------------------------------------

static bool starts_with(const char* s, const char* prefix) { return std::strncmp(s, prefix, std::strlen(prefix)) == 0; }

uint32_t Replayer::auto_create(Ns ns) {
    GLuint n = 0;
    switch (ns) {
    case Ns::texture: gl<decltype(&::glGenTextures)>(OP_glGenTextures)(1, &n); break;
    case Ns::buffer: gl<decltype(&::glGenBuffers)>(OP_glGenBuffers)(1, &n); break;
    case Ns::framebuffer: gl<decltype(&::glGenFramebuffers)>(OP_glGenFramebuffers)(1, &n); break;
    case Ns::renderbuffer: gl<decltype(&::glGenRenderbuffers)>(OP_glGenRenderbuffers)(1, &n); break;
    case Ns::display_list: n = gl<decltype(&::glGenLists)>(OP_glGenLists)(1); break;
    default: break;
    }
    return n;
}

uint64_t Replayer::map_name(Ns ns, uint64_t master, const Call& c) {
    SlaveContext& ctx = current();
    if (master == 0) return 0;  // the window framebuffer and default objects are 0 on the slave too
    uint64_t slave = 0;
    NameMap& map = ctx.names.map(ns);
    if (map.find(master, slave)) return slave;
    // Compatibility GL creates textures, buffers, framebuffers and renderbuffers at their
    // first bind and display lists at glNewList, without a glGen* call.
    const char* name = c.info ? c.info->name : "";
    const bool creates = (starts_with(name, "glBind") && (ns == Ns::texture || ns == Ns::buffer ||
                                                          ns == Ns::framebuffer || ns == Ns::renderbuffer)) ||
                         (ns == Ns::display_list && starts_with(name, "glNewList"));
    if (creates && (slave = auto_create(ns)) != 0) {
        map.set(master, slave);
        return slave;
    }
    throw ReplayError(std::string(name) + ": " + kNamespaces[int(ns)].name + " " + std::to_string(master) +
                      " was never generated");
}

const void* Replayer::names_in(Ns ns, const Call& c, int i) {
    const PtrRecord& r = c.args[size_t(i)].ptr;
    if (r.tag != PtrTag::Data) return nullptr;
    auto out = static_cast<GLuint*>(arena(r.count * sizeof(GLuint)));
    const bool deleting = starts_with(c.info->name, "glDelete");
    NameMap& map = current().names.map(ns);
    for (uint32_t k = 0; k < r.count; ++k) {
        uint32_t master;
        std::memcpy(&master, r.data + 4 * k, 4);
        uint64_t slave = 0;
        if (master && !map.find(master, slave)) {
            if (deleting) continue;  // deleting an unknown name is a no-op in GL too
            slave = map_name(ns, master, c);
        }
        out[k] = GLuint(slave);
    }
    return out;
}

void Replayer::map_generated(Ns ns, const Call& c, int i, const void* slave_names) {
    const Arg& a = c.args[size_t(i)];
    if (a.ptr.tag != PtrTag::Reply || !slave_names) return;
    NameMap& map = current().names.map(ns);
    for (uint32_t k = 0; k < a.reply.count; ++k) {
        uint32_t master, slave;
        std::memcpy(&master, a.reply.data + 4 * k, 4);
        std::memcpy(&slave, static_cast<const uint8_t*>(slave_names) + 4 * k, 4);
        map.set(master, slave);
    }
}

void Replayer::map_created(Ns ns, uint64_t master, uint64_t slave) {
    if (master) current().names.map(ns).set(master, slave);
}

void Replayer::forget(Ns ns, uint64_t master) { current().names.map(ns).erase(master); }

void Replayer::forget_names(Ns ns, const Call& c, int i) {
    const PtrRecord& r = c.args[size_t(i)].ptr;
    if (r.tag != PtrTag::Data) return;
    NameMap& map = current().names.map(ns);
    for (uint32_t k = 0; k < r.count; ++k) {
        uint32_t master;
        std::memcpy(&master, r.data + 4 * k, 4);
        map.erase(master);
    }
}

int32_t Replayer::uniform_location(const Call& c, int i, uint64_t master_program) {
    const int32_t loc = value<int32_t>(c, i);
    if (loc < 0) return loc;
    SlaveContext& ctx = current();
    const uint64_t program = master_program ? master_program : ctx.current_program;
    auto& programs = ctx.names.shared->uniform_locations;
    auto p = programs.find(program);
    if (p == programs.end()) return loc;  // explicit locations: the program never asked
    auto l = p->second.find(loc);
    return l == p->second.end() ? loc : l->second;
}

void Replayer::set_uniform_location(uint64_t master_program, int32_t master, int32_t slave) {
    current().names.shared->uniform_locations[master_program][master] = slave;
}

void Replayer::keep_own_objects(int n) {
    std::vector<GLuint> names(static_cast<size_t>(n));
    gl<decltype(&::glGenTextures)>(OP_glGenTextures)(n, names.data());
    gl<decltype(&::glGenBuffers)>(OP_glGenBuffers)(n, names.data());
    gl<decltype(&::glGenRenderbuffers)>(OP_glGenRenderbuffers)(n, names.data());
    gl<decltype(&::glGenFramebuffers)>(OP_glGenFramebuffers)(n, names.data());
    gl<decltype(&::glGenVertexArrays)>(OP_glGenVertexArrays)(n, names.data());
    gl<decltype(&::glGenQueries)>(OP_glGenQueries)(n, names.data());
    gl<decltype(&::glGenSamplers)>(OP_glGenSamplers)(n, names.data());
    gl<decltype(&::glGenLists)>(OP_glGenLists)(n);
    for (int i = 0; i < n; ++i) gl<decltype(&::glCreateProgram)>(OP_glCreateProgram)();
    // Bound once, so the names are taken whatever the profile says about unbound names.
    for (int i = 0; i < n; ++i) {
        gl<decltype(&::glBindTexture)>(OP_glBindTexture)(GL_TEXTURE_2D, names[size_t(i)]);
        gl<decltype(&::glBindBuffer)>(OP_glBindBuffer)(GL_ARRAY_BUFFER, names[size_t(i)]);
    }
    gl<decltype(&::glBindTexture)>(OP_glBindTexture)(GL_TEXTURE_2D, 0);
    gl<decltype(&::glBindBuffer)>(OP_glBindBuffer)(GL_ARRAY_BUFFER, 0);
}

void Replayer::mismatch(const Call& c, const std::string& what) {
    stats_.mismatches++;
    std::fprintf(stderr, "glcast replay --verify: frame %" PRIu64 ", call %" PRIu64 ": %s: %s\n", frame_, call_index_,
                 c.info->name, what.c_str());
}

void Replayer::check_reply(const Call& c, int i, const void* slave_output) {
    const Arg& a = c.args[size_t(i)];
    if (!checking_ || a.ptr.tag != PtrTag::Reply || !slave_output) return;
    // A headless slave's window framebuffer is single-buffered: these answers describe the
    // slave's window system, not the replay, and are not compared there.
    if (!current().double_buffered && c.info->param_count == 2 && c.info->params[0].kind == ArgKind::Value &&
        std::strncmp(c.info->name, "glGet", 5) == 0) {
        const uint64_t pname = c.args[0].bits;
        if (pname == GL_DOUBLEBUFFER || pname == GL_DRAW_BUFFER || pname == GL_DRAW_BUFFER0 || pname == GL_READ_BUFFER)
            return;
    }
    stats_.verified++;
    const ParamInfo& p = c.info->params[i];
    const size_t bytes = a.reply.count * (p.kind == ArgKind::OutString ? 1 : wire_bytes(p.wire));
    if (std::memcmp(slave_output, a.reply.data, bytes) == 0) return;
    size_t first = 0;
    const auto* s = static_cast<const uint8_t*>(slave_output);
    while (first < bytes && s[first] == a.reply.data[first]) ++first;
    mismatch(c, std::string(p.name) + " differs from the master's reply from byte " + std::to_string(first) + " of " +
                    std::to_string(bytes));
}

void Replayer::check_return(const Call& c, uint64_t slave_value) {
    if (!checking_) return;
    stats_.verified++;
    const uint64_t mask = wire_bytes(c.info->ret.wire) >= 8 ? ~0ull : (1ull << (8 * wire_bytes(c.info->ret.wire))) - 1;
    if ((slave_value & mask) != (c.ret.bits & mask))
        mismatch(c, "returned " + std::to_string(slave_value & mask) + ", the master got " + std::to_string(c.ret.bits & mask));
}

void Replayer::check_return_string(const Call& c, const char* slave_value) {
    if (!checking_) return;
    stats_.verified++;
    const PtrRecord& r = c.ret.ptr;
    const std::string master = r.tag == PtrTag::Data ? std::string(reinterpret_cast<const char*>(r.data), r.count) : "";
    if (master != (slave_value ? slave_value : ""))
        mismatch(c, "returned \"" + std::string(slave_value ? slave_value : "") + "\", the master got \"" + master + "\"");
}

// --- rotated tiles: the projection correction (slave/view_correction.h) ----------------

void Replayer::track_matrix_call(const Call& c) {
    SlaveContext& ctx = current();
    switch (c.opcode) {
    case OP_glMatrixMode: ctx.matrix_mode = uint32_t(c.args[0].bits); return;
    case OP_glPushMatrix:
        if (ctx.matrix_mode == GL_PROJECTION) ctx.projection.push_back(ctx.projection.back());
        return;
    case OP_glPopMatrix:
        if (ctx.matrix_mode == GL_PROJECTION && ctx.projection.size() > 1) ctx.projection.pop_back();
        return;
    default: break;
    }
    if (ctx.matrix_mode != GL_PROJECTION) return;
    auto& top = ctx.projection.back();
    switch (c.opcode) {
    case OP_glLoadIdentity: case OP_glLoadMatrixf: case OP_glLoadMatrixd: case OP_glLoadTransposeMatrixf:
    case OP_glLoadTransposeMatrixd:
        top = SlaveContext::Projection{};  // the program's own matrix again
        break;
    case OP_glMultMatrixf: case OP_glMultMatrixd: case OP_glMultTransposeMatrixf: case OP_glMultTransposeMatrixd:
    case OP_glFrustum: case OP_glOrtho: case OP_glRotatef: case OP_glRotated: case OP_glTranslatef:
    case OP_glTranslated: case OP_glScalef: case OP_glScaled:
        top.dirty = top.corrected;  // M * P_app * X: M must be redone for P_app * X
        break;
    default: break;
    }
}

// Before a draw on the window of a fixed-function program: make GL_PROJECTION hold
// M * P_app for the program's current P_app.
void Replayer::correct_projection() {
    SlaveContext& ctx = current();
    if (redrawing_) {  // an injected pass re-renders the main view: its correction, always
        const glm::dmat4 app = program_projection_now();
        const glm::dmat4 corrected = redraw_correction_ * app;
        gl<decltype(&::glMatrixMode)>(OP_glMatrixMode)(GL_PROJECTION);
        gl<decltype(&::glLoadMatrixd)>(OP_glLoadMatrixd)(&corrected[0][0]);
        gl<decltype(&::glMatrixMode)>(OP_glMatrixMode)(GLenum(ctx.matrix_mode));
        ctx.projection.back() = SlaveContext::Projection{true, false, redraw_correction_};
        return;
    }
    GLint program = 0;
    gl<decltype(&::glGetIntegerv)>(OP_glGetIntegerv)(GL_CURRENT_PROGRAM, &program);
    if (program) {  // a shader program: its patched vertex shader multiplies by glcast_clip
        correct_shader_program(GLuint(program));
        return;
    }
    if (!ctx.drawing_to_window) return;  // the program's own FBOs: untouched
    auto& top = ctx.projection.back();
    if (top.corrected && !top.dirty) return;
    GLdouble current[16];
    gl<decltype(&::glGetDoublev)>(OP_glGetDoublev)(GL_PROJECTION_MATRIX, current);
    glm::dmat4 p;
    std::memcpy(&p[0][0], current, sizeof current);
    const glm::dmat4 app = top.corrected ? glm::inverse(top.m) * p : p;
    const glm::dmat4 m = options_.view.correction(app);
    const glm::dmat4 corrected = m * app;
    GLint mode = GL_MODELVIEW;
    gl<decltype(&::glGetIntegerv)>(OP_glGetIntegerv)(GL_MATRIX_MODE, &mode);
    gl<decltype(&::glMatrixMode)>(OP_glMatrixMode)(GL_PROJECTION);
    gl<decltype(&::glLoadMatrixd)>(OP_glLoadMatrixd)(&corrected[0][0]);
    gl<decltype(&::glMatrixMode)>(OP_glMatrixMode)(GLenum(mode));
    top = SlaveContext::Projection{true, false, m};
}

// Shader programs on rotated tiles: glcast_clip holds M (for the config's program_projection)
// while the window is drawn to, the identity while one of the program's FBOs is.
void Replayer::correct_shader_program(uint32_t program) {
    SlaveContext& ctx = current();
    if (!options_.view.program_fov_y_deg) return;
    auto& cache = ctx.names.shared->clip_uniforms;
    auto it = cache.find(program);
    if (it == cache.end())
        it = cache.emplace(program, std::make_pair(gl<decltype(&::glGetUniformLocation)>(OP_glGetUniformLocation)(
                                                      program, "glcast_clip"), -1)).first;
    const int32_t location = it->second.first;
    const int want = ctx.drawing_to_window ? 1 : 0;
    if (location < 0 || it->second.second == want) return;
    glm::mat4 m(1.0f);
    if (want) {
        const double aspect = ctx.master_height ? double(ctx.master_width) / ctx.master_height : 1.0;
        m = glm::mat4(options_.view.correction(options_.view.program_projection(aspect)));
    }
    gl<decltype(&::glUniformMatrix4fv)>(OP_glUniformMatrix4fv)(location, 1, GL_FALSE, &m[0][0]);
    it->second.second = want;
}

// --- the loop ------------------------------------------------------------------------

void Replayer::reset() {
    std::string ignored;
    if (current_) backend_->make_current(0, 0, 0, ignored);
    current_ = nullptr;
    for (auto& [id, ctx] : contexts_) backend_->destroy_context(id);
    contexts_.clear();
    pending_.clear();
    ids_by_handle_.clear();
    drawable_sizes_.clear();
    std::fill(procs_.begin(), procs_.end(), nullptr);
    frame_ = 0;
    call_index_ = 0;
}

void Replayer::replay(MessageSource& reader) {
    Message m;
    Call c;
    while (frame_ <= options_.last_frame && reader.next(m)) {
        ByteReader r(m.payload.data(), m.payload.size(), 0);
        while (r.remaining() && frame_ <= options_.last_frame) {
            const uint64_t tuple_start = r.offset();
            try {
                decode_tuple(r, c);
            } catch (const DecodeError& e) {
                throw DecodeError(m.offset, "message " + std::to_string(m.header.sequence) + ", payload byte " +
                                                std::to_string(e.offset()) + ": " + e.what());
            }
            arena_used_ = 0;
            try {
                // Recorded before it runs: the scene queries of a draw must not fall inside the
                // glBegin/glEnd block it may open.
                if (options_.effects.any() && current_ && (c.context == current_->id || !c.context)) {
                    tuple_size_ = size_t(r.offset() - tuple_start);
                    tuple_bytes_ = m.payload.data() + tuple_start;
                    record_for_effects(c);
                }
                if (c.opcode >= kSynthBase) {
                    if (c.opcode != kSynthContext) follow_context(c);
                    synthetic(c);
                }
                else dispatch(c);
            } catch (const ReplayError& e) {
                report(e.what());
            }
            call_index_++;
            stats_.calls++;
        }
    }
}

// Tuples name the context their call was made in: the master's threads each have their own
// current context, the slave's one thread switches to it.
void Replayer::follow_context(const Call& c) {
    if (c.context && (!current_ || current_->id != c.context) && contexts_.count(c.context)) {
        SlaveContext& ctx = *contexts_[c.context];
        if (ctx.made_current) make_current(ctx.id, ctx.drawable);
    }
}

void Replayer::dispatch(const Call& c) {
    if (kReplayKind[c.opcode] != ReplayKind::WindowSystem || c.opcode == OP_glXSwapBuffers ||
        c.opcode == OP_eglSwapBuffers)
        follow_context(c);
    switch (kReplayKind[c.opcode]) {
    case ReplayKind::Generated:
    case ReplayKind::Handwritten:
        current();  // a GL call needs a current context
        if (options_.view.enabled) {
            if ((c.info->flags & kDraw) || c.opcode == OP_glBegin || c.opcode == OP_glCallList ||
                c.opcode == OP_glCallLists)
                correct_projection();
        }
        kReplay[c.opcode](*this, c);
        if (options_.view.enabled) track_matrix_call(c);
        if (c.opcode == OP_glCreateShader) current().names.shared->shader_types[c.ret.bits] = uint32_t(c.args[0].bits);
        if (c.opcode == OP_glLinkProgram) current().names.shared->clip_uniforms.clear();  // linking resets uniforms
        stats_.replayed++;
        if (c.opcode == OP_glUseProgram || c.opcode == OP_glUseProgramObjectARB) current().current_program = c.args[0].bits;
        break;
    case ReplayKind::ReplyOnly: {
        stats_.reply_only++;
        // An answer written into a buffer object (glReadPixels into a pixel-pack buffer) is state
        // the slave needs; every other answer is executed only to verify it.
        bool into_buffer = false;
        for (uint16_t i = 0; i < c.info->param_count; ++i)
            into_buffer |= (c.info->params[i].kind == ArgKind::Out) && c.args[i].ptr.tag == PtrTag::Offset;
        if ((options_.verify || into_buffer) && kVerify[c.opcode]) {
            current();
            checking_ = options_.verify;
            kVerify[c.opcode](*this, c);
            checking_ = false;
        }
        break;
    }
    case ReplayKind::WindowSystem: window_system(c); break;
    case ReplayKind::Skip:
    case ReplayKind::Unserializable: break;
    }
}

}  // namespace glcast::slave
