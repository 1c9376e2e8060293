/*
 * live_state.c - programs whose live state a snapshot must carry over (docs/keeper.md), for the
 * late-join tests (tests/e2e/keeper_test.py):
 *   live_state textures      every frame a new texture is made, uploaded with that frame's
 *                            pattern and drawn beside the last two; the one before is deleted
 *   live_state render_once   at the start a pattern is rendered into a texture through a
 *                            framebuffer object; every frame samples it on a turning quad, and
 *                            the picture is never cleared: each frame draws over the last
 *   live_state renderbuffer  at the start a fan is drawn into colour and depth renderbuffers;
 *                            every frame a small quad is drawn into them behind the fan (the
 *                            depth test keeps the fan) and the colour is blitted to the window
 *   live_state fences        as textures, with a fence made every frame and waited on two frames
 *                            later, and an occlusion query whose count, read a frame later,
 *                            sets the ground's brightness
 *   live_state feedback      as textures, with a transform feedback object made at the start
 *                            and never deleted: an object no snapshot here recreates
 *   live_state pushed        as textures, with an attribute stack pushed at the start and never
 *                            popped: state no snapshot can read (a slave must join otherwise)
 * Fixed-function GL 1.x-3.0 in a compatibility context, GLX. Everything depends on the frame
 * index only.
 *
 *   live_state MODE [--frames N] [--size WxH] [--screenshot PATH.ppm]
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

enum { SIZE = 32, KEEP = 3 };

static void pattern(unsigned char *rgba, int frame)
{
    for (int y = 0; y < SIZE; y++)
        for (int x = 0; x < SIZE; x++) {
            unsigned char *p = rgba + 4 * (y * SIZE + x);
            p[0] = (unsigned char)(x * 8 + frame * 3);
            p[1] = (unsigned char)(y * 8 + frame * 5);
            p[2] = (unsigned char)(((x ^ y) & 4) ? 200 : 40);
            p[3] = 255;
        }
}

static void quad(float cx, float cy, float half, float angle)
{
    const float c = cosf(angle) * half, s = sinf(angle) * half;
    glBegin(GL_QUADS);
    glTexCoord2f(0, 0); glVertex2f(cx - c + s, cy - s - c);
    glTexCoord2f(1, 0); glVertex2f(cx + c + s, cy + s - c);
    glTexCoord2f(1, 1); glVertex2f(cx + c - s, cy + s + c);
    glTexCoord2f(0, 1); glVertex2f(cx - c - s, cy - s + c);
    glEnd();
}

/* The texture rendered into once: a fan of coloured triangles on a dark ground. */
static GLuint render_into_texture(void)
{
    GLuint tex, fbo;
    glGenTextures(1, &tex);
    glBindTexture(GL_TEXTURE_2D, tex);
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, 64, 64, 0, GL_RGBA, GL_UNSIGNED_BYTE, NULL);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glGenFramebuffers(1, &fbo);
    glBindFramebuffer(GL_FRAMEBUFFER, fbo);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, tex, 0);
    if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) {
        fprintf(stderr, "live_state: framebuffer incomplete\n");
        exit(1);
    }
    glViewport(0, 0, 64, 64);
    glClearColor(0.1f, 0.1f, 0.2f, 1);
    glClear(GL_COLOR_BUFFER_BIT);
    glDisable(GL_TEXTURE_2D);
    glBegin(GL_TRIANGLES);
    for (int i = 0; i < 8; i++) {
        const float a0 = 2 * APP_PI * i / 8, a1 = 2 * APP_PI * (i + 1) / 8;
        glColor3f(0.5f + 0.5f * cosf(a0), 0.5f + 0.5f * sinf(a0), (float)i / 8);
        glVertex2f(0, 0);
        glVertex2f(0.9f * cosf(a0), 0.9f * sinf(a0));
        glVertex2f(0.9f * cosf(a1), 0.9f * sinf(a1));
    }
    glEnd();
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    glDeleteFramebuffers(1, &fbo);
    glColor3f(1, 1, 1);
    return tex;
}

enum { RB_SIZE = 96 };

static void fan(float z)
{
    glBegin(GL_TRIANGLES);
    for (int i = 0; i < 8; i++) {
        const float a0 = 2 * APP_PI * i / 8, a1 = 2 * APP_PI * (i + 1) / 8;
        glColor3f(0.5f + 0.5f * cosf(a0), 0.5f + 0.5f * sinf(a0), (float)i / 8);
        glVertex3f(0, 0, z);
        glVertex3f(0.6f * cosf(a0), 0.6f * sinf(a0), z);
        glVertex3f(0.6f * cosf(a1), 0.6f * sinf(a1), z);
    }
    glEnd();
}

/* A framebuffer of colour and depth renderbuffers holding a fan, drawn once. */
static GLuint render_into_renderbuffers(void)
{
    GLuint fbo, rb[2];
    glGenFramebuffers(1, &fbo);
    glGenRenderbuffers(2, rb);
    glBindRenderbuffer(GL_RENDERBUFFER, rb[0]);
    glRenderbufferStorage(GL_RENDERBUFFER, GL_RGBA8, RB_SIZE, RB_SIZE);
    glBindRenderbuffer(GL_RENDERBUFFER, rb[1]);
    glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT24, RB_SIZE, RB_SIZE);
    glBindFramebuffer(GL_FRAMEBUFFER, fbo);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, rb[0]);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, rb[1]);
    if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) {
        fprintf(stderr, "live_state: renderbuffer framebuffer incomplete\n");
        exit(1);
    }
    glViewport(0, 0, RB_SIZE, RB_SIZE);
    glClearColor(0.1f, 0.2f, 0.1f, 1);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    glEnable(GL_DEPTH_TEST);
    fan(-0.5f);
    glDisable(GL_DEPTH_TEST);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    return fbo;
}

/* One frame of renderbuffer mode: a quad behind the fan, then the colour blitted to the window. */
static void renderbuffer_frame(GLuint fbo, int f, int width, int height)
{
    glBindFramebuffer(GL_FRAMEBUFFER, fbo);
    glViewport(0, 0, RB_SIZE, RB_SIZE);
    glEnable(GL_DEPTH_TEST);
    glDisable(GL_TEXTURE_2D);
    glColor3f((float)(f % 7) / 7, 0.3f, (float)(f % 11) / 11);
    const float x = 0.8f * cosf(0.13f * f), y = 0.8f * sinf(0.09f * f);
    glBegin(GL_QUADS);
    glVertex3f(x - 0.1f, y - 0.1f, 0); glVertex3f(x + 0.1f, y - 0.1f, 0);
    glVertex3f(x + 0.1f, y + 0.1f, 0); glVertex3f(x - 0.1f, y + 0.1f, 0);
    glEnd();
    glDisable(GL_DEPTH_TEST);
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, 0);
    glViewport(0, 0, width, height);
    glClear(GL_COLOR_BUFFER_BIT);
    const int dx = (f * 3) % (width > RB_SIZE ? width - RB_SIZE : 1), dy = (height - RB_SIZE) / 2;
    glBlitFramebuffer(0, 0, RB_SIZE, RB_SIZE, dx, dy > 0 ? dy : 0, dx + RB_SIZE, (dy > 0 ? dy : 0) + RB_SIZE,
                      GL_COLOR_BUFFER_BIT, GL_NEAREST);
    glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
}

int main(int argc, char **argv)
{
    if (argc < 2 || (strcmp(argv[1], "textures") != 0 && strcmp(argv[1], "render_once") != 0 &&
                     strcmp(argv[1], "renderbuffer") != 0 && strcmp(argv[1], "fences") != 0 &&
                     strcmp(argv[1], "feedback") != 0 && strcmp(argv[1], "pushed") != 0)) {
        fprintf(stderr, "usage: live_state textures|render_once|renderbuffer|fences|feedback|pushed [--frames N] "
                        "[--size WxH]\n");
        return 2;
    }
    const int pushed = strcmp(argv[1], "pushed") == 0;
    const int fences = strcmp(argv[1], "fences") == 0;
    const int feedback = strcmp(argv[1], "feedback") == 0;
    const int textures = strcmp(argv[1], "textures") == 0 || pushed || fences || feedback;
    const int renderbuffer = strcmp(argv[1], "renderbuffer") == 0;
    argv[1] = argv[0];
    struct app_args a;
    app_parse_args("live_state", argc - 1, argv + 1, &a);
    int attribs[] = {GLX_RGBA, GLX_DOUBLEBUFFER, GLX_RED_SIZE, 8, GLX_GREEN_SIZE, 8, GLX_BLUE_SIZE, 8, None};
    struct glx_window w = glx_window_open("live_state", &a, attribs, "double-buffered RGB");

    GLuint once = textures || renderbuffer ? 0 : render_into_texture();
    GLuint rb_fbo = renderbuffer ? render_into_renderbuffers() : 0;
    if (pushed) glPushAttrib(GL_ENABLE_BIT);
    if (feedback) {
        GLuint tf;
        glGenTransformFeedbacks(1, &tf);
        glBindTransformFeedback(GL_TRANSFORM_FEEDBACK, tf);
        glBindTransformFeedback(GL_TRANSFORM_FEEDBACK, 0);
    }
    GLuint ring[KEEP] = {0};
    GLsync fence[2] = {0, 0};
    GLuint occlusion = 0;
    if (fences) glGenQueries(1, &occlusion);
    unsigned char rgba[4 * SIZE * SIZE];
    glViewport(0, 0, a.width, a.height);
    glClearColor(0.05f, 0.05f, 0.05f, 1);
    glClear(GL_COLOR_BUFFER_BIT);  /* render_once never clears again: frames draw over frames */
    glEnable(GL_TEXTURE_2D);
    glTexEnvi(GL_TEXTURE_ENV, GL_TEXTURE_ENV_MODE, GL_REPLACE);
    for (int f = 0; f < a.frames; f++) {
        if (renderbuffer) {
            renderbuffer_frame(rb_fbo, f, a.width, a.height);
        } else if (textures) {
            if (fences && fence[f % 2]) {
                glClientWaitSync(fence[f % 2], GL_SYNC_FLUSH_COMMANDS_BIT, 1000000000);
                glDeleteSync(fence[f % 2]);
            }
            if (fences && f > 0) {
                GLuint passed = 0;
                glGetQueryObjectuiv(occlusion, GL_QUERY_RESULT, &passed);
                glClearColor((float)(passed % 97) / 97, 0.05f, 0.05f, 1);
            }
            glClear(GL_COLOR_BUFFER_BIT);
            if (fences) glBeginQuery(GL_SAMPLES_PASSED, occlusion);
            const int slot = f % KEEP;
            if (ring[slot]) glDeleteTextures(1, &ring[slot]);
            glGenTextures(1, &ring[slot]);
            glBindTexture(GL_TEXTURE_2D, ring[slot]);
            pattern(rgba, f);
            glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, SIZE, SIZE, 0, GL_RGBA, GL_UNSIGNED_BYTE, rgba);
            glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
            glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
            for (int k = 0; k < KEEP; k++) {  /* the newest and the ones before it */
                if (!ring[(f - k + KEEP) % KEEP]) continue;
                glBindTexture(GL_TEXTURE_2D, ring[(f - k + KEEP) % KEEP]);
                quad(-0.6f + 0.6f * k, 0, 0.25f, 0.02f * f);
            }
            if (fences) {
                glEndQuery(GL_SAMPLES_PASSED);
                fence[f % 2] = glFenceSync(GL_SYNC_GPU_COMMANDS_COMPLETE, 0);
            }
        } else {
            glBindTexture(GL_TEXTURE_2D, once);
            quad(0.5f * cosf(0.05f * f), 0.5f * sinf(0.07f * f), 0.3f, 0.03f * f);
        }
        if (a.screenshot && f == a.frames - 1 && app_screenshot("live_state", &a) != 0)
            return 1;
        glXSwapBuffers(w.dpy, w.win);
    }
    glx_window_close(&w);
    return 0;
}
