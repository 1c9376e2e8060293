// The objects of a share group, read back from the keeper's driver and written as the calls
// that make them: buffers, textures (every target, level, face and layer, contents made by
// rendering included), renderbuffers, samplers, shaders and programs with their uniforms, and
// display lists from the tuples that compiled them (keeper/kept_calls.h).
#include <algorithm>
#include <functional>
#include <cstring>

#include "glcast_encode.h"
#include "glcast_snapshot_state.h"
#include "keeper/snapshot_writer.h"

namespace glcast::keeper {

namespace {

constexpr GLenum kTextureTargets[][2] = {
    {GL_TEXTURE_2D, GL_TEXTURE_BINDING_2D},
    {GL_TEXTURE_CUBE_MAP, GL_TEXTURE_BINDING_CUBE_MAP},
    {GL_TEXTURE_3D, GL_TEXTURE_BINDING_3D},
    {GL_TEXTURE_2D_ARRAY, GL_TEXTURE_BINDING_2D_ARRAY},
    {GL_TEXTURE_1D, GL_TEXTURE_BINDING_1D},
    {GL_TEXTURE_1D_ARRAY, GL_TEXTURE_BINDING_1D_ARRAY},
    {GL_TEXTURE_RECTANGLE, GL_TEXTURE_BINDING_RECTANGLE},
    {GL_TEXTURE_CUBE_MAP_ARRAY, GL_TEXTURE_BINDING_CUBE_MAP_ARRAY},
    {GL_TEXTURE_BUFFER, GL_TEXTURE_BINDING_BUFFER},
    {GL_TEXTURE_2D_MULTISAMPLE, GL_TEXTURE_BINDING_2D_MULTISAMPLE},
    {GL_TEXTURE_2D_MULTISAMPLE_ARRAY, GL_TEXTURE_BINDING_2D_MULTISAMPLE_ARRAY},
};

GLenum binding_of(GLenum target) {
    for (const auto& t : kTextureTargets)
        if (t[0] == target) return t[1];
    return 0;
}

int dimensions(GLenum target) {
    switch (target) {
    case GL_TEXTURE_1D: return 1;
    case GL_TEXTURE_3D: case GL_TEXTURE_2D_ARRAY: case GL_TEXTURE_CUBE_MAP_ARRAY: return 3;
    default: return 2;
    }
}

struct Transfer {
    GLenum format = GL_RGBA, type = GL_UNSIGNED_BYTE;
};

// The format and type a texture image is read back in, from what GL says of the image
// (`param`: its glGetTexLevelParameteriv).
Transfer read_back_as(const std::function<GLint(GLenum)>& param) {
    const GLint depth_bits = param(GL_TEXTURE_DEPTH_SIZE);
    const GLint stencil_bits = param(GL_TEXTURE_STENCIL_SIZE);
    GLint component = 0;
    for (GLenum pname : {GL_TEXTURE_RED_TYPE, GL_TEXTURE_ALPHA_TYPE, GL_TEXTURE_LUMINANCE_TYPE,
                         GL_TEXTURE_INTENSITY_TYPE})
        if (!component) component = param(pname);
    const GLint r = param(GL_TEXTURE_RED_SIZE), g = param(GL_TEXTURE_GREEN_SIZE), b = param(GL_TEXTURE_BLUE_SIZE),
                a = param(GL_TEXTURE_ALPHA_SIZE), l = param(GL_TEXTURE_LUMINANCE_SIZE),
                in = param(GL_TEXTURE_INTENSITY_SIZE);
    const GLint bits = std::max({r, g, b, a, l, in});
    // The components the image has, as the program most likely gave them: the driver
    // may choose its storage by the format of the upload (Mesa does), and another
    // storage samples with other roundings.
    const bool integer = component == GL_INT || component == GL_UNSIGNED_INT;
    GLenum components = GL_RGBA;
    if (in) components = GL_RED;
    else if (l) components = a ? GL_LUMINANCE_ALPHA : GL_LUMINANCE;
    else if (r && g && b) components = a ? GL_RGBA : GL_RGB;
    else if (r && g) components = GL_RG;
    else if (r) components = GL_RED;
    else if (a) components = GL_ALPHA;
    if (integer) {
        switch (components) {
        case GL_RGB: components = GL_RGB_INTEGER; break;
        case GL_RG: components = GL_RG_INTEGER; break;
        case GL_RED: components = GL_RED_INTEGER; break;
        case GL_ALPHA: components = GL_ALPHA_INTEGER; break;
        default: components = GL_RGBA_INTEGER; break;
        }
    }
    if (depth_bits) {
        const bool float_depth = param(GL_TEXTURE_DEPTH_TYPE) == GL_FLOAT;
        if (stencil_bits)
            return {GL_DEPTH_STENCIL, GLenum(float_depth ? GL_FLOAT_32_UNSIGNED_INT_24_8_REV : GL_UNSIGNED_INT_24_8)};
        return {GL_DEPTH_COMPONENT, GLenum(float_depth ? GL_FLOAT : GL_UNSIGNED_INT)};
    }
    if (stencil_bits) return {GL_STENCIL_INDEX, GL_UNSIGNED_BYTE};
    if (integer) return {components, GLenum(component)};
    if (component == GL_FLOAT || component == GL_SIGNED_NORMALIZED) return {components, GL_FLOAT};
    return {components, GLenum(bits > 8 ? GL_UNSIGNED_SHORT : GL_UNSIGNED_BYTE)};
}

}  // namespace

void SnapshotWriter::share_group(slave::SlaveContext& ctx) {
    buffers(ctx);
    textures(ctx);
    renderbuffers(ctx);
    samplers(ctx);
    programs(ctx);
    lists(ctx);
    syncs(ctx);
}

// --- buffers -------------------------------------------------------------------------------

void SnapshotWriter::buffers(slave::SlaveContext& ctx) {
    if (!gl_.has(OP_glBindBuffer)) return;
    const GLint was = integer(GL_COPY_READ_BUFFER_BINDING);
    ctx.names.map(Ns::buffer).each([&](uint64_t master, uint64_t slave_name) {
        GLuint name = GLuint(master);
        encode_glGenBuffers(e_, sz_, 1, &name);
        report_.objects++;
        if (!gl_.glIsBuffer(GLuint(slave_name))) return;  // generated, never bound
        gl_.glBindBuffer(GL_COPY_READ_BUFFER, GLuint(slave_name));
        GLint64 size = 0;
        GLint usage = GL_STATIC_DRAW, immutable = GL_FALSE, flags = 0;
        gl_.glGetBufferParameteri64v(GL_COPY_READ_BUFFER, GL_BUFFER_SIZE, &size);
        gl_.glGetBufferParameteriv(GL_COPY_READ_BUFFER, GL_BUFFER_USAGE, &usage);
        if (gl_.has(OP_glBufferStorage)) {
            gl_.glGetBufferParameteriv(GL_COPY_READ_BUFFER, GL_BUFFER_IMMUTABLE_STORAGE, &immutable);
            gl_.glGetBufferParameteriv(GL_COPY_READ_BUFFER, GL_BUFFER_STORAGE_FLAGS, &flags);
        }
        std::vector<uint8_t> data(size_t(std::max<GLint64>(size, 0)));
        if (size > 0) gl_.glGetBufferSubData(GL_COPY_READ_BUFFER, 0, GLsizeiptr(size), data.data());
        encode_glBindBuffer(e_, sz_, GL_COPY_WRITE_BUFFER, GLuint(master));
        if (immutable)
            encode_glBufferStorage(e_, sz_, GL_COPY_WRITE_BUFFER, GLsizeiptr(size), data.data(), GLbitfield(flags));
        else
            encode_glBufferData(e_, sz_, GL_COPY_WRITE_BUFFER, GLsizeiptr(size), data.data(), GLenum(usage));
        flush();
    });
    gl_.glBindBuffer(GL_COPY_READ_BUFFER, GLuint(was));
    encode_glBindBuffer(e_, sz_, GL_COPY_WRITE_BUFFER, 0);
}

// --- textures ------------------------------------------------------------------------------

void SnapshotWriter::textures(slave::SlaveContext& ctx) {
    const GLint unit = integer(GL_ACTIVE_TEXTURE);
    if (gl_.has(OP_glActiveTexture)) {
        gl_.glActiveTexture(GL_TEXTURE0);
        encode_glActiveTexture(e_, sz_, GL_TEXTURE0);
    }
    ctx.names.map(Ns::texture).each([&](uint64_t master, uint64_t slave_name) {
        GLuint name = GLuint(master);
        encode_glGenTextures(e_, sz_, 1, &name);
        report_.objects++;
        if (!gl_.glIsTexture(GLuint(slave_name))) return;  // generated, never bound
        // Its target: the one it binds to without an error (binding to its own target changes nothing).
        GLenum target = 0;
        for (const auto& t : kTextureTargets) {
            GLint was = 0;
            if (!query(t[1], was)) continue;
            gl_.glBindTexture(t[0], GLuint(slave_name));
            const bool fits = asked();
            gl_.glBindTexture(t[0], GLuint(was));
            if (fits) {
                target = t[0];
                break;
            }
        }
        if (!target) {
            missing("texture " + std::to_string(master) + ": its target");
            return;
        }
        texture_targets_[{ctx.names.shared.get(), GLuint(slave_name)}] = target;
        const GLint was = integer(binding_of(target));
        gl_.glBindTexture(target, GLuint(slave_name));
        encode_glBindTexture(e_, sz_, target, GLuint(master));
        texture_images(target, master);
        if (target != GL_TEXTURE_BUFFER) {
            snapshot_texture_parameters_int(gl_, e_, sz_, target, target);
            if (target != GL_TEXTURE_2D_MULTISAMPLE && target != GL_TEXTURE_2D_MULTISAMPLE_ARRAY)
                snapshot_texture_parameters_float(gl_, e_, sz_, target, target);
        }
        gl_.glBindTexture(target, GLuint(was));
        flush();
    });
    if (gl_.has(OP_glActiveTexture)) gl_.glActiveTexture(GLenum(unit));
}

void SnapshotWriter::texture_images(GLenum target, uint64_t master) {
    auto level_value = [&](GLenum face, GLint level, GLenum pname) {
        GLint v = 0;
        gl_.glGetTexLevelParameteriv(face, level, pname, &v);
        return asked() ? v : 0;
    };
    if (target == GL_TEXTURE_BUFFER) {
        const GLint format = level_value(target, 0, GL_TEXTURE_INTERNAL_FORMAT);
        missing("texture " + std::to_string(master) + ": a buffer texture (" + std::to_string(format) + ")");
        return;
    }
    if (target == GL_TEXTURE_2D_MULTISAMPLE || target == GL_TEXTURE_2D_MULTISAMPLE_ARRAY) {
        missing("texture " + std::to_string(master) + ": multisampled contents");
        return;
    }
    GLint immutable = GL_FALSE, immutable_levels = 0;
    gl_.glGetTexParameteriv(target, GL_TEXTURE_IMMUTABLE_FORMAT, &immutable);
    if (!asked()) immutable = GL_FALSE;
    if (immutable) gl_.glGetTexParameteriv(target, GL_TEXTURE_IMMUTABLE_LEVELS, &immutable_levels);
    const bool cube = target == GL_TEXTURE_CUBE_MAP;
    const int dims = dimensions(target);
    const GLenum first_face = cube ? GL_TEXTURE_CUBE_MAP_POSITIVE_X : target;
    if (immutable) {
        const GLint w = level_value(first_face, 0, GL_TEXTURE_WIDTH), h = level_value(first_face, 0, GL_TEXTURE_HEIGHT),
                    d = level_value(first_face, 0, GL_TEXTURE_DEPTH);
        const GLenum internal = GLenum(level_value(first_face, 0, GL_TEXTURE_INTERNAL_FORMAT));
        if (dims == 1) encode_glTexStorage1D(e_, sz_, target, immutable_levels, internal, w);
        else if (dims == 2) encode_glTexStorage2D(e_, sz_, target, immutable_levels, internal, w, h);
        else encode_glTexStorage3D(e_, sz_, target, immutable_levels, internal, w, h, d);
    }
    const int levels = immutable ? immutable_levels : target == GL_TEXTURE_RECTANGLE ? 1 : 16;
    std::vector<uint8_t> pixels;
    for (GLint level = 0; level < levels; ++level) {
        for (int f = 0; f < (cube ? 6 : 1); ++f) {
            const GLenum face = cube ? GLenum(GL_TEXTURE_CUBE_MAP_POSITIVE_X + f) : target;
            const GLint w = level_value(face, level, GL_TEXTURE_WIDTH), h = level_value(face, level, GL_TEXTURE_HEIGHT),
                        d = level_value(face, level, GL_TEXTURE_DEPTH);
            if (w <= 0 || h <= 0 || d <= 0) continue;
            const GLenum internal = GLenum(level_value(face, level, GL_TEXTURE_INTERNAL_FORMAT));
            if (level_value(face, level, GL_TEXTURE_COMPRESSED)) {
                const GLint bytes = level_value(face, level, GL_TEXTURE_COMPRESSED_IMAGE_SIZE);
                pixels.assign(size_t(std::max(bytes, 0)), 0);
                gl_.glGetCompressedTexImage(face, level, pixels.data());
                if (dims == 1 && !immutable)
                    encode_glCompressedTexImage1D(e_, sz_, face, level, internal, w, 0, bytes, pixels.data());
                else if (dims == 1)
                    encode_glCompressedTexSubImage1D(e_, sz_, face, level, 0, w, internal, bytes, pixels.data());
                else if (dims == 2 && !immutable)
                    encode_glCompressedTexImage2D(e_, sz_, face, level, internal, w, h, 0, bytes, pixels.data());
                else if (dims == 2)
                    encode_glCompressedTexSubImage2D(e_, sz_, face, level, 0, 0, w, h, internal, bytes, pixels.data());
                else if (!immutable)
                    encode_glCompressedTexImage3D(e_, sz_, face, level, internal, w, h, d, 0, bytes, pixels.data());
                else
                    encode_glCompressedTexSubImage3D(e_, sz_, face, level, 0, 0, 0, w, h, d, internal, bytes, pixels.data());
                flush();
                continue;
            }
            const Transfer t = read_back_as([&](GLenum pname) { return level_value(face, level, pname); });
            const int64_t bytes = sz_.image(Dir::Out, t.format, t.type, w, h, d);
            if (bytes <= 0) {
                missing("texture " + std::to_string(master) + " level " + std::to_string(level) + ": format " +
                        std::to_string(internal));
                continue;
            }
            pixels.assign(size_t(bytes), 0);
            gl_.glGetTexImage(face, level, t.format, t.type, pixels.data());
            if (!asked()) {
                missing("texture " + std::to_string(master) + " level " + std::to_string(level) + ": its image");
                continue;
            }
            const void* p = pixels.data();
            if (immutable) {
                if (dims == 1) encode_glTexSubImage1D(e_, sz_, face, level, 0, w, t.format, t.type, p);
                else if (dims == 2) encode_glTexSubImage2D(e_, sz_, face, level, 0, 0, w, h, t.format, t.type, p);
                else encode_glTexSubImage3D(e_, sz_, face, level, 0, 0, 0, w, h, d, t.format, t.type, p);
            } else {
                if (dims == 1) encode_glTexImage1D(e_, sz_, face, level, GLint(internal), w, 0, t.format, t.type, p);
                else if (dims == 2) encode_glTexImage2D(e_, sz_, face, level, GLint(internal), w, h, 0, t.format, t.type, p);
                else encode_glTexImage3D(e_, sz_, face, level, GLint(internal), w, h, d, 0, t.format, t.type, p);
            }
            flush();
        }
    }
}

// --- renderbuffers and samplers --------------------------------------------------------------

void SnapshotWriter::renderbuffers(slave::SlaveContext& ctx) {
    if (!gl_.has(OP_glBindRenderbuffer)) return;
    const GLint was = integer(GL_RENDERBUFFER_BINDING);
    ctx.names.map(Ns::renderbuffer).each([&](uint64_t master, uint64_t slave_name) {
        GLuint name = GLuint(master);
        encode_glGenRenderbuffers(e_, sz_, 1, &name);
        report_.objects++;
        if (!gl_.glIsRenderbuffer(GLuint(slave_name))) return;
        gl_.glBindRenderbuffer(GL_RENDERBUFFER, GLuint(slave_name));
        GLint w = 0, h = 0, format = 0, samples = 0;
        gl_.glGetRenderbufferParameteriv(GL_RENDERBUFFER, GL_RENDERBUFFER_WIDTH, &w);
        gl_.glGetRenderbufferParameteriv(GL_RENDERBUFFER, GL_RENDERBUFFER_HEIGHT, &h);
        gl_.glGetRenderbufferParameteriv(GL_RENDERBUFFER, GL_RENDERBUFFER_INTERNAL_FORMAT, &format);
        gl_.glGetRenderbufferParameteriv(GL_RENDERBUFFER, GL_RENDERBUFFER_SAMPLES, &samples);
        encode_glBindRenderbuffer(e_, sz_, GL_RENDERBUFFER, GLuint(master));
        if (w > 0 && h > 0) {
            if (samples) encode_glRenderbufferStorageMultisample(e_, sz_, GL_RENDERBUFFER, samples, GLenum(format), w, h);
            else encode_glRenderbufferStorage(e_, sz_, GL_RENDERBUFFER, GLenum(format), w, h);
            if (samples) missing("renderbuffer " + std::to_string(master) + ": multisampled contents");
            else renderbuffer_contents(GLuint(slave_name), GLuint(master), GLenum(format), w, h);
        }
    });
    gl_.glBindRenderbuffer(GL_RENDERBUFFER, GLuint(was));
}

namespace {

// How a renderbuffer's pixels travel exactly: the attachment point, the blit mask, and the
// format and type that read them back and upload them again without rounding.
struct RenderbufferPixels {
    GLenum attachment, mask, format, type;
    size_t bytes_per_pixel;
};

bool integer_color(GLenum internal) {
    switch (internal) {
    case GL_R8I: case GL_R8UI: case GL_R16I: case GL_R16UI: case GL_R32I: case GL_R32UI:
    case GL_RG8I: case GL_RG8UI: case GL_RG16I: case GL_RG16UI: case GL_RG32I: case GL_RG32UI:
    case GL_RGB8I: case GL_RGB8UI: case GL_RGB16I: case GL_RGB16UI: case GL_RGB32I: case GL_RGB32UI:
    case GL_RGBA8I: case GL_RGBA8UI: case GL_RGBA16I: case GL_RGBA16UI: case GL_RGBA32I: case GL_RGBA32UI:
    case GL_RGB10_A2UI: return true;
    default: return false;
    }
}

}  // namespace

// A renderbuffer's contents (drawn into by the program, or blitted): read back through a
// framebuffer of the keeper's own, and written as a texture of the same format blitted into the
// renderbuffer, both temporary, so a slave gets what the program drew without drawing it again.
void SnapshotWriter::renderbuffer_contents(GLuint slave_name, GLuint master, GLenum internal, GLint w, GLint h) {
    if (!gl_.has(OP_glBlitFramebuffer) || !gl_.has(OP_glFramebufferRenderbuffer)) {
        missing("renderbuffer " + std::to_string(master) + ": its contents");
        return;
    }
    GLint depth = 0, stencil = 0, red = 0, green = 0, blue = 0, alpha = 0;
    gl_.glGetRenderbufferParameteriv(GL_RENDERBUFFER, GL_RENDERBUFFER_DEPTH_SIZE, &depth);
    gl_.glGetRenderbufferParameteriv(GL_RENDERBUFFER, GL_RENDERBUFFER_STENCIL_SIZE, &stencil);
    gl_.glGetRenderbufferParameteriv(GL_RENDERBUFFER, GL_RENDERBUFFER_RED_SIZE, &red);
    gl_.glGetRenderbufferParameteriv(GL_RENDERBUFFER, GL_RENDERBUFFER_GREEN_SIZE, &green);
    gl_.glGetRenderbufferParameteriv(GL_RENDERBUFFER, GL_RENDERBUFFER_BLUE_SIZE, &blue);
    gl_.glGetRenderbufferParameteriv(GL_RENDERBUFFER, GL_RENDERBUFFER_ALPHA_SIZE, &alpha);
    const bool float_depth = internal == GL_DEPTH_COMPONENT32F || internal == GL_DEPTH32F_STENCIL8;
    RenderbufferPixels p{};
    if (depth && stencil)
        p = float_depth ? RenderbufferPixels{GL_DEPTH_STENCIL_ATTACHMENT, GL_DEPTH_BUFFER_BIT | GL_STENCIL_BUFFER_BIT,
                                             GL_DEPTH_STENCIL, GL_FLOAT_32_UNSIGNED_INT_24_8_REV, 8}
                        : RenderbufferPixels{GL_DEPTH_STENCIL_ATTACHMENT, GL_DEPTH_BUFFER_BIT | GL_STENCIL_BUFFER_BIT,
                                             GL_DEPTH_STENCIL, GL_UNSIGNED_INT_24_8, 4};
    else if (depth)
        p = {GL_DEPTH_ATTACHMENT, GL_DEPTH_BUFFER_BIT, GL_DEPTH_COMPONENT, float_depth ? GLenum(GL_FLOAT) : GLenum(GL_UNSIGNED_INT), 4};
    else if (stencil)
        p = {GL_STENCIL_ATTACHMENT, GL_STENCIL_BUFFER_BIT, GL_STENCIL_INDEX, GL_UNSIGNED_BYTE, 1};
    else if (integer_color(internal))
        p = {GL_COLOR_ATTACHMENT0, GL_COLOR_BUFFER_BIT, GL_RGBA_INTEGER, GL_UNSIGNED_INT, 16};
    else if (std::max({red, green, blue, alpha}) <= 8)
        p = {GL_COLOR_ATTACHMENT0, GL_COLOR_BUFFER_BIT, GL_RGBA, GL_UNSIGNED_BYTE, 4};
    else
        p = {GL_COLOR_ATTACHMENT0, GL_COLOR_BUFFER_BIT, GL_RGBA, GL_FLOAT, 16};

    const GLint read_was = integer(GL_READ_FRAMEBUFFER_BINDING);
    GLuint reader = 0;
    gl_.glGenFramebuffers(1, &reader);
    gl_.glBindFramebuffer(GL_READ_FRAMEBUFFER, reader);
    gl_.glFramebufferRenderbuffer(GL_READ_FRAMEBUFFER, p.attachment, GL_RENDERBUFFER, slave_name);
    std::vector<uint8_t> pixels(size_t(w) * size_t(h) * p.bytes_per_pixel);
    const bool complete = gl_.glCheckFramebufferStatus(GL_READ_FRAMEBUFFER) == GL_FRAMEBUFFER_COMPLETE;
    if (complete) gl_.glReadPixels(0, 0, w, h, p.format, p.type, pixels.data());
    const bool read = complete && asked();
    gl_.glBindFramebuffer(GL_READ_FRAMEBUFFER, GLuint(read_was));
    gl_.glDeleteFramebuffers(1, &reader);
    if (!read) {
        missing("renderbuffer " + std::to_string(master) + ": its contents (format " + std::to_string(internal) + ")");
        return;
    }
    GLuint texture = kTemporaryNameBase + next_temporary_++;
    GLuint from = kTemporaryNameBase + next_temporary_++, to = kTemporaryNameBase + next_temporary_++;
    encode_glGenTextures(e_, sz_, 1, &texture);
    encode_glBindTexture(e_, sz_, GL_TEXTURE_2D, texture);
    encode_glTexImage2D(e_, sz_, GL_TEXTURE_2D, 0, GLint(internal), w, h, 0, p.format, p.type, pixels.data());
    encode_glGenFramebuffers(e_, sz_, 1, &from);
    encode_glGenFramebuffers(e_, sz_, 1, &to);
    encode_glBindFramebuffer(e_, sz_, GL_READ_FRAMEBUFFER, from);
    encode_glFramebufferTexture2D(e_, sz_, GL_READ_FRAMEBUFFER, p.attachment, GL_TEXTURE_2D, texture, 0);
    encode_glBindFramebuffer(e_, sz_, GL_DRAW_FRAMEBUFFER, to);
    encode_glFramebufferRenderbuffer(e_, sz_, GL_DRAW_FRAMEBUFFER, p.attachment, GL_RENDERBUFFER, master);
    encode_glBlitFramebuffer(e_, sz_, 0, 0, w, h, 0, 0, w, h, p.mask, GL_NEAREST);
    encode_glBindFramebuffer(e_, sz_, GL_READ_FRAMEBUFFER, 0);
    encode_glBindFramebuffer(e_, sz_, GL_DRAW_FRAMEBUFFER, 0);
    GLuint framebuffers[2] = {from, to};
    encode_glDeleteFramebuffers(e_, sz_, 2, framebuffers);
    encode_glBindTexture(e_, sz_, GL_TEXTURE_2D, 0);
    encode_glDeleteTextures(e_, sz_, 1, &texture);
    flush();
}

void SnapshotWriter::samplers(slave::SlaveContext& ctx) {
    ctx.names.map(Ns::sampler).each([&](uint64_t master, uint64_t slave_name) {
        GLuint name = GLuint(master);
        encode_glGenSamplers(e_, sz_, 1, &name);
        report_.objects++;
        if (!gl_.glIsSampler(GLuint(slave_name))) return;
        snapshot_sampler_parameters_int(gl_, e_, sz_, GLuint(slave_name), GLuint(master));
        snapshot_sampler_parameters_float(gl_, e_, sz_, GLuint(slave_name), GLuint(master));
    });
}

// --- display lists ----------------------------------------------------------------------------

void SnapshotWriter::lists(slave::SlaveContext& ctx) {
    const ListBodies* bodies = kept_.lists(ctx.names.shared.get());
    ctx.names.map(Ns::display_list).each([&](uint64_t master, uint64_t) {
        encode_glGenLists(e_, sz_, 1, GLuint(master));
        report_.lists++;
        auto body = bodies ? bodies->find(master) : ListBodies::const_iterator();
        if (!bodies || body == bodies->end()) return;  // generated, never compiled
        encode_glNewList(e_, sz_, GLuint(master), GL_COMPILE);
        raw(body->second, ctx.id);
        encode_glEndList(e_, sz_);
        flush();
    });
}

// --- syncs ------------------------------------------------------------------------------------

// A fence the program has not deleted yet: later calls wait on it, ask it or delete it, and the
// master's answers travel with them, so a fence made at the snapshot (signalled as soon as the
// snapshot's own commands complete) is all a slave can observe of it.
void SnapshotWriter::syncs(slave::SlaveContext& ctx) {
    if (!gl_.has(OP_glFenceSync)) return;
    ctx.names.map(Ns::sync).each([&](uint64_t master, uint64_t) {
        encode_glFenceSync(e_, sz_, GL_SYNC_GPU_COMMANDS_COMPLETE, 0, reinterpret_cast<GLsync>(uintptr_t(master)));
        report_.objects++;
    });
}

}  // namespace glcast::keeper
