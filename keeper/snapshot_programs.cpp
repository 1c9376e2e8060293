// Shaders and programs: sources, attribute and fragment-output locations, link, uniform block
// bindings and the value of every uniform, with the master's uniform locations told to the slave
// the way the program told them (glGetUniformLocation with the master's answer).
#include <algorithm>
#include <cstring>

#include "glcast_encode.h"
#include "keeper/snapshot_writer.h"

namespace glcast::keeper {

namespace {

enum class UniformKind { Float, Double, Int, Uint, Nothing };
struct UniformShape {
    UniformKind kind = UniformKind::Nothing;
    int components = 0;        // per element; columns * rows for matrices
    int columns = 0, rows = 0; // matrices only
};

UniformShape shape_of(GLenum type) {
    switch (type) {
    case GL_FLOAT: return {UniformKind::Float, 1};
    case GL_FLOAT_VEC2: return {UniformKind::Float, 2};
    case GL_FLOAT_VEC3: return {UniformKind::Float, 3};
    case GL_FLOAT_VEC4: return {UniformKind::Float, 4};
    case GL_DOUBLE: return {UniformKind::Double, 1};
    case GL_DOUBLE_VEC2: return {UniformKind::Double, 2};
    case GL_DOUBLE_VEC3: return {UniformKind::Double, 3};
    case GL_DOUBLE_VEC4: return {UniformKind::Double, 4};
    case GL_INT: case GL_BOOL: return {UniformKind::Int, 1};
    case GL_INT_VEC2: case GL_BOOL_VEC2: return {UniformKind::Int, 2};
    case GL_INT_VEC3: case GL_BOOL_VEC3: return {UniformKind::Int, 3};
    case GL_INT_VEC4: case GL_BOOL_VEC4: return {UniformKind::Int, 4};
    case GL_UNSIGNED_INT: return {UniformKind::Uint, 1};
    case GL_UNSIGNED_INT_VEC2: return {UniformKind::Uint, 2};
    case GL_UNSIGNED_INT_VEC3: return {UniformKind::Uint, 3};
    case GL_UNSIGNED_INT_VEC4: return {UniformKind::Uint, 4};
    case GL_FLOAT_MAT2: return {UniformKind::Float, 4, 2, 2};
    case GL_FLOAT_MAT3: return {UniformKind::Float, 9, 3, 3};
    case GL_FLOAT_MAT4: return {UniformKind::Float, 16, 4, 4};
    case GL_FLOAT_MAT2x3: return {UniformKind::Float, 6, 2, 3};
    case GL_FLOAT_MAT2x4: return {UniformKind::Float, 8, 2, 4};
    case GL_FLOAT_MAT3x2: return {UniformKind::Float, 6, 3, 2};
    case GL_FLOAT_MAT3x4: return {UniformKind::Float, 12, 3, 4};
    case GL_FLOAT_MAT4x2: return {UniformKind::Float, 8, 4, 2};
    case GL_FLOAT_MAT4x3: return {UniformKind::Float, 12, 4, 3};
    default: return {UniformKind::Int, 1};  // samplers and images: a unit
    }
}

bool built_in(const std::string& name) { return name.compare(0, 3, "gl_") == 0; }

}  // namespace

void SnapshotWriter::programs(slave::SlaveContext& ctx) {
    if (!gl_.has(OP_glCreateShader)) return;
    // Shaders first: programs attach them.
    std::vector<std::pair<uint64_t, uint64_t>> programs;
    ctx.names.map(Ns::program).each([&](uint64_t master, uint64_t slave_name) {
        if (gl_.glIsProgram(GLuint(slave_name))) {
            programs.emplace_back(master, slave_name);
            return;
        }
        if (!gl_.glIsShader(GLuint(slave_name))) return;
        GLint compiled = 0;
        gl_.glGetShaderiv(GLuint(slave_name), GL_COMPILE_STATUS, &compiled);
        const LinkedShader shader = read_shader(gl_, GLuint(slave_name));
        const std::string& source = shader.source;
        encode_glCreateShader(e_, sz_, GLenum(shader.type), GLuint(master));
        report_.objects++;
        const char* text = source.c_str();
        const GLint text_length = GLint(source.size());
        if (!source.empty()) encode_glShaderSource(e_, sz_, GLuint(master), 1, &text, &text_length);
        if (compiled) encode_glCompileShader(e_, sz_, GLuint(master));
        flush();
    });
    std::sort(programs.begin(), programs.end());
    for (const auto& [master, slave_name] : programs) program(ctx, GLuint(slave_name), master);
}

void SnapshotWriter::program(slave::SlaveContext& ctx, GLuint slave_name, uint64_t master) {
    encode_glCreateProgram(e_, sz_, GLuint(master));
    report_.objects++;
    GLint attached = 0, linked = 0;
    gl_.glGetProgramiv(slave_name, GL_ATTACHED_SHADERS, &attached);
    gl_.glGetProgramiv(slave_name, GL_LINK_STATUS, &linked);
    std::vector<GLuint> shaders(size_t(std::max(attached, 0)));
    if (attached > 0) gl_.glGetAttachedShaders(slave_name, attached, nullptr, shaders.data());
    // Linked: the shaders it was linked with, whatever is attached now; then what is attached.
    const std::vector<LinkedShader>* kept = linked ? kept_.linked(ctx.names.shared.get(), master) : nullptr;
    std::vector<GLuint> temporary;
    auto make_temporary = [&](GLenum type, const std::string& source) {
        const GLuint m = kTemporaryNameBase + next_temporary_++;
        const char* text = source.c_str();
        const GLint text_length = GLint(source.size());
        encode_glCreateShader(e_, sz_, type, m);
        encode_glShaderSource(e_, sz_, m, 1, &text, &text_length);
        encode_glCompileShader(e_, sz_, m);
        encode_glAttachShader(e_, sz_, GLuint(master), m);
        temporary.push_back(m);
    };
    if (kept) {
        for (const LinkedShader& s : *kept) make_temporary(GLenum(s.type), s.source);
    } else {
        for (GLuint s : shaders) {
            const GLuint m = GLuint(master_name(ctx, Ns::program, s));
            if (m) {
                encode_glAttachShader(e_, sz_, GLuint(master), m);
                continue;
            }
            const LinkedShader deleted = read_shader(gl_, s);  // deleted by the program while attached
            make_temporary(GLenum(deleted.type), deleted.source);
        }
    }
    if (linked) {
        // The locations the linker chose on the keeper, bound before the slave links: the same
        // whatever the slave's linker would choose.
        GLint count = 0, longest = 0;
        gl_.glGetProgramiv(slave_name, GL_ACTIVE_ATTRIBUTES, &count);
        gl_.glGetProgramiv(slave_name, GL_ACTIVE_ATTRIBUTE_MAX_LENGTH, &longest);
        std::vector<char> name(size_t(std::max(longest, 1) + 1));
        for (GLint i = 0; i < count; ++i) {
            GLint size = 0;
            GLenum type = 0;
            gl_.glGetActiveAttrib(slave_name, GLuint(i), GLsizei(name.size()), nullptr, &size, &type, name.data());
            const std::string n = name.data();
            const GLint location = gl_.glGetAttribLocation(slave_name, n.c_str());
            if (location >= 0 && !built_in(n)) encode_glBindAttribLocation(e_, sz_, GLuint(master), GLuint(location), n.c_str());
        }
        if (gl_.has(OP_glGetProgramInterfaceiv) && gl_.has(OP_glBindFragDataLocation)) {
            GLint outputs = 0;
            gl_.glGetProgramInterfaceiv(slave_name, GL_PROGRAM_OUTPUT, GL_ACTIVE_RESOURCES, &outputs);
            if (!asked()) outputs = 0;
            for (GLint i = 0; i < outputs; ++i) {
                char out_name[256] = {};
                gl_.glGetProgramResourceName(slave_name, GL_PROGRAM_OUTPUT, GLuint(i), sizeof out_name, nullptr, out_name);
                const GLint location = gl_.glGetProgramResourceLocation(slave_name, GL_PROGRAM_OUTPUT, out_name);
                if (location >= 0 && !built_in(out_name))
                    encode_glBindFragDataLocation(e_, sz_, GLuint(master), GLuint(location), out_name);
            }
        }
        GLint varyings = 0;
        gl_.glGetProgramiv(slave_name, GL_TRANSFORM_FEEDBACK_VARYINGS, &varyings);
        if (asked() && varyings > 0) missing("program " + std::to_string(master) + ": transform feedback varyings");
        encode_glLinkProgram(e_, sz_, GLuint(master));
        GLint blocks = 0;
        gl_.glGetProgramiv(slave_name, GL_ACTIVE_UNIFORM_BLOCKS, &blocks);
        if (!asked()) blocks = 0;
        for (GLint b = 0; b < blocks; ++b) {
            GLint binding = 0;
            gl_.glGetActiveUniformBlockiv(slave_name, GLuint(b), GL_UNIFORM_BLOCK_BINDING, &binding);
            encode_glUniformBlockBinding(e_, sz_, GLuint(master), GLuint(b), GLuint(binding));
        }
        uniforms(ctx, slave_name, master);
    }
    for (GLuint m : temporary) {
        encode_glDetachShader(e_, sz_, GLuint(master), m);
        encode_glDeleteShader(e_, sz_, m);
    }
    if (kept)
        for (GLuint s : shaders)
            if (const GLuint m = GLuint(master_name(ctx, Ns::program, s))) encode_glAttachShader(e_, sz_, GLuint(master), m);
    flush();
}

void SnapshotWriter::uniforms(slave::SlaveContext& ctx, GLuint slave_name, uint64_t master) {
    // The slave's location -> the master's, as the program learned them.
    std::unordered_map<int32_t, int32_t> master_location;
    bool asked_locations = false;
    auto programs = ctx.names.shared->uniform_locations.find(master);
    if (programs != ctx.names.shared->uniform_locations.end()) {
        asked_locations = true;
        for (const auto& [m, s] : programs->second) master_location[s] = m;
    }
    GLint count = 0, longest = 0;
    gl_.glGetProgramiv(slave_name, GL_ACTIVE_UNIFORMS, &count);
    gl_.glGetProgramiv(slave_name, GL_ACTIVE_UNIFORM_MAX_LENGTH, &longest);
    if (count <= 0) return;
    encode_glUseProgram(e_, sz_, GLuint(master));
    std::vector<char> name(size_t(std::max(longest, 1) + 16));
    for (GLint i = 0; i < count; ++i) {
        GLint size = 0;
        GLenum type = 0;
        gl_.glGetActiveUniform(slave_name, GLuint(i), GLsizei(name.size()), nullptr, &size, &type, name.data());
        std::string base = name.data();
        if (built_in(base)) continue;
        const bool array = base.size() > 3 && base.compare(base.size() - 3, 3, "[0]") == 0;
        if (array) base.resize(base.size() - 3);
        const UniformShape shape = shape_of(type);
        for (GLint k = 0; k < std::max(size, 1); ++k) {
            const std::string element = array ? base + "[" + std::to_string(k) + "]" : base;
            const GLint location = gl_.glGetUniformLocation(slave_name, element.c_str());
            if (location < 0) continue;  // in a uniform block: the buffer holds it
            GLint at = location;
            auto known = master_location.find(location);
            if (known != master_location.end()) {
                at = known->second;
                encode_glGetUniformLocation(e_, sz_, GLuint(master), element.c_str(), at);
            } else if (asked_locations) {
                continue;  // the program never asked for it, so never set it through a location
            }
            float f[16] = {};
            double d[16] = {};
            GLint n[16] = {};
            GLuint u[16] = {};
            const int c = shape.components;
            switch (shape.kind) {
            case UniformKind::Float:
                gl_.glGetUniformfv(slave_name, location, f);
                if (shape.columns == 2 && shape.rows == 2) encode_glUniformMatrix2fv(e_, sz_, at, 1, GL_FALSE, f);
                else if (shape.columns == 3 && shape.rows == 3) encode_glUniformMatrix3fv(e_, sz_, at, 1, GL_FALSE, f);
                else if (shape.columns == 4 && shape.rows == 4) encode_glUniformMatrix4fv(e_, sz_, at, 1, GL_FALSE, f);
                else if (shape.columns == 2 && shape.rows == 3) encode_glUniformMatrix2x3fv(e_, sz_, at, 1, GL_FALSE, f);
                else if (shape.columns == 2 && shape.rows == 4) encode_glUniformMatrix2x4fv(e_, sz_, at, 1, GL_FALSE, f);
                else if (shape.columns == 3 && shape.rows == 2) encode_glUniformMatrix3x2fv(e_, sz_, at, 1, GL_FALSE, f);
                else if (shape.columns == 3 && shape.rows == 4) encode_glUniformMatrix3x4fv(e_, sz_, at, 1, GL_FALSE, f);
                else if (shape.columns == 4 && shape.rows == 2) encode_glUniformMatrix4x2fv(e_, sz_, at, 1, GL_FALSE, f);
                else if (shape.columns == 4 && shape.rows == 3) encode_glUniformMatrix4x3fv(e_, sz_, at, 1, GL_FALSE, f);
                else if (c == 1) encode_glUniform1fv(e_, sz_, at, 1, f);
                else if (c == 2) encode_glUniform2fv(e_, sz_, at, 1, f);
                else if (c == 3) encode_glUniform3fv(e_, sz_, at, 1, f);
                else encode_glUniform4fv(e_, sz_, at, 1, f);
                break;
            case UniformKind::Double:
                gl_.glGetUniformdv(slave_name, location, d);
                if (c == 1) encode_glUniform1dv(e_, sz_, at, 1, d);
                else if (c == 2) encode_glUniform2dv(e_, sz_, at, 1, d);
                else if (c == 3) encode_glUniform3dv(e_, sz_, at, 1, d);
                else encode_glUniform4dv(e_, sz_, at, 1, d);
                break;
            case UniformKind::Int:
                gl_.glGetUniformiv(slave_name, location, n);
                if (c == 1) encode_glUniform1iv(e_, sz_, at, 1, n);
                else if (c == 2) encode_glUniform2iv(e_, sz_, at, 1, n);
                else if (c == 3) encode_glUniform3iv(e_, sz_, at, 1, n);
                else encode_glUniform4iv(e_, sz_, at, 1, n);
                break;
            case UniformKind::Uint:
                gl_.glGetUniformuiv(slave_name, location, u);
                if (c == 1) encode_glUniform1uiv(e_, sz_, at, 1, u);
                else if (c == 2) encode_glUniform2uiv(e_, sz_, at, 1, u);
                else if (c == 3) encode_glUniform3uiv(e_, sz_, at, 1, u);
                else encode_glUniform4uiv(e_, sz_, at, 1, u);
                break;
            case UniformKind::Nothing: break;
            }
        }
    }
}

}  // namespace glcast::keeper
