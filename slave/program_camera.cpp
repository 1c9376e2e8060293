#include "slave/program_camera.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstring>

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
    if (!(f != 0) || !std::isfinite(f) || glm::determinant(glm::dmat3(v)) <= 0) return false;
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

const std::vector<ProgramCameras::Matrix>& ProgramCameras::matrices(uint32_t program) {
    auto it = matrices_.find(program);
    if (it != matrices_.end()) return it->second;
    std::vector<Matrix>& out = matrices_[program];
    GLint count = 0;
    gl_.glGetProgramiv(program, GL_ACTIVE_UNIFORMS, &count);
    for (GLuint i = 0; i < GLuint(std::clamp(count, 0, 1024)); ++i) {
        char name[256] = {};
        GLint size = 0;
        GLenum type = 0;
        gl_.glGetActiveUniform(program, i, sizeof name, nullptr, &size, &type, name);
        const bool builtin = std::strncmp(name, "gl_", 3) == 0;
        if (builtin && (std::strncmp(name, "gl_ModelView", 12) == 0 || std::strncmp(name, "gl_Projection", 13) == 0))
            fixed_function_[program] = true;
        if (type != GL_FLOAT_MAT4 || std::strncmp(name, "glcast_", 7) == 0 || builtin) continue;
        Matrix m;
        m.name = name;
        GLint block = -1, offset = 0, stride = 0, row_major = 0;
        if (gl_.has(OP_glGetActiveUniformsiv)) {
            gl_.glGetActiveUniformsiv(program, 1, &i, GL_UNIFORM_BLOCK_INDEX, &block);
            gl_.glGetActiveUniformsiv(program, 1, &i, GL_UNIFORM_OFFSET, &offset);
            gl_.glGetActiveUniformsiv(program, 1, &i, GL_UNIFORM_MATRIX_STRIDE, &stride);
            gl_.glGetActiveUniformsiv(program, 1, &i, GL_UNIFORM_IS_ROW_MAJOR, &row_major);
        }
        if (block >= 0) {
            m.block = uint32_t(block), m.offset = uint32_t(std::max(offset, 0)), m.stride = uint32_t(std::max(stride, 16));
            m.row_major = row_major != 0;
        } else {
            m.location = gl_.glGetUniformLocation(program, name);
            if (m.location < 0) continue;
        }
        out.push_back(std::move(m));
    }
    return out;
}

bool ProgramCameras::value(uint32_t program, const Matrix& m, glm::dmat4& out) {
    float f[16] = {};
    if (m.location >= 0) {
        gl_.glGetUniformfv(program, m.location, f);
    } else {
        if (!gl_.has(OP_glGetNamedBufferSubData) || !gl_.has(OP_glGetIntegeri_v)) return false;
        GLint binding = 0, buffer = 0;
        GLint64 start = 0, bound_size = 0;
        gl_.glGetActiveUniformBlockiv(program, m.block, GL_UNIFORM_BLOCK_BINDING, &binding);
        gl_.glGetIntegeri_v(GL_UNIFORM_BUFFER_BINDING, GLuint(binding), &buffer);
        if (!buffer) return false;
        gl_.glGetInteger64i_v(GL_UNIFORM_BUFFER_START, GLuint(binding), &start);
        gl_.glGetInteger64i_v(GL_UNIFORM_BUFFER_SIZE, GLuint(binding), &bound_size);
        GLint64 buffer_size = 0;
        gl_.glGetNamedBufferParameteri64v(GLuint(buffer), GL_BUFFER_SIZE, &buffer_size);
        const GLint64 at = start + m.offset, bytes = GLint64(m.stride) * 3 + 16;
        if (at < 0 || at + bytes > buffer_size || (bound_size > 0 && m.offset + bytes > bound_size)) return false;
        std::vector<uint8_t> raw(static_cast<size_t>(bytes));
        gl_.glGetNamedBufferSubData(GLuint(buffer), at, bytes, raw.data());
        for (int v = 0; v < 4; ++v) std::memcpy(f + 4 * v, raw.data() + size_t(v) * m.stride, 16);
        if (m.row_major) {
            float t[16];
            for (int r = 0; r < 4; ++r)
                for (int c = 0; c < 4; ++c) t[4 * c + r] = f[4 * r + c];
            std::memcpy(f, t, sizeof f);
        }
    }
    for (int i = 0; i < 16; ++i) {
        if (!std::isfinite(f[i])) return false;
        out[i / 4][i % 4] = f[i];
    }
    return true;
}

bool ProgramCameras::reads_fixed_function(uint32_t program) {
    if (!program) return false;
    matrices(program);
    const auto it = fixed_function_.find(program);
    return it != fixed_function_.end() && it->second;
}

// (w = s z, with no constant: up to the rounding of a projection recovered from a corrected one,
// inverse(M) * M * P, whose M moves the eye; GL keeps M * P in floats: 1e-8 of s and more)
bool is_perspective(const glm::dmat4& p) { return p[2][3] != 0 && std::abs(p[3][3]) <= 1e-6 * std::abs(p[2][3]); }

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
    const std::vector<Matrix>& all = matrices(program);
    std::vector<glm::dmat4> values(all.size());
    std::vector<bool> read(all.size());
    for (size_t i = 0; i < all.size(); ++i) read[i] = value(program, all[i], values[i]);
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
                break;
            }
        }
        return true;
    }
    return false;
}

}  // namespace glcast::slave
