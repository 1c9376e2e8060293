// Display lists: glGenLists hands out a range, and glCallLists adds glListBase to every
// entry, so names are mapped entry by entry here rather than by the generated code.
#include "common/gl_headers.h"
#include "slave/call_replay.h"
#include "slave/replay_limits.h"
#include "slave/slave_context.h"

namespace glcast::slave::replay_special {

namespace {

// Each name of a range is one map entry, and glDeleteLists looks each up.
void check_range(CallReplay& r, int64_t range) {
    if (range > 0 && uint64_t(range) > r.limits().list_range)
        throw ReplayError("list range " + std::to_string(range) + " is over the limit list_range=" +
                          std::to_string(r.limits().list_range));
}

}  // namespace

void glGenLists(CallReplay& r, const Call& c) {
    const GLsizei range = r.value<GLsizei>(c, 0);
    check_range(r, range);
    if (range > 0) r.room_for_names(Ns::display_list, uint64_t(range));
    const GLuint slave = r.api().glGenLists(range);
    const uint64_t master = c.ret.bits;
    if (!master || !slave) return;
    for (GLsizei i = 0; i < range; ++i) r.map_created(Ns::display_list, master + uint64_t(i), slave + GLuint(i));
}

void glDeleteLists(CallReplay& r, const Call& c) {
    const uint64_t master = c.args[0].bits;
    const GLsizei range = r.value<GLsizei>(c, 1);
    check_range(r, range);
    NameMap& map = r.current().names.map(Ns::display_list);
    const GlApi& gl = r.api();
    for (GLsizei i = 0; i < range; ++i) {
        uint64_t slave = 0;
        if (map.find(master + uint64_t(i), slave)) {
            gl.glDeleteLists(GLuint(slave), 1);
            map.erase(master + uint64_t(i));
        }
    }
}

void glListBase(CallReplay& r, const Call& c) { r.current().list_base = r.value<GLuint>(c, 0); }

void glCallLists(CallReplay& r, const Call& c) {
    const GLsizei n = r.value<GLsizei>(c, 0);
    const GLenum type = r.value<GLenum>(c, 1);
    const PtrRecord& lists = c.args[2].ptr;
    if (n <= 0 || lists.tag != PtrTag::Data) return;
    // Every name is read from the stream: n may not say more than it holds.
    const int64_t bytes_per = type == GL_2_BYTES || type == GL_SHORT || type == GL_UNSIGNED_SHORT ? 2
                              : type == GL_3_BYTES                                              ? 3
                              : type == GL_BYTE || type == GL_UNSIGNED_BYTE                     ? 1
                                                                                                : 4;
    if (int64_t(n) * bytes_per > int64_t(lists.count))
        throw ReplayError("glCallLists of " + std::to_string(n) + " lists, the stream has " +
                          std::to_string(lists.count / bytes_per));
    SlaveContext& ctx = r.current();
    NameMap& map = ctx.names.map(Ns::display_list);
    std::vector<GLuint> names(static_cast<size_t>(n));
    const uint8_t* p = lists.data;
    const size_t bytes = lists.count;
    for (GLsizei i = 0; i < n; ++i) {
        int64_t v = 0;
        auto take = [&](size_t k) { return size_t(i) * k + k <= bytes; };
        switch (type) {
        case GL_BYTE: if (take(1)) v = int8_t(p[i]); break;
        case GL_UNSIGNED_BYTE: if (take(1)) v = p[i]; break;
        case GL_SHORT: if (take(2)) { int16_t s; std::memcpy(&s, p + 2 * i, 2); v = s; } break;
        case GL_UNSIGNED_SHORT: if (take(2)) { uint16_t s; std::memcpy(&s, p + 2 * i, 2); v = s; } break;
        case GL_INT: if (take(4)) { int32_t s; std::memcpy(&s, p + 4 * i, 4); v = s; } break;
        case GL_UNSIGNED_INT: if (take(4)) { uint32_t s; std::memcpy(&s, p + 4 * i, 4); v = s; } break;
        case GL_FLOAT: if (take(4)) { float s; std::memcpy(&s, p + 4 * i, 4); v = int64_t(s); } break;
        case GL_2_BYTES: if (take(2)) v = p[2 * i] * 256 + p[2 * i + 1]; break;
        case GL_3_BYTES: if (take(3)) v = (p[3 * i] << 16) + (p[3 * i + 1] << 8) + p[3 * i + 2]; break;
        case GL_4_BYTES: if (take(4)) v = (int64_t(p[4 * i]) << 24) + (p[4 * i + 1] << 16) + (p[4 * i + 2] << 8) + p[4 * i + 3]; break;
        default: return;
        }
        uint64_t slave = 0;
        // An undefined list is ignored by GL; 0 is never a list, so the slave ignores it too.
        names[size_t(i)] = map.find(uint64_t(int64_t(ctx.list_base) + v), slave) ? GLuint(slave) : 0;
    }
    r.api().glListBase(0);
    r.api().glCallLists(n, GL_UNSIGNED_INT, names.data());
}

}  // namespace glcast::slave::replay_special
