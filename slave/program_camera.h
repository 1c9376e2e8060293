// The camera of a shader program, found from the matrices it uploads (docs/effects.md, "The
// main view of shader programs"): no display config needed. A perspective projection has a
// fixed structure (row 3 is (0, 0, -1, 0), rows 0 and 1 mix only their own axis with z), so a
// matrix P * V, with V a rotation, a uniform scale and a translation, splits into both, as a
// camera matrix is decomposed in computer vision; P alone splits into P and the identity.
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "glcast_gl_api.h"

namespace glcast::slave {

// Splits m = P * V (column-major, as GL stores it); false when m is no such product (an
// orthographic projection, a model or normal matrix). P may be off-centre (b, d below), so a
// model matrix with a non-uniform scale inside P * V splits too, with a skewed P: the stream
// cannot tell the two apart; programs put such scales in a model matrix of their own.
bool split_perspective(const glm::dmat4& m, glm::dmat4& projection, glm::dmat4& view);

// A rotation, a uniform scale and a translation (a view or modelview matrix).
bool is_rigid(const glm::dmat4& m);

bool is_perspective(const glm::dmat4& p);
// Two projections split from different matrices of one camera: the same to float precision (a
// projection split from projection * view * model comes out of each draw's product rounded
// differently).
bool same_projection(const glm::dmat4& a, const glm::dmat4& b);
// A view turned inside out (glScalef(1, -1, 1)): a planar reflection drawn below a floor
// before the scene. No camera is: it is not the main view.
bool mirrored(const glm::dmat4& modelview);

struct ProgramCamera {
    glm::dmat4 projection{1.0}, modelview{1.0};
    bool modelview_known = false;  // false: the program's view transform is not among its matrices
};

// Reads the 4x4 matrices of a linked program as they are now (default-block uniforms, and
// members of uniform blocks from the buffers bound to them) and finds its camera: the first
// matrix that splits as a perspective product; when that one is a projection alone, the
// modelview is a rigid matrix whose name says "view" if there is one. Per program, what its
// matrices are is read once (forget() after a link).
class ProgramCameras {
public:
    explicit ProgramCameras(const GlApi& gl) : gl_(gl) {}
    bool find(uint32_t program, ProgramCamera& out);
    // Its shaders read the fixed-function matrices through GLSL's built-ins
    // (gl_ModelViewProjectionMatrix, gl_ProjectionMatrix, ...): its camera is GL_PROJECTION's.
    bool reads_fixed_function(uint32_t program);
    void forget() { matrices_.clear(), fixed_function_.clear(); }

private:
    struct Matrix {
        std::string name;
        int32_t location = -1;  // default block; -1: in a uniform block
        uint32_t block = 0, offset = 0, stride = 16;
        bool row_major = false;
    };
    const std::vector<Matrix>& matrices(uint32_t program);
    bool value(uint32_t program, const Matrix& m, glm::dmat4& out);

    const GlApi& gl_;
    std::map<uint32_t, std::vector<Matrix>> matrices_;
    std::map<uint32_t, bool> fixed_function_;  // by program, filled with matrices_
};

}  // namespace glcast::slave
