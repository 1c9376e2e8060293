/*
 * client_draws.c - the draws over client-memory vertex arrays whose ranges a slave must check
 * (docs/security.md, "The slave"), each in a legitimate form:
 *   - instanced draws with a per-instance client array (glVertexAttribDivisor 1), by
 *     glDrawElementsInstanced with client indices and glDrawArraysInstancedBaseInstance;
 *   - glDrawElements whose indices are in an element buffer and whose vertices are in client
 *     memory (the shim reads the indices back to know which vertices to ship);
 *   - glMultiDrawElements with one client index array per draw, and glMultiDrawArrays.
 * A GLSL 1.30 program in a compatibility context, GLX. Everything moves with the frame.
 *
 * The committed capture tests/data/client_draws.glcs is this program's stream; the attack
 * tests (tests/e2e/replay_attack_test.py) edit it so that each draw reads past what was
 * shipped.
 *
 *   client_draws [--frames N] [--size WxH] [--screenshot PATH.ppm]
 */
#define GL_GLEXT_PROTOTYPES 1
#include <GL/gl.h>
#include <GL/glext.h>
#include <GL/glx.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../apps/app_common.h"
#include "glx_screenshot.h"
#include "glx_window.h"

static const char *kVertex =
    "#version 130\n"
    "in vec2 position;\n"
    "in vec3 offset_scale;\n"  /* per instance: x, y offset and scale */
    "in vec3 color;\n"
    "out vec3 v_color;\n"
    "void main() {\n"
    "    v_color = color;\n"
    "    gl_Position = vec4(position * offset_scale.z + offset_scale.xy, 0.0, 1.0);\n"
    "}\n";
static const char *kFragment =
    "#version 130\n"
    "in vec3 v_color;\n"
    "out vec4 frag;\n"
    "void main() { frag = vec4(v_color, 1.0); }\n";

enum { POSITION = 0, OFFSET_SCALE = 1, COLOR = 2 };

static GLuint compile(GLenum type, const char *src)
{
    GLuint s = glCreateShader(type);
    glShaderSource(s, 1, &src, NULL);
    glCompileShader(s);
    GLint ok = 0;
    glGetShaderiv(s, GL_COMPILE_STATUS, &ok);
    if (!ok) {
        char log[1024];
        glGetShaderInfoLog(s, sizeof log, NULL, log);
        fprintf(stderr, "client_draws: shader: %s\n", log);
        exit(1);
    }
    return s;
}

/* A ring of n vertices around the origin (a fan's centre first), radius 1. */
static void ring(float *xy, int n, float phase)
{
    xy[0] = xy[1] = 0;
    for (int i = 1; i < n; i++) {
        const float a = phase + 2 * APP_PI * (float)(i - 1) / (float)(n - 2);
        xy[2 * i] = cosf(a);
        xy[2 * i + 1] = sinf(a);
    }
}

int main(int argc, char **argv)
{
    struct app_args a;
    app_parse_args("client_draws", argc, argv, &a);
    int attribs[] = {GLX_RGBA, GLX_DOUBLEBUFFER, GLX_RED_SIZE, 8, GLX_GREEN_SIZE, 8, GLX_BLUE_SIZE, 8, None};
    struct glx_window w = glx_window_open("client_draws", &a, attribs, "double-buffered RGB");

    GLuint program = glCreateProgram();
    glAttachShader(program, compile(GL_VERTEX_SHADER, kVertex));
    glAttachShader(program, compile(GL_FRAGMENT_SHADER, kFragment));
    glBindAttribLocation(program, POSITION, "position");
    glBindAttribLocation(program, OFFSET_SCALE, "offset_scale");
    glBindAttribLocation(program, COLOR, "color");
    glLinkProgram(program);
    GLint linked = 0;
    glGetProgramiv(program, GL_LINK_STATUS, &linked);
    if (!linked) {
        fprintf(stderr, "client_draws: link failed\n");
        return 1;
    }
    glUseProgram(program);

    /* Indices of a fan of 10 vertices as triangles, in an element buffer. */
    enum { RING = 10 };
    GLushort fan[3 * (RING - 2)];
    for (int i = 0; i < RING - 2; i++) {
        fan[3 * i] = 0;
        fan[3 * i + 1] = (GLushort)(i + 1);
        fan[3 * i + 2] = (GLushort)(i + 2);
    }
    GLuint element_buffer;
    glGenBuffers(1, &element_buffer);
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, element_buffer);
    glBufferData(GL_ELEMENT_ARRAY_BUFFER, sizeof fan, fan, GL_STATIC_DRAW);
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, 0);

    float positions[2 * RING], colors[3 * RING], instances[3 * 4];
    for (int f = 0; f < a.frames; f++) {
        const float t = 0.15f * (float)f;
        ring(positions, RING, t);
        for (int i = 0; i < RING; i++) {
            colors[3 * i] = 0.5f + 0.5f * cosf(t + (float)i);
            colors[3 * i + 1] = 0.5f + 0.5f * sinf(1.3f * t + (float)i);
            colors[3 * i + 2] = (float)i / RING;
        }
        for (int i = 0; i < 4; i++) {
            instances[3 * i] = -0.75f + 0.2f * (float)i + 0.05f * sinf(t);
            instances[3 * i + 1] = 0.55f;
            instances[3 * i + 2] = 0.08f + 0.02f * (float)i;
        }
        glViewport(0, 0, a.width, a.height);
        glClearColor(0.1f, 0.12f, 0.15f, 1);
        glClear(GL_COLOR_BUFFER_BIT);
        glEnableVertexAttribArray(POSITION);
        glEnableVertexAttribArray(COLOR);
        glVertexAttribPointer(POSITION, 2, GL_FLOAT, GL_FALSE, 0, positions);
        glVertexAttribPointer(COLOR, 3, GL_FLOAT, GL_FALSE, 0, colors);

        /* 1. instanced, client indices, per-instance client array: a row of four fans */
        glEnableVertexAttribArray(OFFSET_SCALE);
        glVertexAttribPointer(OFFSET_SCALE, 3, GL_FLOAT, GL_FALSE, 0, instances);
        glVertexAttribDivisor(OFFSET_SCALE, 1);
        glDrawElementsInstanced(GL_TRIANGLES, 3 * (RING - 2), GL_UNSIGNED_SHORT, fan, 4);
        /* 2. instanced arrays from a base instance: the last two of the row, lower */
        for (int i = 0; i < 4; i++) instances[3 * i + 1] = 0.2f;
        glDrawArraysInstancedBaseInstance(GL_TRIANGLE_FAN, 0, RING, 2, 2);
        glDisableVertexAttribArray(OFFSET_SCALE);
        glVertexAttribDivisor(OFFSET_SCALE, 0);

        /* 3. indices in the element buffer, vertices in client memory */
        glVertexAttrib3f(OFFSET_SCALE, -0.5f, -0.3f, 0.25f);
        glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, element_buffer);
        glDrawElements(GL_TRIANGLES, 3 * (RING - 2), GL_UNSIGNED_SHORT, (const void *)0);
        glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, 0);

        /* 4. multi-draws: two halves of the fan from client index arrays, then two arrays */
        glVertexAttrib3f(OFFSET_SCALE, 0.1f, -0.3f, 0.25f + 0.03f * sinf(t));
        const GLsizei counts[2] = {3 * 4, 3 * (RING - 2 - 4)};
        const void *lists[2] = {fan, fan + 3 * 4};
        glMultiDrawElements(GL_TRIANGLES, counts, GL_UNSIGNED_SHORT, lists, 2);
        glVertexAttrib3f(OFFSET_SCALE, 0.6f, -0.3f, 0.2f);
        const GLint firsts[2] = {0, 0};
        const GLsizei fan_counts[2] = {RING / 2 + 1, RING};
        glMultiDrawArrays(GL_TRIANGLE_FAN, firsts, fan_counts, 2);

        glDisableVertexAttribArray(POSITION);
        glDisableVertexAttribArray(COLOR);
        if (a.screenshot && f == a.frames - 1 && app_screenshot("client_draws", &a) != 0)
            return 1;
        glXSwapBuffers(w.dpy, w.win);
        const GLenum err = glGetError();
        if (err != GL_NO_ERROR) {
            fprintf(stderr, "client_draws: GL error 0x%x in frame %d\n", err, f);
            return 1;
        }
    }
    glDeleteBuffers(1, &element_buffer);
    glDeleteProgram(program);
    glx_window_close(&w);
    return 0;
}
