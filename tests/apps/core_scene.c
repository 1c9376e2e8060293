/*
 * core_scene.c - glcast test app: OpenGL 3.3 core profile through Xlib + GLX.
 *
 * The context comes from glXChooseFBConfig + glXCreateContextAttribsARB (3.3, core profile
 * bit), and every GL entry point above 1.1 is loaded with glXGetProcAddressARB into the
 * program's own pointer table (no GL_GLEXT_PROTOTYPES). GL 1.0/1.1 functions (glClear,
 * glDrawElements, glTexImage2D, ...) are called directly from libGL.
 *
 * The scene mirrors ff_scene: a large checkered ground plane, boxes standing on it, a box
 * floating (bobbing and spinning) above the ground, a camera orbiting with the frame index,
 * diffuse + ambient lighting in the fragment shader. Every frame first renders the scene from
 * a fixed second camera into an FBO (RGBA8 texture + DEPTH24_STENCIL8 renderbuffer); the
 * main pass then shows that texture on a "monitor" standing behind the scene.
 *
 * Exercised on purpose (for the capture side):
 *  - glShaderSource with 2 strings and a lengths array {-1, n}: the first string is the
 *    NUL-terminated "#version 330 core\n", the second has an explicit length that stops
 *    before a trailing "#error" line in the same C string (a capture that ignores the
 *    lengths and reads up to the NUL ships a shader that no longer compiles)
 *  - glGetShaderiv / glGetProgramiv + info logs, glGetUniformLocation + glUniform*
 *  - VAOs over an interleaved VBO (position + normal) and one element buffer; every draw is
 *    glDrawElements with a byte offset into the element buffer (0, 72, 84)
 *  - a std140 uniform block (view/projection/light) bound with glGetUniformBlockIndex +
 *    glUniformBlockBinding + glBindBufferBase, rewritten with glBufferSubData before each
 *    of the two passes of every frame
 *  - one vertex buffer rewritten every frame through glMapBufferRange(GL_MAP_WRITE_BIT |
 *    GL_MAP_INVALIDATE_RANGE_BIT) + memcpy + glUnmapBuffer (the floating box)
 *  - an FBO render-to-texture pass every frame, glCheckFramebufferStatus(GL_FRAMEBUFFER),
 *    glGenerateMipmap on the result, which is then sampled in the main pass
 *
 * With --painter (a first argument) the window pass draws everything after the ground with the
 * depth test off, in order (a program that paints its scene back to front).
 *
 * With --offscreen the main pass renders into a framebuffer object of the window's size (RGBA8
 * texture + DEPTH_COMPONENT24 renderbuffer, as post-processing engines do), which a full-window
 * triangle with the depth test off then copies to the window (nearest texels: the same pixels);
 * a HUD panel (HUD_X, HUD_Y, HUD_W, HUD_H, solid HUD_COLOR) follows with the depth test off.
 * With --offscreen --hud-vao the panel is drawn by glDrawElements from a vertex-array object of its
 * own, whose element buffer holds {9, 9, 9, 0, 1, 2} (the draw takes the last three: gl_VertexID
 * 0, 1, 2), and every frame starts by binding the scene's element buffer with the vertex-array
 * object 0 bound (which holds it then), as SuperTuxKart leaves its element buffer bound.
 * With --offscreen --dim a full-window black triangle of alpha 0.27 is blended over the shown
 * scene before the panel (a menu dims the scene behind it so).
 *
 * Prints to stdout:
 *   core_scene: GL_RENDERER <string>
 *   core_scene: GL_VERSION <string>
 *   core_scene: glGenBuffers -> <static vbo> <element buffer> <dynamic vbo> <ubo>
 *   core_scene: glGenVertexArrays -> <static vao> <dynamic vao>
 *   core_scene: glGenTextures -> <fbo colour texture>
 *   core_scene: glGenRenderbuffers -> <depth/stencil>
 *   core_scene: glGenFramebuffers -> <fbo>
 *   core_scene: frames <N>
 */
#include <GL/gl.h>
#include <GL/glext.h>
#include <GL/glx.h>
#include <X11/Xlib.h>
#include <X11/Xutil.h>
#include <math.h>

#include "app_common.h"

static const char *PROG = "core_scene";

/* ---------------------------------------------------------------- GL 1.2+ entry points */

#define CORE_GL_FUNCS(F)                                              \
    F(PFNGLGENBUFFERSPROC, GenBuffers)                                \
    F(PFNGLDELETEBUFFERSPROC, DeleteBuffers)                          \
    F(PFNGLBINDBUFFERPROC, BindBuffer)                                \
    F(PFNGLBINDBUFFERBASEPROC, BindBufferBase)                        \
    F(PFNGLBUFFERDATAPROC, BufferData)                                \
    F(PFNGLBUFFERSUBDATAPROC, BufferSubData)                          \
    F(PFNGLMAPBUFFERRANGEPROC, MapBufferRange)                        \
    F(PFNGLUNMAPBUFFERPROC, UnmapBuffer)                              \
    F(PFNGLGENVERTEXARRAYSPROC, GenVertexArrays)                      \
    F(PFNGLDELETEVERTEXARRAYSPROC, DeleteVertexArrays)                \
    F(PFNGLBINDVERTEXARRAYPROC, BindVertexArray)                      \
    F(PFNGLENABLEVERTEXATTRIBARRAYPROC, EnableVertexAttribArray)      \
    F(PFNGLVERTEXATTRIBPOINTERPROC, VertexAttribPointer)              \
    F(PFNGLCREATESHADERPROC, CreateShader)                            \
    F(PFNGLDELETESHADERPROC, DeleteShader)                            \
    F(PFNGLSHADERSOURCEPROC, ShaderSource)                            \
    F(PFNGLCOMPILESHADERPROC, CompileShader)                          \
    F(PFNGLGETSHADERIVPROC, GetShaderiv)                              \
    F(PFNGLGETSHADERINFOLOGPROC, GetShaderInfoLog)                    \
    F(PFNGLCREATEPROGRAMPROC, CreateProgram)                          \
    F(PFNGLDELETEPROGRAMPROC, DeleteProgram)                          \
    F(PFNGLATTACHSHADERPROC, AttachShader)                            \
    F(PFNGLDETACHSHADERPROC, DetachShader)                            \
    F(PFNGLLINKPROGRAMPROC, LinkProgram)                              \
    F(PFNGLGETPROGRAMIVPROC, GetProgramiv)                            \
    F(PFNGLGETPROGRAMINFOLOGPROC, GetProgramInfoLog)                  \
    F(PFNGLUSEPROGRAMPROC, UseProgram)                                \
    F(PFNGLGETUNIFORMLOCATIONPROC, GetUniformLocation)                \
    F(PFNGLUNIFORM1IPROC, Uniform1i)                                  \
    F(PFNGLUNIFORM3FPROC, Uniform3f)                                  \
    F(PFNGLUNIFORMMATRIX3FVPROC, UniformMatrix3fv)                    \
    F(PFNGLUNIFORMMATRIX4FVPROC, UniformMatrix4fv)                    \
    F(PFNGLGETUNIFORMBLOCKINDEXPROC, GetUniformBlockIndex)            \
    F(PFNGLGETACTIVEUNIFORMBLOCKIVPROC, GetActiveUniformBlockiv)      \
    F(PFNGLUNIFORMBLOCKBINDINGPROC, UniformBlockBinding)              \
    F(PFNGLACTIVETEXTUREPROC, ActiveTexture)                          \
    F(PFNGLGENERATEMIPMAPPROC, GenerateMipmap)                        \
    F(PFNGLGENFRAMEBUFFERSPROC, GenFramebuffers)                      \
    F(PFNGLDELETEFRAMEBUFFERSPROC, DeleteFramebuffers)                \
    F(PFNGLBINDFRAMEBUFFERPROC, BindFramebuffer)                      \
    F(PFNGLFRAMEBUFFERTEXTURE2DPROC, FramebufferTexture2D)            \
    F(PFNGLFRAMEBUFFERRENDERBUFFERPROC, FramebufferRenderbuffer)      \
    F(PFNGLCHECKFRAMEBUFFERSTATUSPROC, CheckFramebufferStatus)        \
    F(PFNGLGENRENDERBUFFERSPROC, GenRenderbuffers)                    \
    F(PFNGLDELETERENDERBUFFERSPROC, DeleteRenderbuffers)              \
    F(PFNGLBINDRENDERBUFFERPROC, BindRenderbuffer)                    \
    F(PFNGLRENDERBUFFERSTORAGEPROC, RenderbufferStorage)              \
    F(PFNGLUNIFORM4FPROC, Uniform4f)

static struct {
#define F(type, name) type name;
    CORE_GL_FUNCS(F)
#undef F
} gl;

/* Every pointer from glXGetProcAddressARB; a NULL one is fatal. */
static void load_gl(void)
{
    int missing = 0;
#define F(type, name)                                                               \
    gl.name = (type)glXGetProcAddressARB((const GLubyte *)"gl" #name);              \
    if (gl.name == NULL) {                                                          \
        fprintf(stderr, "%s: glXGetProcAddressARB(\"gl%s\") returned NULL\n", PROG, #name); \
        missing = 1;                                                                \
    }
    CORE_GL_FUNCS(F)
#undef F
    if (missing)
        exit(1);
}

/* ---------------------------------------------------------------- matrices */

/* 4x4 column-major (m[col * 4 + row]), as GL wants them. */
typedef struct {
    float m[16];
} mat4;

static mat4 m4_identity(void)
{
    mat4 r;
    int i;
    for (i = 0; i < 16; i++)
        r.m[i] = (i % 5 == 0) ? 1.0f : 0.0f;
    return r;
}

static mat4 m4_mul(mat4 a, mat4 b)
{
    mat4 r;
    int c, row, k;
    for (c = 0; c < 4; c++)
        for (row = 0; row < 4; row++) {
            float s = 0.0f;
            for (k = 0; k < 4; k++)
                s += a.m[k * 4 + row] * b.m[c * 4 + k];
            r.m[c * 4 + row] = s;
        }
    return r;
}

static mat4 m4_translate(float x, float y, float z)
{
    mat4 r = m4_identity();
    r.m[12] = x;
    r.m[13] = y;
    r.m[14] = z;
    return r;
}

static mat4 m4_scale(float x, float y, float z)
{
    mat4 r = m4_identity();
    r.m[0] = x;
    r.m[5] = y;
    r.m[10] = z;
    return r;
}

static mat4 m4_rotate_x(float deg)
{
    mat4 r = m4_identity();
    float a = deg * APP_PI / 180.0f, c = cosf(a), s = sinf(a);
    r.m[5] = c;
    r.m[6] = s;
    r.m[9] = -s;
    r.m[10] = c;
    return r;
}

static mat4 m4_rotate_y(float deg)
{
    mat4 r = m4_identity();
    float a = deg * APP_PI / 180.0f, c = cosf(a), s = sinf(a);
    r.m[0] = c;
    r.m[2] = -s;
    r.m[8] = s;
    r.m[10] = c;
    return r;
}

static mat4 m4_rotate_z(float deg)
{
    mat4 r = m4_identity();
    float a = deg * APP_PI / 180.0f, c = cosf(a), s = sinf(a);
    r.m[0] = c;
    r.m[1] = s;
    r.m[4] = -s;
    r.m[5] = c;
    return r;
}

static mat4 m4_perspective(float fovy_deg, float aspect, float znear, float zfar)
{
    mat4 r;
    float f = 1.0f / tanf(0.5f * fovy_deg * APP_PI / 180.0f);
    memset(&r, 0, sizeof r);
    r.m[0] = f / aspect;
    r.m[5] = f;
    r.m[10] = (zfar + znear) / (znear - zfar);
    r.m[11] = -1.0f;
    r.m[14] = 2.0f * zfar * znear / (znear - zfar);
    return r;
}

/* Inverse transpose of the upper 3x3 (column-major out), for normals under non-uniform
 * scales: cofactor matrix / determinant. */
static void m4_normal_matrix(const mat4 *m, float out[9])
{
    float a[3][3], cof[3][3], det;
    int r, c;
    for (r = 0; r < 3; r++)
        for (c = 0; c < 3; c++)
            a[r][c] = m->m[c * 4 + r];
    for (r = 0; r < 3; r++)
        for (c = 0; c < 3; c++)
            cof[r][c] = a[(r + 1) % 3][(c + 1) % 3] * a[(r + 2) % 3][(c + 2) % 3] -
                        a[(r + 1) % 3][(c + 2) % 3] * a[(r + 2) % 3][(c + 1) % 3];
    det = a[0][0] * cof[0][0] + a[0][1] * cof[0][1] + a[0][2] * cof[0][2];
    for (r = 0; r < 3; r++)
        for (c = 0; c < 3; c++)
            out[c * 3 + r] = cof[r][c] / det;
}

static void m4_apply(const mat4 *m, const float in[3], float w, float out[3])
{
    int r;
    for (r = 0; r < 3; r++)
        out[r] = m->m[r] * in[0] + m->m[4 + r] * in[1] + m->m[8 + r] * in[2] + m->m[12 + r] * w;
}

/* ---------------------------------------------------------------- geometry */

/* Interleaved vertex: position, normal. */
struct vertex {
    GLfloat pos[3];
    GLfloat nrm[3];
};

/*
 * Static vertex buffer:
 *   0..23   unit cube (-0.5..0.5), 4 vertices per face, CCW from outside
 *   24..27  ground quad (y = 0, +-GROUND_HALF), normal +y
 *   28..31  monitor screen quad (z = 0, -0.5..0.5), normal +z; the shader takes its
 *           texture coordinates from the position (uv = pos.xy + 0.5)
 * Element buffer (GLushort):
 *   0..35   cube triangles (vertices 0..23)      byte offset 0
 *   36..41  ground                               byte offset 72
 *   42..47  monitor screen                       byte offset 84
 * The dynamic buffer holds 24 vertices laid out like the cube, so the floating box is drawn
 * with the cube's indices (offset 0) through its own VAO.
 */
#define CUBE_VERTS 24
#define STATIC_VERTS 32
#define CUBE_INDICES 36
#define QUAD_INDICES 6
#define GROUND_FIRST_INDEX 36
#define SCREEN_FIRST_INDEX 42
#define TOTAL_INDICES 48
#define GROUND_HALF 20.0f

static struct vertex static_verts[STATIC_VERTS];
static GLushort indices[TOTAL_INDICES];

static void build_geometry(void)
{
    /* per face: normal n, tangents u, v with u x v = n (as ff_scene) */
    static const float f[6][3][3] = {
        {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}},  {{-1, 0, 0}, {0, 0, 1}, {0, 1, 0}},
        {{0, 1, 0}, {0, 0, 1}, {1, 0, 0}},  {{0, -1, 0}, {1, 0, 0}, {0, 0, 1}},
        {{0, 0, 1}, {1, 0, 0}, {0, 1, 0}},  {{0, 0, -1}, {0, 1, 0}, {1, 0, 0}},
    };
    static const float cu[4] = {-1, 1, 1, -1}, cv[4] = {-1, -1, 1, 1};
    static const float ground[4][3] = {{-1, 0, 1}, {1, 0, 1}, {1, 0, -1}, {-1, 0, -1}};
    static const float screen[4][3] = {{-0.5f, -0.5f, 0}, {0.5f, -0.5f, 0}, {0.5f, 0.5f, 0},
                                       {-0.5f, 0.5f, 0}};
    int i, k, c, n = 0;
    for (i = 0; i < 6; i++) {
        for (k = 0; k < 4; k++) {
            struct vertex *v = &static_verts[i * 4 + k];
            for (c = 0; c < 3; c++) {
                v->pos[c] = 0.5f * (f[i][0][c] + cu[k] * f[i][1][c] + cv[k] * f[i][2][c]);
                v->nrm[c] = f[i][0][c];
            }
        }
        indices[n++] = (GLushort)(i * 4);
        indices[n++] = (GLushort)(i * 4 + 1);
        indices[n++] = (GLushort)(i * 4 + 2);
        indices[n++] = (GLushort)(i * 4);
        indices[n++] = (GLushort)(i * 4 + 2);
        indices[n++] = (GLushort)(i * 4 + 3);
    }
    for (k = 0; k < 4; k++) {
        struct vertex *g = &static_verts[24 + k], *s = &static_verts[28 + k];
        for (c = 0; c < 3; c++) {
            g->pos[c] = GROUND_HALF * ground[k][c];
            g->nrm[c] = (c == 1) ? 1.0f : 0.0f;
            s->pos[c] = screen[k][c];
            s->nrm[c] = (c == 2) ? 1.0f : 0.0f;
        }
    }
    for (i = 0; i < 2; i++) {
        GLushort b = (GLushort)(24 + i * 4);
        indices[n++] = b;
        indices[n++] = (GLushort)(b + 1);
        indices[n++] = (GLushort)(b + 2);
        indices[n++] = b;
        indices[n++] = (GLushort)(b + 2);
        indices[n++] = (GLushort)(b + 3);
    }
}

/* The floating box for this frame, transformed on the CPU (its draw uses an identity model
 * matrix): it bobs up and down and spins, driven by the frame index only. */
static void build_floating_box(int frame, struct vertex out[CUBE_VERTS])
{
    const float bob = 0.45f * sinf(0.12f * (float)frame);
    mat4 m = m4_mul(m4_translate(-0.3f, 3.3f + bob, 0.0f),
                    m4_mul(m4_rotate_y(3.0f * (float)frame),
                           m4_mul(m4_rotate_z(25.0f), m4_scale(1.1f, 1.1f, 1.1f))));
    int v;
    for (v = 0; v < CUBE_VERTS; v++) {
        m4_apply(&m, static_verts[v].pos, 1.0f, out[v].pos);
        /* rotation and uniform scale: the rotated normal only needs renormalizing, which
         * the fragment shader does */
        m4_apply(&m, static_verts[v].nrm, 0.0f, out[v].nrm);
    }
}

/* ---------------------------------------------------------------- shaders */

#define GLSL_VERSION_LINE "#version 330 core\n"

/* The second source string of each shader: the explicit length passed to glShaderSource
 * covers *_BODY only, never the "#error" line that follows it in the same C string. */
#define VS_BODY                                                        \
    "layout(std140) uniform Camera {\n"                                \
    "    mat4 view;\n"                                                 \
    "    mat4 proj;\n"                                                 \
    "    vec4 light_dir;\n"                                            \
    "    vec4 tint;\n"                                                 \
    "};\n"                                                             \
    "layout(location = 0) in vec3 a_pos;\n"                            \
    "layout(location = 1) in vec3 a_nrm;\n"                            \
    "uniform mat4 u_model;\n"                                          \
    "uniform mat3 u_normal;\n"                                         \
    "out vec3 v_world;\n"                                              \
    "out vec3 v_nrm;\n"                                                \
    "out vec2 v_uv;\n"                                                 \
    "void main() {\n"                                                  \
    "    vec4 w = u_model * vec4(a_pos, 1.0);\n"                       \
    "    v_world = w.xyz;\n"                                           \
    "    v_nrm = u_normal * a_nrm;\n"                                  \
    "    v_uv = a_pos.xy + 0.5;\n"                                     \
    "    gl_Position = proj * view * w;\n"                             \
    "}\n"

#define FS_BODY                                                                   \
    "layout(std140) uniform Camera {\n"                                           \
    "    mat4 view;\n"                                                            \
    "    mat4 proj;\n"                                                            \
    "    vec4 light_dir;\n"                                                       \
    "    vec4 tint;\n"                                                            \
    "};\n"                                                                        \
    "in vec3 v_world;\n"                                                          \
    "in vec3 v_nrm;\n"                                                            \
    "in vec2 v_uv;\n"                                                             \
    "uniform vec3 u_color;\n"                                                     \
    "uniform int u_mode;\n" /* 0 lit, 1 lit + ground checker, 2 monitor screen */ \
    "uniform sampler2D u_screen;\n"                                               \
    "out vec4 frag_color;\n"                                                      \
    "void main() {\n"                                                             \
    "    if (u_mode == 2) {\n"                                                    \
    "        vec3 t = texture(u_screen, v_uv).rgb;\n"                             \
    "        float scan = 0.94 + 0.06 * step(0.5, fract(v_uv.y * 48.0));\n"       \
    "        frag_color = vec4(t * scan + vec3(0.02, 0.04, 0.03), 1.0);\n"        \
    "        return;\n"                                                           \
    "    }\n"                                                                     \
    "    vec3 base = u_color;\n"                                                  \
    "    if (u_mode == 1) {\n"                                                    \
    "        vec2 cell = floor(v_world.xz * 0.5);\n"                              \
    "        base *= mix(0.62, 1.0, mod(cell.x + cell.y, 2.0));\n"                \
    "    }\n"                                                                     \
    "    vec3 n = normalize(v_nrm);\n"                                            \
    "    float diffuse = max(dot(n, normalize(light_dir.xyz)), 0.0);\n"           \
    "    frag_color = vec4(base * (0.3 + 0.7 * diffuse) * tint.rgb, 1.0);\n"      \
    "}\n"

static const char vs_text[] = VS_BODY "#error past the explicit length: must not be compiled\n";
static const char fs_text[] = FS_BODY "#error past the explicit length: must not be compiled\n";

static GLuint compile_shader(GLenum type, const char *body, GLint body_len, const char *what)
{
    const GLchar *strings[2] = {GLSL_VERSION_LINE, body};
    const GLint lengths[2] = {-1, body_len};
    GLuint s = gl.CreateShader(type);
    GLint ok = GL_FALSE;
    gl.ShaderSource(s, 2, strings, lengths);
    gl.CompileShader(s);
    gl.GetShaderiv(s, GL_COMPILE_STATUS, &ok);
    if (ok != GL_TRUE) {
        GLint n = 0;
        char *log;
        gl.GetShaderiv(s, GL_INFO_LOG_LENGTH, &n);
        log = calloc((size_t)(n > 1 ? n : 1), 1);
        gl.GetShaderInfoLog(s, n > 1 ? n : 1, NULL, log);
        fprintf(stderr, "%s: %s shader does not compile:\n%s\n", PROG, what, log);
        free(log);
        exit(1);
    }
    return s;
}

static GLuint build_program(void)
{
    GLuint vs = compile_shader(GL_VERTEX_SHADER, vs_text, (GLint)(sizeof(VS_BODY) - 1), "vertex");
    GLuint fs = compile_shader(GL_FRAGMENT_SHADER, fs_text, (GLint)(sizeof(FS_BODY) - 1), "fragment");
    GLuint prog = gl.CreateProgram();
    GLint ok = GL_FALSE;
    gl.AttachShader(prog, vs);
    gl.AttachShader(prog, fs);
    gl.LinkProgram(prog);
    gl.GetProgramiv(prog, GL_LINK_STATUS, &ok);
    if (ok != GL_TRUE) {
        GLint n = 0;
        char *log;
        gl.GetProgramiv(prog, GL_INFO_LOG_LENGTH, &n);
        log = calloc((size_t)(n > 1 ? n : 1), 1);
        gl.GetProgramInfoLog(prog, n > 1 ? n : 1, NULL, log);
        fprintf(stderr, "%s: program does not link:\n%s\n", PROG, log);
        free(log);
        exit(1);
    }
    gl.DetachShader(prog, vs);
    gl.DetachShader(prog, fs);
    gl.DeleteShader(vs);
    gl.DeleteShader(fs);
    return prog;
}

/* Layout of the std140 block "Camera" (mat4 = 4 vec4 columns, vec4 aligned to 16). */
struct camera_block {
    GLfloat view[16];
    GLfloat proj[16];
    GLfloat light_dir[4];
    GLfloat tint[4];
};

static struct {
    GLint model, normal, color, mode, screen;
} loc;

enum { MODE_LIT = 0, MODE_GROUND = 1, MODE_SCREEN = 2 };

static GLint uniform_location(GLuint prog, const char *name)
{
    GLint l = gl.GetUniformLocation(prog, name);
    if (l < 0) {
        fprintf(stderr, "%s: glGetUniformLocation(\"%s\") = %d\n", PROG, name, l);
        exit(1);
    }
    return l;
}

/* ---------------------------------------------------------------- misc */

static void check_gl_errors(int frame)
{
    GLenum e;
    int bad = 0;
    while ((e = glGetError()) != GL_NO_ERROR) {
        fprintf(stderr, "%s: GL error 0x%04x in frame %d\n", PROG, e, frame);
        bad = 1;
    }
    if (bad)
        exit(1);
}

static Bool wait_for_map(Display *d, XEvent *e, XPointer arg)
{
    (void)d;
    return e->type == MapNotify && e->xmap.window == *(Window *)arg;
}

static int has_extension(const char *list, const char *name)
{
    size_t n = strlen(name);
    const char *p = list;
    if (list == NULL)
        return 0;
    while ((p = strstr(p, name)) != NULL) {
        if ((p == list || p[-1] == ' ') && (p[n] == ' ' || p[n] == '\0'))
            return 1;
        p += n;
    }
    return 0;
}

static int x_error_seen;
static int on_x_error(Display *d, XErrorEvent *e)
{
    (void)d;
    x_error_seen = e->error_code;
    return 0;
}

/* --offscreen: the program that shows the scene's texture in the window, or a solid colour */
#define PRESENT_VS "out vec2 v_uv;\n" \
    "void main() {\n" \
    "    vec2 p = vec2(gl_VertexID == 1 ? 3.0 : -1.0, gl_VertexID == 2 ? 3.0 : -1.0);\n" \
    "    v_uv = 0.5 * p + 0.5;\n" \
    "    gl_Position = vec4(p, 0.0, 1.0);\n" \
    "}\n"
#define PRESENT_FS "uniform sampler2D u_image;\n" \
    "uniform vec4 u_solid;\n" \
    "in vec2 v_uv;\n" \
    "out vec4 frag_color;\n" \
    "void main() {\n" \
    "    frag_color = u_solid.a > 0.0 ? u_solid : texture(u_image, v_uv);\n" \
    "}\n"
#define HUD_X 8
#define HUD_Y 8
#define HUD_W 96
#define HUD_H 24
#define HUD_COLOR 0.9f, 0.2f, 0.15f, 1.0f

static GLuint build_present_program(void)
{
    GLuint vs = compile_shader(GL_VERTEX_SHADER, PRESENT_VS, (GLint)(sizeof(PRESENT_VS) - 1), "present vertex");
    GLuint fs = compile_shader(GL_FRAGMENT_SHADER, PRESENT_FS, (GLint)(sizeof(PRESENT_FS) - 1), "present fragment");
    GLuint p = gl.CreateProgram();
    GLint ok = GL_FALSE;
    gl.AttachShader(p, vs);
    gl.AttachShader(p, fs);
    gl.LinkProgram(p);
    gl.GetProgramiv(p, GL_LINK_STATUS, &ok);
    if (ok != GL_TRUE) {
        fprintf(stderr, "%s: the present program does not link\n", PROG);
        exit(1);
    }
    gl.DeleteShader(vs);
    gl.DeleteShader(fs);
    return p;
}

/* ---------------------------------------------------------------- drawing */

#define FBO_W 256
#define FBO_H 192

/* Monitor: the screen quad faces +z rotated by MONITOR_YAW about y, in front of a dark
 * frame box standing on a post. */
#define MONITOR_X (-3.4f)
#define MONITOR_Z (-3.4f)
#define MONITOR_Y 2.1f
#define MONITOR_YAW 45.0f
#define SCREEN_W 2.8f
#define SCREEN_H (SCREEN_W * (float)FBO_H / (float)FBO_W)

struct box {
    float pos[3], yaw, size[3], color[3];
};

static const struct box boxes[] = {
    /* orange crate, wide and low */
    {{2.5f, 0.5f, -0.5f}, -35.0f, {2.0f, 1.0f, 1.2f}, {0.95f, 0.55f, 0.15f}},
    /* tall green pillar */
    {{1.0f, 1.0f, 2.5f}, 10.0f, {0.8f, 2.0f, 0.8f}, {0.3f, 0.75f, 0.35f}},
    /* blue cube */
    {{-1.6f, 0.6f, 1.4f}, 30.0f, {1.2f, 1.2f, 1.2f}, {0.3f, 0.45f, 0.9f}},
    /* monitor post and frame */
    {{MONITOR_X, 0.5f * (MONITOR_Y - 0.5f * SCREEN_H), MONITOR_Z}, MONITOR_YAW,
     {0.25f, MONITOR_Y - 0.5f * SCREEN_H, 0.25f}, {0.35f, 0.35f, 0.38f}},
    {{MONITOR_X, MONITOR_Y, MONITOR_Z}, MONITOR_YAW, {SCREEN_W + 0.3f, SCREEN_H + 0.3f, 0.2f},
     {0.18f, 0.18f, 0.2f}},
};

static void set_model(const mat4 *model)
{
    float nm[9];
    m4_normal_matrix(model, nm);
    gl.UniformMatrix4fv(loc.model, 1, GL_FALSE, model->m);
    gl.UniformMatrix3fv(loc.normal, 1, GL_FALSE, nm);
}

static void upload_camera(GLuint ubo, const mat4 *view, const mat4 *proj, const float tint[3])
{
    struct camera_block cb;
    const float l[3] = {0.45f, 1.0f, 0.35f};
    memcpy(cb.view, view->m, sizeof cb.view);
    memcpy(cb.proj, proj->m, sizeof cb.proj);
    cb.light_dir[0] = l[0];
    cb.light_dir[1] = l[1];
    cb.light_dir[2] = l[2];
    cb.light_dir[3] = 0.0f;
    cb.tint[0] = tint[0];
    cb.tint[1] = tint[1];
    cb.tint[2] = tint[2];
    cb.tint[3] = 1.0f;
    gl.BindBuffer(GL_UNIFORM_BUFFER, ubo);
    gl.BufferSubData(GL_UNIFORM_BUFFER, 0, (GLsizeiptr)sizeof cb, &cb);
}

/* --painter: the window pass draws everything after the ground with the depth test off, in
 * order, as programs that paint their scene back to front do (glmark2's ideas scene). */
static int painter;
static int offscreen, dim, hud_vao_mode;

/* Draws ground, boxes and the floating box; the monitor screen only when screen_tex != 0
 * (never in the pass that renders into that texture). */
static void draw_scene(GLuint vao_static, GLuint vao_dynamic, GLuint screen_tex)
{
    const mat4 ident = m4_identity();
    size_t i;

    gl.BindVertexArray(vao_static);

    /* ground */
    set_model(&ident);
    gl.Uniform1i(loc.mode, MODE_GROUND);
    gl.Uniform3f(loc.color, 0.82f, 0.84f, 0.74f);
    glDrawElements(GL_TRIANGLES, QUAD_INDICES, GL_UNSIGNED_SHORT,
                   (const void *)(GROUND_FIRST_INDEX * sizeof(GLushort)));
    if (painter && screen_tex != 0)
        glDisable(GL_DEPTH_TEST);

    /* boxes: base of each at its pos minus half its height is on the ground */
    gl.Uniform1i(loc.mode, MODE_LIT);
    for (i = 0; i < sizeof boxes / sizeof boxes[0]; i++) {
        const struct box *b = &boxes[i];
        mat4 m = m4_mul(m4_translate(b->pos[0], b->pos[1], b->pos[2]),
                        m4_mul(m4_rotate_y(b->yaw), m4_scale(b->size[0], b->size[1], b->size[2])));
        set_model(&m);
        gl.Uniform3f(loc.color, b->color[0], b->color[1], b->color[2]);
        glDrawElements(GL_TRIANGLES, CUBE_INDICES, GL_UNSIGNED_SHORT, (const void *)0);
    }

    /* monitor screen, just in front of the frame box */
    if (screen_tex != 0) {
        mat4 m = m4_mul(m4_translate(MONITOR_X, MONITOR_Y, MONITOR_Z),
                        m4_mul(m4_rotate_y(MONITOR_YAW),
                               m4_mul(m4_translate(0.0f, 0.0f, 0.11f),
                                      m4_scale(SCREEN_W, SCREEN_H, 1.0f))));
        set_model(&m);
        gl.Uniform1i(loc.mode, MODE_SCREEN);
        glBindTexture(GL_TEXTURE_2D, screen_tex);
        glDrawElements(GL_TRIANGLES, QUAD_INDICES, GL_UNSIGNED_SHORT,
                       (const void *)(SCREEN_FIRST_INDEX * sizeof(GLushort)));
        glBindTexture(GL_TEXTURE_2D, 0);
    }

    /* floating box: vertices already in world space, rewritten every frame */
    gl.BindVertexArray(vao_dynamic);
    set_model(&ident);
    gl.Uniform1i(loc.mode, MODE_LIT);
    gl.Uniform3f(loc.color, 0.8f, 0.2f, 0.6f);
    glDrawElements(GL_TRIANGLES, CUBE_INDICES, GL_UNSIGNED_SHORT, (const void *)0);
    gl.BindVertexArray(0);
    if (painter)
        glEnable(GL_DEPTH_TEST);
}

/* Orbiting camera like ff_scene's: 'dist' from (0, 1, 0), pitched down, yaw in degrees. */
static mat4 orbit_view(float dist, float pitch, float yaw)
{
    return m4_mul(m4_translate(0.0f, 0.0f, -dist),
                  m4_mul(m4_rotate_x(pitch), m4_mul(m4_rotate_y(-yaw), m4_translate(0.0f, -1.0f, 0.0f))));
}

static void setup_vao(GLuint vao, GLuint vbo, GLuint ebo)
{
    gl.BindVertexArray(vao);
    gl.BindBuffer(GL_ARRAY_BUFFER, vbo);
    gl.BindBuffer(GL_ELEMENT_ARRAY_BUFFER, ebo);
    gl.EnableVertexAttribArray(0);
    gl.VertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, (GLsizei)sizeof(struct vertex),
                           (const void *)0);
    gl.EnableVertexAttribArray(1);
    gl.VertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, (GLsizei)sizeof(struct vertex),
                           (const void *)(3 * sizeof(GLfloat)));
    gl.BindVertexArray(0);
}

/* ---------------------------------------------------------------- main */

int main(int argc, char **argv)
{
    struct app_args args;
    Display *dpy;
    GLXFBConfig *configs;
    XVisualInfo *vi;
    Colormap cmap;
    XSetWindowAttributes swa;
    Window win;
    XEvent ev;
    GLXContext ctx;
    PFNGLXCREATECONTEXTATTRIBSARBPROC create_context_attribs;
    int (*old_handler)(Display *, XErrorEvent *);
    int glx_major = 0, glx_minor = 0, nconfigs = 0, frame;
    GLuint prog, bufs[4], vaos[2], tex, rbo, fbo, block;
    GLuint scene_tex = 0, scene_depth = 0, scene_fbo = 0, present = 0, empty_vao = 0, hud_vao = 0, hud_ebo = 0;
    GLint present_solid = -1;
    GLint block_size = 0;
    GLenum status;
    unsigned char *shot = NULL;
    mat4 proj_main, proj_fbo, view_fbo;
    const float tint_main[3] = {1.0f, 1.0f, 1.0f}, tint_fbo[3] = {0.85f, 1.0f, 0.9f};
    static struct vertex floating[CUBE_VERTS];
    const int fb_attribs[] = {GLX_X_RENDERABLE, True,
                              GLX_DRAWABLE_TYPE, GLX_WINDOW_BIT,
                              GLX_RENDER_TYPE, GLX_RGBA_BIT,
                              GLX_X_VISUAL_TYPE, GLX_TRUE_COLOR,
                              GLX_RED_SIZE, 8,
                              GLX_GREEN_SIZE, 8,
                              GLX_BLUE_SIZE, 8,
                              GLX_DEPTH_SIZE, 24,
                              GLX_STENCIL_SIZE, 8,
                              GLX_DOUBLEBUFFER, True,
                              None};
    const int ctx_attribs[] = {GLX_CONTEXT_MAJOR_VERSION_ARB, 3,
                               GLX_CONTEXT_MINOR_VERSION_ARB, 3,
                               GLX_CONTEXT_PROFILE_MASK_ARB, GLX_CONTEXT_CORE_PROFILE_BIT_ARB,
                               None};

    painter = app_take_flag(&argc, &argv, "--painter");
    offscreen = app_take_flag(&argc, &argv, "--offscreen");
    dim = offscreen && app_take_flag(&argc, &argv, "--dim");
    hud_vao_mode = offscreen && app_take_flag(&argc, &argv, "--hud-vao");
    app_parse_args(PROG, argc, argv, &args);

    dpy = XOpenDisplay(NULL);
    if (dpy == NULL) {
        fprintf(stderr, "%s: cannot open X display\n", PROG);
        return 1;
    }
    if (!glXQueryVersion(dpy, &glx_major, &glx_minor) || glx_major < 1 ||
        (glx_major == 1 && glx_minor < 3)) {
        fprintf(stderr, "%s: GLX 1.3 needed, have %d.%d\n", PROG, glx_major, glx_minor);
        return 1;
    }
    if (!has_extension(glXQueryExtensionsString(dpy, DefaultScreen(dpy)),
                       "GLX_ARB_create_context_profile")) {
        fprintf(stderr, "%s: GLX_ARB_create_context_profile missing\n", PROG);
        return 1;
    }
    configs = glXChooseFBConfig(dpy, DefaultScreen(dpy), fb_attribs, &nconfigs);
    if (configs == NULL || nconfigs < 1) {
        fprintf(stderr, "%s: glXChooseFBConfig: no RGBA8 double-buffered config with depth 24 "
                        "and stencil 8\n", PROG);
        return 1;
    }
    vi = glXGetVisualFromFBConfig(dpy, configs[0]);
    if (vi == NULL) {
        fprintf(stderr, "%s: glXGetVisualFromFBConfig failed\n", PROG);
        return 1;
    }
    cmap = XCreateColormap(dpy, RootWindow(dpy, vi->screen), vi->visual, AllocNone);
    memset(&swa, 0, sizeof swa);
    swa.colormap = cmap;
    swa.event_mask = StructureNotifyMask | ExposureMask;
    win = XCreateWindow(dpy, RootWindow(dpy, vi->screen), 0, 0, (unsigned)args.width,
                        (unsigned)args.height, 0, vi->depth, InputOutput, vi->visual,
                        CWColormap | CWEventMask, &swa);
    XStoreName(dpy, win, "glcast core_scene");
    XMapWindow(dpy, win);
    XIfEvent(dpy, &ev, wait_for_map, (XPointer)&win);

    create_context_attribs = (PFNGLXCREATECONTEXTATTRIBSARBPROC)glXGetProcAddressARB(
        (const GLubyte *)"glXCreateContextAttribsARB");
    if (create_context_attribs == NULL) {
        fprintf(stderr, "%s: glXGetProcAddressARB(\"glXCreateContextAttribsARB\") returned NULL\n",
                PROG);
        return 1;
    }
    /* a refused version/profile is reported as an X error: catch it instead of dying */
    XSync(dpy, False);
    old_handler = XSetErrorHandler(on_x_error);
    ctx = create_context_attribs(dpy, configs[0], NULL, True, ctx_attribs);
    XSync(dpy, False);
    XSetErrorHandler(old_handler);
    if (ctx == NULL || x_error_seen) {
        fprintf(stderr, "%s: glXCreateContextAttribsARB(3.3 core) failed (X error %d)\n", PROG,
                x_error_seen);
        return 1;
    }
    if (!glXMakeCurrent(dpy, win, ctx)) {
        fprintf(stderr, "%s: glXMakeCurrent failed\n", PROG);
        return 1;
    }

    printf("%s: GL_RENDERER %s\n", PROG, (const char *)glGetString(GL_RENDERER));
    printf("%s: GL_VERSION %s\n", PROG, (const char *)glGetString(GL_VERSION));
    fflush(stdout);
    load_gl();

    build_geometry();
    build_floating_box(0, floating);

    /* shaders and uniforms */
    prog = build_program();
    gl.UseProgram(prog);
    loc.model = uniform_location(prog, "u_model");
    loc.normal = uniform_location(prog, "u_normal");
    loc.color = uniform_location(prog, "u_color");
    loc.mode = uniform_location(prog, "u_mode");
    loc.screen = uniform_location(prog, "u_screen");
    gl.Uniform1i(loc.screen, 0);

    /* buffers: static vertices, elements, floating box vertices, camera block */
    gl.GenBuffers(4, bufs);
    app_print_names(PROG, "glGenBuffers", bufs, 4);
    gl.BindBuffer(GL_ARRAY_BUFFER, bufs[0]);
    gl.BufferData(GL_ARRAY_BUFFER, (GLsizeiptr)sizeof static_verts, static_verts, GL_STATIC_DRAW);
    gl.BindBuffer(GL_ARRAY_BUFFER, bufs[2]);
    gl.BufferData(GL_ARRAY_BUFFER, (GLsizeiptr)sizeof floating, floating, GL_DYNAMIC_DRAW);
    gl.BindBuffer(GL_ARRAY_BUFFER, 0);

    gl.GenVertexArrays(2, vaos);
    app_print_names(PROG, "glGenVertexArrays", vaos, 2);
    /* the element buffer binding is VAO state: upload it with the first VAO bound */
    gl.BindVertexArray(vaos[0]);
    gl.BindBuffer(GL_ELEMENT_ARRAY_BUFFER, bufs[1]);
    gl.BufferData(GL_ELEMENT_ARRAY_BUFFER, (GLsizeiptr)sizeof indices, indices, GL_STATIC_DRAW);
    gl.BindVertexArray(0);
    setup_vao(vaos[0], bufs[0], bufs[1]);
    setup_vao(vaos[1], bufs[2], bufs[1]);

    /* uniform block */
    block = gl.GetUniformBlockIndex(prog, "Camera");
    if (block == GL_INVALID_INDEX) {
        fprintf(stderr, "%s: glGetUniformBlockIndex(\"Camera\") = GL_INVALID_INDEX\n", PROG);
        return 1;
    }
    gl.GetActiveUniformBlockiv(prog, block, GL_UNIFORM_BLOCK_DATA_SIZE, &block_size);
    if (block_size != (GLint)sizeof(struct camera_block)) {
        fprintf(stderr, "%s: uniform block Camera is %d bytes, expected %u\n", PROG, block_size,
                (unsigned)sizeof(struct camera_block));
        return 1;
    }
    gl.UniformBlockBinding(prog, block, 0);
    gl.BindBuffer(GL_UNIFORM_BUFFER, bufs[3]);
    gl.BufferData(GL_UNIFORM_BUFFER, (GLsizeiptr)sizeof(struct camera_block), NULL, GL_DYNAMIC_DRAW);
    gl.BindBufferBase(GL_UNIFORM_BUFFER, 0, bufs[3]);

    /* render target: RGBA8 texture (mipmapped after each pass) + depth/stencil renderbuffer */
    glGenTextures(1, &tex);
    app_print_names(PROG, "glGenTextures", &tex, 1);
    gl.ActiveTexture(GL_TEXTURE0);
    glBindTexture(GL_TEXTURE_2D, tex);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_LINEAR);
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, FBO_W, FBO_H, 0, GL_RGBA, GL_UNSIGNED_BYTE, NULL);
    gl.GenerateMipmap(GL_TEXTURE_2D);
    glBindTexture(GL_TEXTURE_2D, 0);

    gl.GenRenderbuffers(1, &rbo);
    app_print_names(PROG, "glGenRenderbuffers", &rbo, 1);
    gl.BindRenderbuffer(GL_RENDERBUFFER, rbo);
    gl.RenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH24_STENCIL8, FBO_W, FBO_H);
    gl.BindRenderbuffer(GL_RENDERBUFFER, 0);

    gl.GenFramebuffers(1, &fbo);
    app_print_names(PROG, "glGenFramebuffers", &fbo, 1);
    gl.BindFramebuffer(GL_FRAMEBUFFER, fbo);
    gl.FramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, tex, 0);
    gl.FramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_STENCIL_ATTACHMENT, GL_RENDERBUFFER, rbo);
    status = gl.CheckFramebufferStatus(GL_FRAMEBUFFER);
    if (status != GL_FRAMEBUFFER_COMPLETE) {
        fprintf(stderr, "%s: glCheckFramebufferStatus = 0x%04x, not GL_FRAMEBUFFER_COMPLETE\n",
                PROG, status);
        return 1;
    }
    gl.BindFramebuffer(GL_FRAMEBUFFER, 0);

    if (offscreen) {
        glGenTextures(1, &scene_tex);
        glBindTexture(GL_TEXTURE_2D, scene_tex);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
        glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, args.width, args.height, 0, GL_RGBA, GL_UNSIGNED_BYTE, NULL);
        glBindTexture(GL_TEXTURE_2D, 0);
        gl.GenRenderbuffers(1, &scene_depth);
        gl.BindRenderbuffer(GL_RENDERBUFFER, scene_depth);
        gl.RenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT24, args.width, args.height);
        gl.BindRenderbuffer(GL_RENDERBUFFER, 0);
        gl.GenFramebuffers(1, &scene_fbo);
        gl.BindFramebuffer(GL_FRAMEBUFFER, scene_fbo);
        gl.FramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, scene_tex, 0);
        gl.FramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, scene_depth);
        if (gl.CheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) {
            fprintf(stderr, "%s: the scene framebuffer is incomplete\n", PROG);
            return 1;
        }
        gl.BindFramebuffer(GL_FRAMEBUFFER, 0);
        present = build_present_program();
        present_solid = uniform_location(present, "u_solid");
        gl.GenVertexArrays(1, &empty_vao);
        if (hud_vao_mode) {
            static const GLushort hud_indices[6] = {9, 9, 9, 0, 1, 2};
            gl.GenVertexArrays(1, &hud_vao);
            gl.BindVertexArray(hud_vao);
            gl.GenBuffers(1, &hud_ebo);
            gl.BindBuffer(GL_ELEMENT_ARRAY_BUFFER, hud_ebo);
            gl.BufferData(GL_ELEMENT_ARRAY_BUFFER, sizeof hud_indices, hud_indices, GL_STATIC_DRAW);
            gl.BindVertexArray(0);
        }
        gl.UseProgram(prog);
    }

    /* fixed state */
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glEnable(GL_CULL_FACE);
    glCullFace(GL_BACK);
    glFrontFace(GL_CCW);
    check_gl_errors(-1);

    proj_main = m4_perspective(45.0f, (float)args.width / (float)args.height, 0.5f, 100.0f);
    proj_fbo = m4_perspective(50.0f, (float)FBO_W / (float)FBO_H, 0.5f, 100.0f);
    /* the monitor's camera: high, from behind on the right (the main camera orbits in front) */
    view_fbo = orbit_view(12.0f, 42.0f, 140.0f);

    printf("%s: frames %d\n", PROG, args.frames);
    fflush(stdout);

    for (frame = 0; frame < args.frames; frame++) {
        mat4 view_main = orbit_view(13.0f, 30.0f, 20.0f + 0.5f * (float)frame);
        void *map;

        while (XPending(dpy) > 0)
            XNextEvent(dpy, &ev);

        if (hud_vao_mode)  /* (into the vertex-array object 0: bound now) */
            gl.BindBuffer(GL_ELEMENT_ARRAY_BUFFER, bufs[1]);
        /* floating box vertices for this frame, through a mapped range */
        build_floating_box(frame, floating);
        gl.BindBuffer(GL_ARRAY_BUFFER, bufs[2]);
        map = gl.MapBufferRange(GL_ARRAY_BUFFER, 0, (GLsizeiptr)sizeof floating,
                                GL_MAP_WRITE_BIT | GL_MAP_INVALIDATE_RANGE_BIT);
        if (map == NULL) {
            fprintf(stderr, "%s: glMapBufferRange returned NULL in frame %d\n", PROG, frame);
            check_gl_errors(frame);
            return 1;
        }
        memcpy(map, floating, sizeof floating);
        if (gl.UnmapBuffer(GL_ARRAY_BUFFER) != GL_TRUE) {
            fprintf(stderr, "%s: glUnmapBuffer: buffer contents lost in frame %d\n", PROG, frame);
            return 1;
        }
        gl.BindBuffer(GL_ARRAY_BUFFER, 0);

        /* pass 1: the monitor's view into the texture */
        gl.BindFramebuffer(GL_FRAMEBUFFER, fbo);
        glViewport(0, 0, FBO_W, FBO_H);
        glClearColor(0.32f, 0.38f, 0.52f, 1.0f);
        glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT | GL_STENCIL_BUFFER_BIT);
        upload_camera(bufs[3], &view_fbo, &proj_fbo, tint_fbo);
        draw_scene(vaos[0], vaos[1], 0);
        gl.BindFramebuffer(GL_FRAMEBUFFER, 0);
        glBindTexture(GL_TEXTURE_2D, tex);
        gl.GenerateMipmap(GL_TEXTURE_2D);
        glBindTexture(GL_TEXTURE_2D, 0);

        /* pass 2: the window, or with --offscreen the scene's framebuffer object */
        if (offscreen)
            gl.BindFramebuffer(GL_FRAMEBUFFER, scene_fbo);
        glViewport(0, 0, args.width, args.height);
        glClearColor(0.53f, 0.75f, 0.95f, 1.0f);
        glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT | GL_STENCIL_BUFFER_BIT);
        upload_camera(bufs[3], &view_main, &proj_main, tint_main);
        draw_scene(vaos[0], vaos[1], tex);
        if (offscreen) {
            /* shown in the window, then the HUD over it */
            gl.BindFramebuffer(GL_FRAMEBUFFER, 0);
            glClear(GL_DEPTH_BUFFER_BIT);
            glDisable(GL_DEPTH_TEST);
            gl.UseProgram(present);
            gl.BindVertexArray(empty_vao);
            glBindTexture(GL_TEXTURE_2D, scene_tex);
            gl.Uniform4f(present_solid, 0.0f, 0.0f, 0.0f, 0.0f);
            glDrawArrays(GL_TRIANGLES, 0, 3);
            glBindTexture(GL_TEXTURE_2D, 0);
            if (dim) {
                glEnable(GL_BLEND);
                glBlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
                gl.Uniform4f(present_solid, 0.0f, 0.0f, 0.0f, 0.27f);
                glDrawArrays(GL_TRIANGLES, 0, 3);
                glDisable(GL_BLEND);
            }
            glViewport(HUD_X, HUD_Y, HUD_W, HUD_H);
            gl.Uniform4f(present_solid, HUD_COLOR);
            if (hud_vao_mode) {
                gl.BindVertexArray(hud_vao);
                glDrawElements(GL_TRIANGLES, 3, GL_UNSIGNED_SHORT, (const void *)(3 * sizeof(GLushort)));
            } else {
                glDrawArrays(GL_TRIANGLES, 0, 3);
            }
            gl.BindVertexArray(0);
            gl.UseProgram(prog);
            glEnable(GL_DEPTH_TEST);
            glViewport(0, 0, args.width, args.height);
        }

        if (frame == args.frames - 1 && args.screenshot != NULL) {
            shot = malloc((size_t)args.width * (size_t)args.height * 3u);
            glReadBuffer(GL_BACK);
            glPixelStorei(GL_PACK_ALIGNMENT, 1);
            glReadPixels(0, 0, args.width, args.height, GL_RGB, GL_UNSIGNED_BYTE, shot);
        }
        check_gl_errors(frame);
        glXSwapBuffers(dpy, win);
    }

    gl.UseProgram(0);
    gl.BindBuffer(GL_UNIFORM_BUFFER, 0);
    gl.DeleteFramebuffers(1, &fbo);
    gl.DeleteRenderbuffers(1, &rbo);
    glDeleteTextures(1, &tex);
    gl.DeleteVertexArrays(2, vaos);
    gl.DeleteBuffers(4, bufs);
    gl.DeleteProgram(prog);
    check_gl_errors(args.frames);
    glXMakeCurrent(dpy, None, NULL);
    glXDestroyContext(dpy, ctx);
    XDestroyWindow(dpy, win);
    XFreeColormap(dpy, cmap);
    XFree(vi);
    XFree(configs);
    XCloseDisplay(dpy);

    if (shot != NULL) {
        if (app_write_ppm(args.screenshot, args.width, args.height, shot) != 0) {
            fprintf(stderr, "%s: cannot write screenshot '%s'\n", PROG, args.screenshot);
            free(shot);
            return 1;
        }
        free(shot);
    }
    return 0;
}
