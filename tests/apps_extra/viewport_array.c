/*
 * viewport_array.c - indexed viewports and scissor boxes (GL_ARB_viewport_array, GL 4.1
 * core), for the wall tests. Every frame draws one batch that a geometry shader with four
 * invocations sends to four viewports at once (gl_ViewportIndex = gl_InvocationID): each
 * viewport shows a background square in its own colour and a rotating triangle with coloured
 * corners, clipped by its own scissor box. The state is set with every indexed entry point:
 *
 *   viewport 0  glViewportIndexedf    10,  10, 180,  90  red     scissor 0   0,   0, 175, 240 (glScissorIndexed)
 *   viewport 1  glViewportIndexedfv  200,  20, 110, 150  green   scissor 1 215,   0, 105, 240 (glScissorIndexedv)
 *   viewport 2  glViewportArrayv      20, 110, 150, 120  blue    scissor 2  40,   0, 280, 240 (glScissorArrayv)
 *   viewport 3  glViewportArrayv     180, 180, 130,  55  yellow  scissor 3 150, 125, 170, 100 (glScissorArrayv)
 *
 * (window coordinates of the default 320x240 window; for another --size they scale with it).
 * On a 2x2 wall viewport 0 spans the vertical seam (x 160), viewport 1 the horizontal one
 * (y 120), viewport 2 both, viewport 3 lies on one tile. Each scissor box cuts one side of
 * its viewport, so a slave that maps viewports but not
 * scissor boxes (or the other way round), or maps neither, moves or clips the squares.
 * glViewport and glScissor (which set every index) come first in every frame.
 *
 * With --plain (a first argument) the same picture comes from four draws, each after
 * glViewport and glScissor with one region's rectangles, the shader writing viewport 0: a
 * control that shows what a slave that maps the indexed state must produce.
 *
 *   viewport_array [--plain] [--frames N] [--size WxH] [--screenshot PATH.ppm]
 */
#define GL_GLEXT_PROTOTYPES 1
#include <GL/gl.h>
#include <GL/glext.h>
#include <GL/glx.h>
#include <X11/Xlib.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../apps/app_common.h"
#include "glx_screenshot.h"

static const char *PROG = "viewport_array";

static const char *VS =
    "#version 410 core\n"
    "layout(location = 0) in vec2 pos;\n"
    "layout(location = 1) in vec3 col;\n"
    "uniform float u_angle;\n"
    "uniform float u_scale;\n"
    "out vec3 v_col;\n"
    "void main() {\n"
    "    float c = cos(u_angle), s = sin(u_angle);\n"
    "    v_col = col;\n"
    "    gl_Position = vec4(u_scale * mat2(c, s, -s, c) * pos, 0.0, 1.0);\n"
    "}\n";
static const char *GS =
    "#version 410 core\n"
    "layout(triangles, invocations = 4) in;\n"
    "layout(triangle_strip, max_vertices = 3) out;\n"
    "in vec3 v_col[];\n"
    "out vec3 g_col;\n"
    "flat out int g_view;\n"
    "uniform int u_only;\n"
    "void main() {\n"
    "    if (u_only >= 0 && gl_InvocationID != u_only) return;\n"
    "    for (int i = 0; i < 3; i++) {\n"
    "        gl_ViewportIndex = u_only >= 0 ? 0 : gl_InvocationID;\n"
    "        g_view = gl_InvocationID;\n"
    "        g_col = v_col[i];\n"
    "        gl_Position = gl_in[i].gl_Position;\n"
    "        EmitVertex();\n"
    "    }\n"
    "    EndPrimitive();\n"
    "}\n";
static const char *FS =
    "#version 410 core\n"
    "uniform vec3 u_tint[4];\n"
    "uniform int u_mode;\n"
    "in vec3 g_col;\n"
    "flat in int g_view;\n"
    "out vec4 o_color;\n"
    "void main() {\n"
    "    vec3 t = u_tint[g_view];\n"
    "    o_color = vec4(u_mode == 0 ? t : mix(g_col, t, 0.3), 1.0);\n"
    "}\n";

static GLuint shader(GLenum type, const char *src)
{
    GLuint s = glCreateShader(type);
    GLint ok = 0;
    glShaderSource(s, 1, &src, NULL);
    glCompileShader(s);
    glGetShaderiv(s, GL_COMPILE_STATUS, &ok);
    if (!ok) {
        char log[2048];
        glGetShaderInfoLog(s, sizeof log, NULL, log);
        fprintf(stderr, "%s: shader does not compile: %s\n", PROG, log);
        exit(1);
    }
    return s;
}

static int x_error_seen;
static int on_x_error(Display *d, XErrorEvent *e)
{
    (void)d;
    x_error_seen = e->error_code ? e->error_code : 1;
    return 0;
}

/* The squares, then the triangles; the geometry shader's invocation `only` alone, or all four. */
static void draw(GLint mode, GLint angle, GLint scale, GLint only, int index, int f)
{
    glUniform1i(only, index);
    glUniform1i(mode, 0);
    glUniform1f(angle, 0);
    glUniform1f(scale, 1);
    glDrawArrays(GL_TRIANGLES, 0, 6);
    glUniform1i(mode, 1);
    glUniform1f(angle, 0.15f * (float)f);
    glUniform1f(scale, 0.8f);
    glDrawArrays(GL_TRIANGLES, 6, 3);
}

int main(int argc, char **argv)
{
    struct app_args a;
    const int plain = app_take_flag(&argc, &argv, "--plain");
    app_parse_args(PROG, argc, argv, &a);
    Display *dpy = XOpenDisplay(NULL);
    if (!dpy) {
        fprintf(stderr, "%s: cannot open display\n", PROG);
        return 1;
    }
    const int fb_attribs[] = {GLX_X_RENDERABLE, True, GLX_DRAWABLE_TYPE, GLX_WINDOW_BIT, GLX_RENDER_TYPE, GLX_RGBA_BIT,
                              GLX_RED_SIZE, 8, GLX_GREEN_SIZE, 8, GLX_BLUE_SIZE, 8, GLX_DOUBLEBUFFER, True, None};
    int nconfigs = 0;
    GLXFBConfig *configs = glXChooseFBConfig(dpy, DefaultScreen(dpy), fb_attribs, &nconfigs);
    if (!configs || nconfigs < 1) {
        fprintf(stderr, "%s: no double-buffered RGB8 config\n", PROG);
        return 1;
    }
    XVisualInfo *vi = glXGetVisualFromFBConfig(dpy, configs[0]);
    XSetWindowAttributes swa;
    memset(&swa, 0, sizeof swa);
    swa.colormap = XCreateColormap(dpy, RootWindow(dpy, vi->screen), vi->visual, AllocNone);
    Window win = XCreateWindow(dpy, RootWindow(dpy, vi->screen), 0, 0, a.width, a.height, 0, vi->depth, InputOutput,
                               vi->visual, CWColormap, &swa);
    XMapWindow(dpy, win);
    PFNGLXCREATECONTEXTATTRIBSARBPROC create_context_attribs =
        (PFNGLXCREATECONTEXTATTRIBSARBPROC)glXGetProcAddressARB((const GLubyte *)"glXCreateContextAttribsARB");
    if (!create_context_attribs) {
        fprintf(stderr, "%s: glXCreateContextAttribsARB missing\n", PROG);
        return 1;
    }
    const int ctx_attribs[] = {GLX_CONTEXT_MAJOR_VERSION_ARB, 4, GLX_CONTEXT_MINOR_VERSION_ARB, 1,
                               GLX_CONTEXT_PROFILE_MASK_ARB, GLX_CONTEXT_CORE_PROFILE_BIT_ARB, None};
    XSync(dpy, False);
    int (*old_handler)(Display *, XErrorEvent *) = XSetErrorHandler(on_x_error);
    GLXContext ctx = create_context_attribs(dpy, configs[0], NULL, True, ctx_attribs);
    XSync(dpy, False);
    XSetErrorHandler(old_handler);
    if (!ctx || x_error_seen) {
        fprintf(stderr, "%s: no GL 4.1 core context (X error %d)\n", PROG, x_error_seen);
        return 1;
    }
    XFree(configs);
    glXMakeCurrent(dpy, win, ctx);
    GLint max_viewports = 0;
    glGetIntegerv(GL_MAX_VIEWPORTS, &max_viewports);
    if (max_viewports < 4) {
        fprintf(stderr, "%s: GL_MAX_VIEWPORTS is %d\n", PROG, max_viewports);
        return 1;
    }

    GLuint program = glCreateProgram();
    glAttachShader(program, shader(GL_VERTEX_SHADER, VS));
    glAttachShader(program, shader(GL_GEOMETRY_SHADER, GS));
    glAttachShader(program, shader(GL_FRAGMENT_SHADER, FS));
    glLinkProgram(program);
    GLint linked = 0;
    glGetProgramiv(program, GL_LINK_STATUS, &linked);
    if (!linked) {
        char log[2048];
        glGetProgramInfoLog(program, sizeof log, NULL, log);
        fprintf(stderr, "%s: program does not link: %s\n", PROG, log);
        return 1;
    }
    glUseProgram(program);
    const GLint angle = glGetUniformLocation(program, "u_angle"), scale = glGetUniformLocation(program, "u_scale");
    const GLint mode = glGetUniformLocation(program, "u_mode"), only = glGetUniformLocation(program, "u_only");
    const GLfloat tints[12] = {0.85f, 0.2f, 0.2f, 0.2f, 0.8f, 0.3f, 0.2f, 0.35f, 0.9f, 0.95f, 0.85f, 0.2f};
    glUniform3fv(glGetUniformLocation(program, "u_tint"), 4, tints);

    /* x, y, r, g, b: a square over the whole viewport (two triangles), then a triangle */
    const GLfloat verts[] = {
        -1, -1, 0, 0, 0, 1, -1, 0, 0, 0, 1, 1, 0, 0, 0,
        -1, -1, 0, 0, 0, 1, 1, 0, 0, 0, -1, 1, 0, 0, 0,
        0, 0.9f, 1, 1, 1, -0.8f, -0.6f, 1, 0, 1, 0.8f, -0.6f, 0, 1, 1,
    };
    GLuint vao, vbo;
    glGenVertexArrays(1, &vao);
    glBindVertexArray(vao);
    glGenBuffers(1, &vbo);
    glBindBuffer(GL_ARRAY_BUFFER, vbo);
    glBufferData(GL_ARRAY_BUFFER, sizeof verts, verts, GL_STATIC_DRAW);
    glEnableVertexAttribArray(0);
    glVertexAttribPointer(0, 2, GL_FLOAT, GL_FALSE, 5 * sizeof(GLfloat), (const void *)0);
    glEnableVertexAttribArray(1);
    glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, 5 * sizeof(GLfloat), (const void *)(2 * sizeof(GLfloat)));

    /* the table above is for 320x240; other sizes scale it */
    const float kx = (float)a.width / 320.0f, ky = (float)a.height / 240.0f;
    const GLfloat vp[4][4] = {{10, 10, 180, 90}, {200, 20, 110, 150}, {20, 110, 150, 120}, {180, 180, 130, 55}};
    const GLint sc[4][4] = {{0, 0, 175, 240}, {215, 0, 105, 240}, {40, 0, 280, 240}, {150, 125, 170, 100}};
    GLfloat v[4][4];
    GLint s[4][4];
    for (int i = 0; i < 4; i++)
        for (int j = 0; j < 4; j++) {
            v[i][j] = vp[i][j] * (j % 2 ? ky : kx);
            s[i][j] = (GLint)lroundf((float)sc[i][j] * (j % 2 ? ky : kx));
        }

    for (int f = 0; f < a.frames; f++) {
        glViewport(0, 0, a.width, a.height);
        glScissor(0, 0, a.width, a.height);
        glDisable(GL_SCISSOR_TEST);
        glClearColor(0.12f, 0.12f, 0.14f, 1);
        glClear(GL_COLOR_BUFFER_BIT);

        glEnable(GL_SCISSOR_TEST);
        if (plain) {
            for (int i = 0; i < 4; i++) {
                glViewport((GLint)v[i][0], (GLint)v[i][1], (GLsizei)v[i][2], (GLsizei)v[i][3]);
                glScissor(s[i][0], s[i][1], s[i][2], s[i][3]);
                draw(mode, angle, scale, only, i, f);
            }
        } else {
            glViewportIndexedf(0, v[0][0], v[0][1], v[0][2], v[0][3]);
            glViewportIndexedfv(1, v[1]);
            glViewportArrayv(2, 2, &v[2][0]);
            glScissorIndexed(0, s[0][0], s[0][1], s[0][2], s[0][3]);
            glScissorIndexedv(1, s[1]);
            glScissorArrayv(2, 2, &s[2][0]);
            draw(mode, angle, scale, only, -1, f);
        }

        if (a.screenshot && f == a.frames - 1 && app_screenshot("viewport_array", &a) != 0)
            return 1;
        glXSwapBuffers(dpy, win);
        const GLenum err = glGetError();
        if (err != GL_NO_ERROR) {
            fprintf(stderr, "%s: GL error 0x%x in frame %d\n", PROG, err, f);
            return 1;
        }
    }
    glDeleteBuffers(1, &vbo);
    glDeleteVertexArrays(1, &vao);
    glDeleteProgram(program);
    glXMakeCurrent(dpy, None, NULL);
    glXDestroyContext(dpy, ctx);
    XCloseDisplay(dpy);
    return 0;
}
