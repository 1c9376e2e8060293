// Object names: the master's names mapped to the slave's, per share group or per context
// (slave/name_map.h), and uniform locations per program.
#include <cstdio>
#include <cstring>

#include "common/gl_headers.h"
#include "slave/replayer.h"

namespace glcast::slave {

uint64_t Replayer::map_name(Ns ns, uint64_t master, const Call& c, NameUse use) {
    SlaveContext& ctx = current();
    if (master == 0) return 0;  // the window framebuffer and default objects are 0 on the slave too
    uint64_t slave = 0;
    NameMap& map = ctx.names.map(ns);
    if (map.find(master, slave)) return slave;
    // Compatibility GL creates some objects at their first bind (and display lists at
    // glNewList) without a glGen* call: semantics.yaml names.
    if (use == NameUse::CreateAtFirstUse && (slave = create_name(*this, ns)) != 0) {
        map.set(master, slave);
        return slave;
    }
    if (use == NameUse::AskAbout) return 0;  // never made on the master either: 0 is no object here
    if (redrawing_)
        throw ReplayError(std::string(c.info ? c.info->name : "?") + ": " + kNamespaces[int(ns)].name + " " +
                          std::to_string(master) + " is no longer an object of the stream");
    // A name the stream never made (or deleted) was no object on the master: its call raised its
    // error there (Mesa's piglit makes such calls on purpose) or did nothing (glCallList). The
    // slave passes a name no object of its driver has (its generators count up from 1), so that
    // the driver answers the same.
    if (!said_name_never_made_) {
        said_name_never_made_ = true;
        std::fprintf(stderr, "glcast replay: frame %llu, call %llu: %s: %s %llu was never made by the stream: passed as "
                             "a name that is no object (said once)\n",
                     (unsigned long long)frame(), (unsigned long long)call_index(), c.info ? c.info->name : "?",
                     kNamespaces[int(ns)].name, (unsigned long long)master);
    }
    return kNoObjectName;
}

const void* Replayer::names_in(Ns ns, const Call& c, int i, NameUse use) {
    const PtrRecord& r = c.args[size_t(i)].ptr;
    if (r.tag != PtrTag::Data) return nullptr;
    auto out = static_cast<GLuint*>(scratch_.take(r.count * sizeof(GLuint)));
    NameMap& map = current().names.map(ns);
    for (uint32_t k = 0; k < r.count; ++k) {
        uint32_t master;
        std::memcpy(&master, r.data + 4 * k, 4);
        uint64_t slave = 0;
        if (master && !map.find(master, slave)) {
            if (use == NameUse::Delete) {  // deleting an unknown name is a no-op in GL too (0: also)
                out[k] = 0;
                continue;
            }
            slave = map_name(ns, master, c, use);
        }
        out[k] = GLuint(slave);
    }
    return out;
}

void Replayer::room_for_names(Ns ns, uint64_t count) {
    const NameMap& map = current().names.map(ns);
    if (map.size() + count > options_.limits.names)
        throw ReplayError(std::to_string(count) + " more names where " + std::to_string(map.size()) +
                          " of their kind live: over the limit names=" + std::to_string(options_.limits.names));
}

void Replayer::map_generated(Ns ns, const Call& c, int i, const void* slave_names) {
    const Arg& a = c.args[size_t(i)];
    if (a.ptr.tag != PtrTag::Reply || !slave_names) return;
    room_for_names(ns, a.reply.count);
    NameMap& map = current().names.map(ns);
    for (uint32_t k = 0; k < a.reply.count; ++k) {
        uint32_t master, slave;
        std::memcpy(&master, a.reply.data + 4 * k, 4);
        std::memcpy(&slave, static_cast<const uint8_t*>(slave_names) + 4 * k, 4);
        map.set(master, slave);
    }
}

void Replayer::map_created(Ns ns, uint64_t master, uint64_t slave) {
    if (!master) return;
    NameMap& map = current().names.map(ns);
    uint64_t existing = 0;
    if (!map.find(master, existing)) room_for_names(ns, 1);
    map.set(master, slave);
}

void Replayer::forget(Ns ns, uint64_t master) {
    // A program deleted while in use keeps its name until it is no longer current (GL 4.6, 7.3):
    // the program may go on asking about it (piglit's copyteximage does).
    if (ns == Ns::program && master && master == current().current_program) {
        current().program_deleted_in_use = master;
        return;
    }
    release_store(current(), ns, master);
    current().names.map(ns).erase(master);
}

void Replayer::used_program(uint64_t master) {
    SlaveContext& ctx = current();
    ctx.current_program = master;
    const uint64_t deleted = ctx.program_deleted_in_use;
    if (!deleted || deleted == master) return;
    ctx.program_deleted_in_use = 0;
    forget(Ns::program, deleted);
}

void Replayer::forget_names(Ns ns, const Call& c, int i) {
    const PtrRecord& r = c.args[size_t(i)].ptr;
    if (r.tag != PtrTag::Data) return;
    NameMap& map = current().names.map(ns);
    for (uint32_t k = 0; k < r.count; ++k) {
        uint32_t master;
        std::memcpy(&master, r.data + 4 * k, 4);
        release_store(current(), ns, master);
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
    api_.glGenTextures(n, names.data());
    api_.glGenBuffers(n, names.data());
    api_.glGenRenderbuffers(n, names.data());
    api_.glGenFramebuffers(n, names.data());
    api_.glGenVertexArrays(n, names.data());
    api_.glGenQueries(n, names.data());
    api_.glGenSamplers(n, names.data());
    api_.glGenLists(n);
    for (int i = 0; i < n; ++i) api_.glCreateProgram();
    // Bound once, so the names are taken whatever the profile says about unbound names.
    for (int i = 0; i < n; ++i) {
        api_.glBindTexture(GL_TEXTURE_2D, names[size_t(i)]);
        api_.glBindBuffer(GL_ARRAY_BUFFER, names[size_t(i)]);
    }
    api_.glBindTexture(GL_TEXTURE_2D, 0);
    api_.glBindBuffer(GL_ARRAY_BUFFER, 0);
}

}  // namespace glcast::slave
