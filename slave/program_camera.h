// The camera of a shader program, found from the matrices it uploads (docs/effects.md, "The
// main view of shader programs"): no display config needed. A perspective projection has a
// fixed structure (row 3 is (0, 0, -1, 0), rows 0 and 1 mix only their own axis with z), so a
// matrix P * V, with V a rotation, a uniform scale and a translation, splits into both, as a
// camera matrix is decomposed in computer vision; P alone splits into P and the identity.
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <unordered_map>
#include <unordered_set>
#include <vector>

#include <glm/glm.hpp>

#include "glcast_gl_api.h"
#include "slave/effects/frame_view.h"

namespace glcast::slave {

// Splits m = P * V (column-major, as GL stores it); false when m is no such product (an
// orthographic projection, a model or normal matrix). A product whose view would come out
// mirrored splits as a left-handed camera (P with w = +z, V a rotation): the two write one
// frustum, and the picture cannot tell a mirrored view from a left-handed one. P may be off-centre (b, d below), so a
// model matrix with a non-uniform scale inside P * V splits too, with a skewed P: the stream
// cannot tell the two apart; programs put such scales in a model matrix of their own.
bool split_perspective(const glm::dmat4& m, glm::dmat4& projection, glm::dmat4& view);

// A rotation, a uniform scale and a translation (a view or modelview matrix).
bool is_rigid(const glm::dmat4& m);

bool is_perspective(const glm::dmat4& p);
// A projection onto the screen without perspective: (0, 0, 0, 1) as its last row, x and y each
// scaled alone and not by 1 (a HUD's glOrtho over pixels; an identity or a translation draws in
// clip space as a full-screen pass does).
bool is_orthographic(const glm::dmat4& m);
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
    // That transform is a model-view matrix (its name says "model" and "view"): the program's
    // shaders have no world space, and the lights it uploads are in the eye's (Castle Game
    // Engine's castle_LightSource0Position), whatever their names say.
    bool lights_in_eye_space = false;
};

// What a vec3 or vec4 uniform's name says it holds: an engine's sun or light, as a direction or a
// position, in the world's space or the eye's (docs/effects.md, "The light of shader programs").
// A name with "sun", or "light" with "dir" or "pos", and none of the words of its other
// properties (colour, intensity, ...); "view", "eye", "camera" or "vc" (VTK's view coordinates)
// in it: the eye's space.
struct LightUniform {
    bool light = false;
    bool position = false;   // a vec3 whose name says "pos"; a vec4 says it by its w
    bool eye_space = false;
};
LightUniform light_uniform(const std::string& name);

// The identifiers a GLSL text reads: those it names twice or more outside comments (a uniform
// block member the text only declares, as engines declare one block of every matrix in each
// shader, is named once).
std::unordered_set<std::string> names_read(const std::string& glsl);

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
    // The program's sun as the passes take a light (an eye-space GL_POSITION): the fixed-function
    // light its shaders read through gl_LightSource[i], else the first light uniform
    // (light_uniform) that holds a finite, non-zero vector, brought from the world's space by
    // `camera`'s view. False: none. A direction from a uniform may point either way (towards the
    // sun or the way its light travels): SceneLight::sign_from_up says so.
    bool light(uint32_t program, const ProgramCamera& camera, effects::SceneLight& out);
    // One of its matrices is orthographic (is_orthographic) as they are now: it draws flat (a
    // HUD's text, VTK's 2D actors).
    bool orthographic(uint32_t program);
    // It has a 4x4 matrix at all (its own, or the fixed-function ones through the built-ins): a
    // program with none places its vertices itself (a full-target pass by gl_VertexID).
    bool places_by_matrix(uint32_t program);
    void forget() { uniforms_.clear(); }
    // The program was linked: what its stages read, from the sources of the shaders attached now
    // (engines detach them after linking). A matrix in a uniform block that its vertex stages do
    // not read places no vertex, a light in one that no stage reads lights nothing (the driver
    // lists every member of a std140 block as active: SuperTuxKart's HUD and full-screen programs
    // declare its block of camera matrices too).
    void linked(uint32_t program);

private:
    struct Uniform {
        std::string name;
        int32_t location = -1;  // default block; -1: in a uniform block
        uint32_t block = 0, offset = 0, stride = 16;
        int columns = 4, components = 4;  // a mat4: 4 x 4; a vec3: 1 x 3
        bool row_major = false;
        LightUniform meaning;  // vectors only
    };
    struct Uniforms {
        std::vector<Uniform> matrices, lights;
        bool fixed_function = false;     // gl_ModelView..., gl_Projection...
        int fixed_function_light = -1;   // gl_LightSource[i]: the first i read
    };
    const Uniforms& uniforms(uint32_t program);
    bool value(uint32_t program, const Uniform& u, float out[16]);

    bool read(uint32_t program, const std::string& name, bool by_vertex_stages) const;

    const GlApi& gl_;
    std::map<uint32_t, Uniforms> uniforms_;  // by program, read once
    // By program: the names its vertex stages and all its stages read (no entry: not known,
    // every name read).
    struct Reads {
        std::unordered_set<std::string> vertex, any;
    };
    std::unordered_map<uint32_t, Reads> reads_;
};

}  // namespace glcast::slave
