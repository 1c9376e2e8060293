#include "slave/program_camera.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstring>
#include <regex>
#include <sstream>

namespace glcast::slave {

namespace {

glm::dvec4 row(const glm::dmat4& m, int r) { return {m[0][r], m[1][r], m[2][r], m[3][r]}; }
glm::dvec3 xyz(const glm::dvec4& v) { return {v.x, v.y, v.z}; }
constexpr double kTolerance = 1e-4;  // relative: float uniforms carry about 7 digits

}  // namespace

bool split_perspective(const glm::dmat4& m, glm::dmat4& projection, glm::dmat4& view) {
    // With V's rows v0..v3 (v3 = (0, 0, 0, 1)) and P = [a 0 b 0; 0 c d 0; 0 0 e f; 0 0 -1 0]:
    // row 3 of m is -v2, row 0 is a v0 + b v2, row 1 is c v1 + d v2, row 2 is e v2 + f v3.
    const glm::dvec4 r0 = row(m, 0), r1 = row(m, 1), r2 = row(m, 2), r3 = row(m, 3);
    const glm::dvec4 v2 = -r3;
    const double s2 = glm::dot(xyz(v2), xyz(v2));
    if (!(s2 > 1e-12) || !std::isfinite(s2)) return false;
    const double b = glm::dot(xyz(r0), xyz(v2)) / s2, d = glm::dot(xyz(r1), xyz(v2)) / s2;
    const double e = glm::dot(xyz(r2), xyz(v2)) / s2;
    const glm::dvec4 a_v0 = r0 - b * v2, c_v1 = r1 - d * v2;
    const double s = std::sqrt(s2), a = glm::length(xyz(a_v0)) / s, c = glm::length(xyz(c_v1)) / s;
    if (!(a > 1e-9) || !(c > 1e-9)) return false;
    const glm::dvec4 v0 = a_v0 / a, v1 = c_v1 / c;
    // Row 2 must be e v2 plus a constant, and v0, v1, v2 orthogonal with one length.
    const glm::dvec3 rest = xyz(r2) - e * xyz(v2);
    const double scale = std::max({std::abs(e) * s, glm::length(xyz(r2)), 1e-12});
    if (glm::length(rest) > kTolerance * scale) return false;
    if (std::abs(glm::dot(xyz(v0), xyz(v1))) > kTolerance * s2 || std::abs(glm::dot(xyz(v0), xyz(v2))) > kTolerance * s2 ||
        std::abs(glm::dot(xyz(v1), xyz(v2))) > kTolerance * s2)
        return false;
    const double f = r2.w - e * v2.w;
    glm::dmat4 p(0.0);
    p[0][0] = a, p[2][0] = b, p[1][1] = c, p[2][1] = d, p[2][2] = e, p[3][2] = f, p[2][3] = -1;
    glm::dmat4 v(1.0);
    for (int col = 0; col < 4; ++col) v[col][0] = v0[col], v[col][1] = v1[col], v[col][2] = v2[col];
    v[0][3] = v[1][3] = v[2][3] = 0, v[3][3] = 1;
    if (!(f != 0) || !std::isfinite(f)) return false;
    if (glm::determinant(glm::dmat3(v)) <= 0) {
        // A left-handed eye space (w = +z, Irrlicht's): V's third row and P's third column change
        // sign, and P keeps w = +z, as such a program's own projection does (view_correction.h).
        for (int col = 0; col < 4; ++col) v[col][2] = -v[col][2];
        p[2][0] = -b, p[2][1] = -d, p[2][2] = -e, p[2][3] = 1;
    }
    projection = p;
    view = v;
    return true;
}

bool is_rigid(const glm::dmat4& m) {
    if (m[0][3] != 0 || m[1][3] != 0 || m[2][3] != 0 || m[3][3] != 1) return false;
    const glm::dvec3 x(m[0]), y(m[1]), z(m[2]);
    const double s2 = glm::dot(x, x);
    if (!(s2 > 1e-12)) return false;
    return std::abs(glm::dot(y, y) - s2) <= kTolerance * s2 && std::abs(glm::dot(z, z) - s2) <= kTolerance * s2 &&
           std::abs(glm::dot(x, y)) <= kTolerance * s2 && std::abs(glm::dot(x, z)) <= kTolerance * s2 &&
           std::abs(glm::dot(y, z)) <= kTolerance * s2;
}

namespace {

bool has(const std::string& name, const char* word) { return name.find(word) != std::string::npos; }

// gl_LightSource[i]...: i, else -1
int light_source_index(const char* name) {
    constexpr char kPrefix[] = "gl_LightSource[";
    if (std::strncmp(name, kPrefix, sizeof kPrefix - 1) != 0) return -1;
    const char* digits = name + sizeof kPrefix - 1;
    return std::isdigit(static_cast<unsigned char>(*digits)) && digits[1] == ']' ? *digits - '0' : -1;
}

// An element after the first of an array of structures in a uniform block, which the driver lists
// one by one ("objects[7].model"): per-object data, never the camera. (An array of matrices is
// listed once, by its first element, whose value is all this class reads of it.)
bool past_first_element(const char* name) {
    for (const char* at = std::strchr(name, '['); at; at = std::strchr(at + 1, '['))
        if (at[1] != '0' || at[2] != ']') return true;
    return false;
}

constexpr GLint kMostActiveUniforms = 1 << 16;
// The matrices (and light vectors) kept per program: each is read from its buffer at every draw
// that looks for a camera, so their number, not the uniforms looked at, bounds that draw's cost.
constexpr size_t kMostKept = 1024;

}  // namespace

LightUniform light_uniform(const std::string& original) {
    std::string name = original;
    std::transform(name.begin(), name.end(), name.begin(), [](unsigned char ch) { return std::tolower(ch); });
    LightUniform u;
    const bool direction = has(name, "dir"), position = has(name, "pos");
    if (!has(name, "sun") && !(has(name, "light") && (direction || position))) return u;
    for (const char* other : {"col", "intens", "ambient", "diffuse", "specular", "power", "strength", "energy",
                              "scatter", "size", "radius", "angle", "atten", "matrix", "mvp", "count", "cone"})
        if (has(name, other)) return u;
    u.light = true;
    u.position = position && !direction;
    u.eye_space = has(name, "view") || has(name, "eye") || has(name, "camera") || has(name, "vc");  // (VTK: "VC")
    return u;
}

const ProgramCameras::Uniforms& ProgramCameras::uniforms(uint32_t program) {
    auto it = uniforms_.find(program);
    if (it != uniforms_.end()) return it->second;
    Uniforms& out = uniforms_[program];
    GLint count = 0;
    gl_.glGetProgramiv(program, GL_ACTIVE_UNIFORMS, &count);
    // (every one the driver lists: Blender's programs list 1,024 per-object matrices of a block
    // before the one that holds the view; the driver's own limits bound the count, kMostKept
    // what is kept of them)
    for (GLuint i = 0; i < GLuint(std::clamp(count, 0, kMostActiveUniforms)); ++i) {
        char name[256] = {};
        GLint size = 0;
        GLenum type = 0;
        gl_.glGetActiveUniform(program, i, sizeof name, nullptr, &size, &type, name);
        if (past_first_element(name)) continue;
        const bool builtin = std::strncmp(name, "gl_", 3) == 0;
        if (builtin && (std::strncmp(name, "gl_ModelView", 12) == 0 || std::strncmp(name, "gl_Projection", 13) == 0))
            out.fixed_function = true;
        if (const int light = light_source_index(name); light >= 0 && out.fixed_function_light < 0)
            out.fixed_function_light = light;
        if (builtin || std::strncmp(name, "glcast_", 7) == 0) continue;
        Uniform u;
        u.name = name;
        if (type == GL_FLOAT_MAT4) {
            u.columns = 4, u.components = 4;
        } else if (type == GL_FLOAT_VEC3 || type == GL_FLOAT_VEC4) {
            u.meaning = light_uniform(u.name);
            if (!u.meaning.light) continue;
            u.columns = 1, u.components = type == GL_FLOAT_VEC3 ? 3 : 4;
        } else {
            continue;
        }
        if ((u.columns == 4 ? out.matrices : out.lights).size() >= kMostKept) continue;
        GLint block = -1, offset = 0, stride = 0, row_major = 0;
        if (gl_.has(OP_glGetActiveUniformsiv)) {
            gl_.glGetActiveUniformsiv(program, 1, &i, GL_UNIFORM_BLOCK_INDEX, &block);
            gl_.glGetActiveUniformsiv(program, 1, &i, GL_UNIFORM_OFFSET, &offset);
            gl_.glGetActiveUniformsiv(program, 1, &i, GL_UNIFORM_MATRIX_STRIDE, &stride);
            gl_.glGetActiveUniformsiv(program, 1, &i, GL_UNIFORM_IS_ROW_MAJOR, &row_major);
        }
        // (a light in a block no stage reads may be bound to another block's buffer: SuperTuxKart
        // leaves its geometry programs' LightingData at binding 0, its camera's)
        if (block >= 0 && !read(program, u.name, /*by_vertex_stages=*/u.columns == 4)) continue;
        if (block >= 0) {
            u.block = uint32_t(block), u.offset = uint32_t(std::max(offset, 0)), u.stride = uint32_t(std::max(stride, 16));
            u.row_major = row_major != 0 && u.columns == 4;
        } else {
            u.location = gl_.glGetUniformLocation(program, name);
            if (u.location < 0) continue;
        }
        (u.columns == 4 ? out.matrices : out.lights).push_back(std::move(u));
    }
    return out;
}

// out: column-major, `u.columns` columns of 4 (a vector's missing components 0)
bool ProgramCameras::value(uint32_t program, const Uniform& u, float f[16]) {
    std::fill(f, f + 16, 0.0f);
    if (u.location >= 0) {
        gl_.glGetUniformfv(program, u.location, f);
    } else {
        if (!gl_.has(OP_glGetNamedBufferSubData) || !gl_.has(OP_glGetIntegeri_v)) return false;
        GLint binding = 0, buffer = 0;
        GLint64 start = 0, bound_size = 0;
        gl_.glGetActiveUniformBlockiv(program, u.block, GL_UNIFORM_BLOCK_BINDING, &binding);
        gl_.glGetIntegeri_v(GL_UNIFORM_BUFFER_BINDING, GLuint(binding), &buffer);
        if (!buffer) return false;
        gl_.glGetInteger64i_v(GL_UNIFORM_BUFFER_START, GLuint(binding), &start);
        gl_.glGetInteger64i_v(GL_UNIFORM_BUFFER_SIZE, GLuint(binding), &bound_size);
        GLint64 buffer_size = 0;
        gl_.glGetNamedBufferParameteri64v(GLuint(buffer), GL_BUFFER_SIZE, &buffer_size);
        const GLint64 at = start + u.offset, bytes = GLint64(u.stride) * (u.columns - 1) + 4 * u.components;
        if (at < 0 || at + bytes > buffer_size || (bound_size > 0 && u.offset + bytes > bound_size)) return false;
        std::vector<uint8_t> raw(static_cast<size_t>(bytes));
        gl_.glGetNamedBufferSubData(GLuint(buffer), at, bytes, raw.data());
        for (int v = 0; v < u.columns; ++v) std::memcpy(f + 4 * v, raw.data() + size_t(v) * u.stride, 4 * size_t(u.components));
        if (u.row_major) {
            float t[16];
            for (int r = 0; r < 4; ++r)
                for (int c = 0; c < 4; ++c) t[4 * c + r] = f[4 * r + c];
            std::memcpy(f, t, sizeof t);
        }
    }
    for (int i = 0; i < 4 * u.columns; ++i)
        if (!std::isfinite(f[i])) return false;
    return true;
}

namespace {

// A preprocessor condition as far as it can be told without the driver's macros: 0, 1, and
// defined(NAME) (or !defined) of the text's own #defines; anything else counts as true.
bool condition_holds(const std::string& expression, const std::unordered_set<std::string>& defined) {
    // (std::regex recurses per character: a stream's line of any length must not reach it)
    if (expression.size() > 256) return true;
    static const std::regex is_defined(R"(^\s*(!?)\s*defined\s*\(?\s*(\w+)\s*\)?\s*$)");
    std::smatch m;
    if (std::regex_match(expression, m, is_defined)) return (defined.count(m[2].str()) > 0) != (m[1].length() > 0);
    static const std::regex number(R"(^\s*(\d+)\s*$)");
    if (std::regex_match(expression, m, number)) return std::stol(m[1].str()) != 0;
    return true;
}

// The lines of `glsl` its own #if, #ifdef, #ifndef, #elif, #else and #endif leave in (those
// lines themselves left out; #define kept: a macro's body names what its uses read).
std::string active_text(const std::string& glsl) {
    std::unordered_set<std::string> defined;
    struct Branch {
        bool outer = true, taken = false, active = true;
    };
    std::vector<Branch> stack;
    auto active = [&] { return stack.empty() || stack.back().active; };
    std::string out;
    std::istringstream lines(glsl);
    for (std::string line; std::getline(lines, line);) {
        // A directive: '#', its word, the rest (read by hand: a line may be of any length).
        const size_t hash = line.find_first_not_of(" \t\r");
        if (hash == std::string::npos || line[hash] != '#') {
            if (active()) out += line + '\n';
            continue;
        }
        const size_t word_at = std::min(line.find_first_not_of(" \t", hash + 1), line.size());
        size_t word_end = word_at;
        while (word_end < line.size() && (std::isalnum(static_cast<unsigned char>(line[word_end])) || line[word_end] == '_'))
            ++word_end;
        const std::string word = line.substr(word_at, word_end - word_at);
        const std::string rest = line.substr(std::min(line.find_first_not_of(" \t", word_end), line.size()));
        if (word == "if" || word == "ifdef" || word == "ifndef") {
            const bool holds = word == "if" ? condition_holds(rest, defined)
                                            : (defined.count(rest.substr(0, rest.find_first_of(" \t/"))) > 0) == (word == "ifdef");
            const bool outer = active();
            stack.push_back({outer, holds, outer && holds});
        } else if ((word == "elif" || word == "else") && !stack.empty()) {
            Branch& b = stack.back();
            const bool holds = !b.taken && (word == "else" || condition_holds(rest, defined));
            b.active = b.outer && holds;
            b.taken = b.taken || holds;
        } else if (word == "endif" && !stack.empty()) {
            stack.pop_back();
        } else if (active()) {
            if (word == "define") defined.insert(rest.substr(0, rest.find_first_of(" \t(")));
            else if (word == "undef") defined.erase(rest.substr(0, rest.find_first_of(" \t")));
            out += line + '\n';
        }
    }
    return out;
}

}  // namespace

std::unordered_set<std::string> names_read(const std::string& source) {
    const std::string glsl = active_text(source);
    std::unordered_map<std::string, int> count;
    for (size_t i = 0; i < glsl.size();) {
        const char c = glsl[i];
        if (c == '/' && i + 1 < glsl.size() && glsl[i + 1] == '/') {
            i = glsl.find('\n', i);
        } else if (c == '/' && i + 1 < glsl.size() && glsl[i + 1] == '*') {
            i = glsl.find("*/", i + 2);
            if (i != std::string::npos) i += 2;
        } else if (std::isalpha(static_cast<unsigned char>(c)) || c == '_') {
            size_t end = i + 1;
            while (end < glsl.size() && (std::isalnum(static_cast<unsigned char>(glsl[end])) || glsl[end] == '_')) ++end;
            ++count[glsl.substr(i, end - i)];
            i = end;
        } else {
            ++i;
        }
    }
    std::unordered_set<std::string> read;
    for (const auto& [name, n] : count)
        if (n >= 2) read.insert(name);
    return read;
}

void ProgramCameras::linked(uint32_t program) {
    // (bounded: a stream that links without end keeps as many entries as this)
    constexpr size_t kMostPrograms = 4096;
    constexpr GLsizei kMostShaders = 16;
    reads_.erase(program);
    if (!program || !gl_.has(OP_glGetAttachedShaders) || !gl_.has(OP_glGetShaderSource)) return;
    GLuint shaders[kMostShaders] = {};
    GLsizei count = 0;
    gl_.glGetAttachedShaders(program, kMostShaders, &count, shaders);
    Reads reads;
    // (each shader's own: every stage declares the blocks of a shared header once)
    for (GLsizei i = 0; i < std::clamp(count, 0, kMostShaders); ++i) {
        GLint type = 0, length = 0;
        gl_.glGetShaderiv(shaders[i], GL_SHADER_TYPE, &type);
        gl_.glGetShaderiv(shaders[i], GL_SHADER_SOURCE_LENGTH, &length);
        if (length <= 0) return;  // (a shader whose source is not known: nothing to go by)
        std::string source(size_t(length), '\0');
        GLsizei written = 0;
        gl_.glGetShaderSource(shaders[i], length, &written, source.data());
        source.resize(size_t(std::clamp(written, 0, length)));
        for (const std::string& name : names_read(source)) {
            if (type != GL_FRAGMENT_SHADER && type != GL_COMPUTE_SHADER) reads.vertex.insert(name);
            reads.any.insert(name);
        }
    }
    if (count <= 0) return;
    if (reads_.size() >= kMostPrograms) reads_.clear();
    reads_[program] = std::move(reads);
}

// A block member's name as the driver lists it: "Block.member[0]" or "member".
bool ProgramCameras::read(uint32_t program, const std::string& name, bool by_vertex_stages) const {
    const auto it = reads_.find(program);
    if (it == reads_.end()) return true;
    const size_t dot = name.rfind('.');
    std::string member = name.substr(dot == std::string::npos ? 0 : dot + 1);
    member = member.substr(0, member.find('['));
    return (by_vertex_stages ? it->second.vertex : it->second.any).count(member) > 0;
}

bool ProgramCameras::orthographic(uint32_t program) {
    if (!program) return false;
    for (const Uniform& u : uniforms(program).matrices) {
        float f[16];
        if (!value(program, u, f)) continue;
        glm::dmat4 m;
        for (int k = 0; k < 16; ++k) m[k / 4][k % 4] = f[k];
        if (is_orthographic(m)) return true;
    }
    return false;
}

bool ProgramCameras::reads_fixed_function(uint32_t program) { return program && uniforms(program).fixed_function; }

bool ProgramCameras::places_by_matrix(uint32_t program) {
    return program && (!uniforms(program).matrices.empty() || uniforms(program).fixed_function);
}

bool ProgramCameras::light(uint32_t program, const ProgramCamera& camera, effects::SceneLight& out) {
    if (!program) return false;
    const Uniforms& all = uniforms(program);
    if (all.fixed_function_light >= 0) {  // GL keeps it in eye space, as the program's modelview then was
        GLfloat position[4] = {0, 0, 1, 0};
        gl_.glGetLightfv(GLenum(GL_LIGHT0 + all.fixed_function_light), GL_POSITION, position);
        out = effects::SceneLight{true, glm::dvec4(position[0], position[1], position[2], position[3])};
        return true;
    }
    for (const Uniform& u : all.lights) {
        float f[16];
        if (!value(program, u, f)) continue;
        glm::dvec4 v(f[0], f[1], f[2], u.components == 4 ? f[3] : (u.meaning.position ? 1.0 : 0.0));
        if (glm::length(glm::dvec3(v)) < 1e-12 && v.w == 0) continue;
        if (!u.meaning.eye_space && !camera.lights_in_eye_space)
            v = camera.modelview * v;  // (the identity when no view was found)
        out = effects::SceneLight{true, v};
        out.sign_from_up = v.w == 0;
        return true;
    }
    return false;
}

// (w = s z, with no constant: up to the rounding of a projection recovered from a corrected one,
// inverse(M) * M * P, whose M moves the eye; GL keeps M * P in floats: 1e-8 of s and more)
bool is_perspective(const glm::dmat4& p) { return p[2][3] != 0 && std::abs(p[3][3]) <= 1e-6 * std::abs(p[2][3]); }

bool is_orthographic(const glm::dmat4& m) {
    if (m[0][3] != 0 || m[1][3] != 0 || m[2][3] != 0 || m[3][3] != 1) return false;
    if (m[1][0] != 0 || m[2][0] != 0 || m[0][1] != 0 || m[2][1] != 0) return false;
    return m[0][0] != 0 && m[1][1] != 0 && (std::abs(m[0][0] - 1) > 1e-6 || std::abs(m[1][1] - 1) > 1e-6);
}

bool same_projection(const glm::dmat4& a, const glm::dmat4& b) {
    double scale = 0;
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r) scale = std::max(scale, std::abs(a[c][r]));
    const double tolerance = 1e-5 * scale;
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r)
            if (!(std::abs(a[c][r] - b[c][r]) <= tolerance)) return false;
    return true;
}

bool mirrored(const glm::dmat4& modelview) { return glm::determinant(glm::dmat3(modelview)) < 0; }

bool ProgramCameras::find(uint32_t program, ProgramCamera& out) {
    if (!program) return false;
    const std::vector<Uniform>& all = uniforms(program).matrices;
    std::vector<glm::dmat4> values(all.size());
    std::vector<bool> read(all.size());
    for (size_t i = 0; i < all.size(); ++i) {
        float f[16];
        read[i] = value(program, all[i], f);
        for (int k = 0; k < 16; ++k) values[i][k / 4][k % 4] = f[k];
    }
    for (size_t i = 0; i < all.size(); ++i) {
        glm::dmat4 p, v;
        if (!read[i] || !split_perspective(values[i], p, v)) continue;
        out.projection = p;
        out.modelview = v;
        out.modelview_known = v != glm::dmat4(1.0);  // a product P * V: V is the view
        if (v == glm::dmat4(1.0)) {  // a projection alone: the view is another matrix, if any
            for (size_t k = 0; k < all.size(); ++k) {
                std::string name = all[k].name;
                std::transform(name.begin(), name.end(), name.begin(), [](unsigned char ch) { return std::tolower(ch); });
                if (k == i || !read[k] || !is_rigid(values[k]) || name.find("view") == std::string::npos) continue;
                out.modelview = values[k];
                out.modelview_known = true;
                out.lights_in_eye_space = name.find("model") != std::string::npos;
                break;
            }
        }
        return true;
    }
    return false;
}

}  // namespace glcast::slave
