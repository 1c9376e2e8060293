/*
 * glfw_dynamic.c - glcast test app: GLFW 3 window with an OpenGL 2.1 context, and no link
 * to libGL at all. GLFW dlopens libGL itself; every GL function this program calls, from
 * glClear up, comes from glfwGetProcAddress into the program's own pointer table. A capture
 * layer that only interposes the symbols an executable links against sees nothing here.
 *
 * Scene (deterministic, driven by the frame index only): a rotating six-pointed star drawn
 * as a triangle fan from a vertex buffer object (interleaved float xy + ubyte rgba, with
 * glVertexPointer/glColorPointer at byte offsets 0 and 8), and a small square circling it,
 * drawn with glDrawArrays from client-side arrays that change every frame.
 * glfwSwapInterval(0), frames end at glfwSwapBuffers.
 *
 * Prints to stdout:
 *   glfw_dynamic: GL_RENDERER <string>
 *   glfw_dynamic: GL_VERSION <string>
 *   glfw_dynamic: glGenBuffers -> <vbo>
 *   glfw_dynamic: frames <N>
 */
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
/* types, enums and the PFN...PROC typedefs of GL 1.2+ only; no gl* symbol is referenced */
#include <GL/gl.h>
#include <GL/glext.h>
#include <math.h>

#include "app_common.h"

static const char *PROG = "glfw_dynamic";

/* ---------------------------------------------------------------- GL entry points */

/* glext.h has no PFN types for GL 1.0/1.1: our own */
typedef const GLubyte *(APIENTRYP APP_PFNGLGETSTRINGPROC)(GLenum name);
typedef GLenum(APIENTRYP APP_PFNGLGETERRORPROC)(void);
typedef void(APIENTRYP APP_PFNGLVIEWPORTPROC)(GLint x, GLint y, GLsizei width, GLsizei height);
typedef void(APIENTRYP APP_PFNGLCLEARCOLORPROC)(GLclampf r, GLclampf g, GLclampf b, GLclampf a);
typedef void(APIENTRYP APP_PFNGLCLEARPROC)(GLbitfield mask);
typedef void(APIENTRYP APP_PFNGLMATRIXMODEPROC)(GLenum mode);
typedef void(APIENTRYP APP_PFNGLLOADIDENTITYPROC)(void);
typedef void(APIENTRYP APP_PFNGLORTHOPROC)(GLdouble left, GLdouble right, GLdouble bottom,
                                           GLdouble top, GLdouble znear, GLdouble zfar);
typedef void(APIENTRYP APP_PFNGLROTATEFPROC)(GLfloat angle, GLfloat x, GLfloat y, GLfloat z);
typedef void(APIENTRYP APP_PFNGLENABLECLIENTSTATEPROC)(GLenum cap);
typedef void(APIENTRYP APP_PFNGLDISABLECLIENTSTATEPROC)(GLenum cap);
typedef void(APIENTRYP APP_PFNGLVERTEXPOINTERPROC)(GLint size, GLenum type, GLsizei stride,
                                                   const void *ptr);
typedef void(APIENTRYP APP_PFNGLCOLORPOINTERPROC)(GLint size, GLenum type, GLsizei stride,
                                                  const void *ptr);
typedef void(APIENTRYP APP_PFNGLDRAWARRAYSPROC)(GLenum mode, GLint first, GLsizei count);
typedef void(APIENTRYP APP_PFNGLREADBUFFERPROC)(GLenum mode);
typedef void(APIENTRYP APP_PFNGLPIXELSTOREIPROC)(GLenum pname, GLint param);
typedef void(APIENTRYP APP_PFNGLREADPIXELSPROC)(GLint x, GLint y, GLsizei width, GLsizei height,
                                                GLenum format, GLenum type, void *pixels);

#define DYN_GL_FUNCS(F)                                      \
    F(APP_PFNGLGETSTRINGPROC, GetString)                     \
    F(APP_PFNGLGETERRORPROC, GetError)                       \
    F(APP_PFNGLVIEWPORTPROC, Viewport)                       \
    F(APP_PFNGLCLEARCOLORPROC, ClearColor)                   \
    F(APP_PFNGLCLEARPROC, Clear)                             \
    F(APP_PFNGLMATRIXMODEPROC, MatrixMode)                   \
    F(APP_PFNGLLOADIDENTITYPROC, LoadIdentity)               \
    F(APP_PFNGLORTHOPROC, Ortho)                             \
    F(APP_PFNGLROTATEFPROC, Rotatef)                         \
    F(APP_PFNGLENABLECLIENTSTATEPROC, EnableClientState)     \
    F(APP_PFNGLDISABLECLIENTSTATEPROC, DisableClientState)   \
    F(APP_PFNGLVERTEXPOINTERPROC, VertexPointer)             \
    F(APP_PFNGLCOLORPOINTERPROC, ColorPointer)               \
    F(APP_PFNGLDRAWARRAYSPROC, DrawArrays)                   \
    F(APP_PFNGLREADBUFFERPROC, ReadBuffer)                   \
    F(APP_PFNGLPIXELSTOREIPROC, PixelStorei)                 \
    F(APP_PFNGLREADPIXELSPROC, ReadPixels)                   \
    F(PFNGLGENBUFFERSPROC, GenBuffers)                       \
    F(PFNGLDELETEBUFFERSPROC, DeleteBuffers)                 \
    F(PFNGLBINDBUFFERPROC, BindBuffer)                       \
    F(PFNGLBUFFERDATAPROC, BufferData)

static struct {
#define F(type, name) type name;
    DYN_GL_FUNCS(F)
#undef F
} gl;

/* Needs a current context. A NULL pointer is fatal. */
static void load_gl(void)
{
    int missing = 0;
#define F(type, name)                                                                   \
    gl.name = (type)glfwGetProcAddress("gl" #name);                                     \
    if (gl.name == NULL) {                                                              \
        fprintf(stderr, "%s: glfwGetProcAddress(\"gl%s\") returned NULL\n", PROG, #name); \
        missing = 1;                                                                    \
    }
    DYN_GL_FUNCS(F)
#undef F
    if (missing)
        exit(1);
}

/* ---------------------------------------------------------------- geometry */

struct star_vertex {
    GLfloat xy[2];
    GLubyte rgba[4];
};

/* Triangle fan: centre, then 12 rim points alternating outer/inner radius, closed. */
#define STAR_POINTS 12
#define STAR_VERTS (STAR_POINTS + 2)
static struct star_vertex star[STAR_VERTS];

static void build_star(void)
{
    static const GLubyte rim[6][3] = {{230, 60, 50},  {240, 200, 40}, {70, 200, 80},
                                      {50, 190, 220}, {70, 90, 230},  {200, 70, 210}};
    int i;
    star[0].xy[0] = star[0].xy[1] = 0.0f;
    star[0].rgba[0] = star[0].rgba[1] = star[0].rgba[2] = star[0].rgba[3] = 255;
    for (i = 0; i <= STAR_POINTS; i++) {
        int k = i % STAR_POINTS;
        float a = 2.0f * APP_PI * (float)k / STAR_POINTS + 0.5f * APP_PI;
        float r = (k % 2 == 0) ? 0.8f : 0.38f;
        struct star_vertex *v = &star[1 + i];
        v->xy[0] = r * cosf(a);
        v->xy[1] = r * sinf(a);
        memcpy(v->rgba, rim[k / 2], 3);
        if (k % 2 == 1) { /* inner points darker */
            v->rgba[0] = (GLubyte)(v->rgba[0] / 2);
            v->rgba[1] = (GLubyte)(v->rgba[1] / 2);
            v->rgba[2] = (GLubyte)(v->rgba[2] / 2);
        }
        v->rgba[3] = 255;
    }
}

/* Client-side arrays for the orbiting square: positions change every frame. */
static GLfloat sq_pos[4][2];
static const GLfloat sq_col[4][3] = {{1, 1, 1}, {1, 0.9f, 0.3f}, {1, 0.5f, 0.1f}, {1, 0.9f, 0.3f}};

static void build_square(int frame)
{
    static const float corner[4][2] = {{-1, -1}, {1, -1}, {-1, 1}, {1, 1}}; /* strip order */
    float a = -0.05f * (float)frame, cx = 0.88f * cosf(a), cy = 0.88f * sinf(a);
    float s = 0.07f + 0.02f * sinf(0.3f * (float)frame);
    int i;
    for (i = 0; i < 4; i++) {
        sq_pos[i][0] = cx + s * corner[i][0];
        sq_pos[i][1] = cy + s * corner[i][1];
    }
}

/* ---------------------------------------------------------------- misc */

static void check_gl_errors(int frame)
{
    GLenum e;
    int bad = 0;
    while ((e = gl.GetError()) != GL_NO_ERROR) {
        fprintf(stderr, "%s: GL error 0x%04x in frame %d\n", PROG, e, frame);
        bad = 1;
    }
    if (bad)
        exit(1);
}

static void on_glfw_error(int code, const char *what)
{
    fprintf(stderr, "%s: GLFW error 0x%x: %s\n", PROG, code, what);
}

/* ---------------------------------------------------------------- main */

int main(int argc, char **argv)
{
    struct app_args args;
    GLFWwindow *win;
    GLuint vbo;
    unsigned char *shot = NULL;
    double aspect;
    int frame;

    app_parse_args(PROG, argc, argv, &args);

    glfwSetErrorCallback(on_glfw_error);
    if (!glfwInit()) {
        fprintf(stderr, "%s: glfwInit failed\n", PROG);
        return 1;
    }
    glfwWindowHint(GLFW_CLIENT_API, GLFW_OPENGL_API);
    glfwWindowHint(GLFW_CONTEXT_CREATION_API, GLFW_NATIVE_CONTEXT_API);
    glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 2);
    glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 1);
    glfwWindowHint(GLFW_DOUBLEBUFFER, GLFW_TRUE);
    glfwWindowHint(GLFW_RESIZABLE, GLFW_FALSE);
    win = glfwCreateWindow(args.width, args.height, "glcast glfw_dynamic", NULL, NULL);
    if (win == NULL) {
        fprintf(stderr, "%s: glfwCreateWindow (OpenGL 2.1) failed\n", PROG);
        glfwTerminate();
        return 1;
    }
    glfwMakeContextCurrent(win);
    glfwSwapInterval(0);
    load_gl();

    printf("%s: GL_RENDERER %s\n", PROG, (const char *)gl.GetString(GL_RENDERER));
    printf("%s: GL_VERSION %s\n", PROG, (const char *)gl.GetString(GL_VERSION));
    fflush(stdout);

    build_star();
    gl.GenBuffers(1, &vbo);
    app_print_names(PROG, "glGenBuffers", &vbo, 1);
    gl.BindBuffer(GL_ARRAY_BUFFER, vbo);
    gl.BufferData(GL_ARRAY_BUFFER, (GLsizeiptr)sizeof star, star, GL_STATIC_DRAW);
    gl.BindBuffer(GL_ARRAY_BUFFER, 0);
    check_gl_errors(-1);

    printf("%s: frames %d\n", PROG, args.frames);
    fflush(stdout);

    aspect = (double)args.width / (double)args.height;
    for (frame = 0; frame < args.frames; frame++) {
        glfwPollEvents();

        gl.Viewport(0, 0, args.width, args.height);
        gl.ClearColor(0.08f, 0.1f, 0.16f, 1.0f);
        gl.Clear(GL_COLOR_BUFFER_BIT);
        gl.MatrixMode(GL_PROJECTION);
        gl.LoadIdentity();
        gl.Ortho(-aspect, aspect, -1.0, 1.0, -1.0, 1.0);
        gl.MatrixMode(GL_MODELVIEW);
        gl.LoadIdentity();

        gl.EnableClientState(GL_VERTEX_ARRAY);
        gl.EnableClientState(GL_COLOR_ARRAY);

        /* star from the VBO: pointers are byte offsets into it */
        gl.Rotatef(2.5f * (float)frame, 0.0f, 0.0f, 1.0f);
        gl.BindBuffer(GL_ARRAY_BUFFER, vbo);
        gl.VertexPointer(2, GL_FLOAT, (GLsizei)sizeof(struct star_vertex), (const void *)0);
        gl.ColorPointer(4, GL_UNSIGNED_BYTE, (GLsizei)sizeof(struct star_vertex),
                        (const void *)(2 * sizeof(GLfloat)));
        gl.DrawArrays(GL_TRIANGLE_FAN, 0, STAR_VERTS);
        gl.BindBuffer(GL_ARRAY_BUFFER, 0);

        /* orbiting square from client memory */
        gl.LoadIdentity();
        build_square(frame);
        gl.VertexPointer(2, GL_FLOAT, 0, sq_pos);
        gl.ColorPointer(3, GL_FLOAT, 0, sq_col);
        gl.DrawArrays(GL_TRIANGLE_STRIP, 0, 4);

        gl.DisableClientState(GL_COLOR_ARRAY);
        gl.DisableClientState(GL_VERTEX_ARRAY);

        if (frame == args.frames - 1 && args.screenshot != NULL) {
            shot = malloc((size_t)args.width * (size_t)args.height * 3u);
            gl.ReadBuffer(GL_BACK);
            gl.PixelStorei(GL_PACK_ALIGNMENT, 1);
            gl.ReadPixels(0, 0, args.width, args.height, GL_RGB, GL_UNSIGNED_BYTE, shot);
        }
        check_gl_errors(frame);
        glfwSwapBuffers(win);
    }

    gl.DeleteBuffers(1, &vbo);
    check_gl_errors(args.frames);
    glfwMakeContextCurrent(NULL);
    glfwDestroyWindow(win);
    glfwTerminate();

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
