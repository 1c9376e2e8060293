/*
 * fbo_ext.c - render to texture through GL_EXT_framebuffer_object, as glmark2's terrain and
 * desktop scenes do: every frame draws a scene into a 256x256 texture attached to a
 * framebuffer object that is created and bound with the EXT entry points
 * (glGenFramebuffersEXT, glBindFramebufferEXT, glFramebufferTexture2DEXT), with the viewport
 * 0,0,256,256 inside it; binds the window back with glBindFramebufferEXT(GL_FRAMEBUFFER_EXT, 0),
 * sets the window's viewport, and shows the texture on a quad covering part of the window.
 * Fixed function, GLX.
 *
 * For the wall tests: gl.xml does not make glBindFramebufferEXT an alias of glBindFramebuffer,
 * so a slave that only follows glBindFramebuffer takes the FBO's viewport for a window
 * viewport and maps it to the tile, which stretches the texture's picture. The texture's
 * content (a clear colour, a rotating six-coloured fan and a band of stripes, all changing
 * with the frame) makes any such stretch or shift change pixels.
 *
 * With --core-bind (a first argument) the FBO is bound with glBindFramebuffer instead (same
 * object, GL 3.0 / ARB_framebuffer_object entry point): a control that shows the picture a
 * slave that understands the binding must produce.
 *
 * With --line the program sets glLineWidth(3) while its window is bound, and the texture's scene
 * gets a white line 3 texels wide from x -0.95 to -0.45 at y -0.2 (texture t 0.4): line width is
 * context state, which a slave that scales it for the window's draws must not carry into the
 * framebuffer object's (Blender sets it with its hidden window bound, 1x1, and drew its overlay
 * wires hundreds of pixels wide on every tile).
 *
 *   fbo_ext [--core-bind] [--line] [--frames N] [--size WxH] [--screenshot PATH.ppm]
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

#define TEX 256

static int core_bind, line;

static void bind_fbo(GLuint fb)
{
    if (core_bind)
        glBindFramebuffer(GL_FRAMEBUFFER, fb);
    else
        glBindFramebufferEXT(GL_FRAMEBUFFER_EXT, fb);
}

/* The texture's scene: everything in it changes with the frame. */
static void draw_offscreen(int f)
{
    glViewport(0, 0, TEX, TEX);
    glClearColor(0.15f + 0.02f * (float)(f % 10), 0.1f, 0.3f, 1);
    glClear(GL_COLOR_BUFFER_BIT);
    glMatrixMode(GL_PROJECTION);
    glLoadIdentity();
    glOrtho(-1, 1, -1, 1, -1, 1);
    glMatrixMode(GL_MODELVIEW);
    glLoadIdentity();
    /* stripes across the bottom, moving to the right */
    glBegin(GL_QUADS);
    for (int i = 0; i < 8; i++) {
        const float x0 = -1.0f + 0.25f * (float)i + 0.03f * (float)f, x1 = x0 + 0.125f;
        glColor3f(i & 1 ? 1.0f : 0.2f, 0.9f - 0.1f * (float)i, 0.1f * (float)i);
        glVertex2f(x0, -0.95f); glVertex2f(x1, -0.95f); glVertex2f(x1, -0.55f); glVertex2f(x0, -0.55f);
    }
    glEnd();
    /* a fan with six coloured corners, rotating, off centre so a stretch moves it */
    glTranslatef(0.2f, 0.25f, 0);
    glRotatef(9.0f * (float)f, 0, 0, 1);
    glBegin(GL_TRIANGLE_FAN);
    glColor3f(1, 1, 1);
    glVertex2f(0, 0);
    for (int k = 0; k <= 6; k++) {
        const float a = (float)k * 2.0f * APP_PI / 6.0f;
        glColor3f(k % 3 == 0 ? 1.0f : 0.1f, k % 3 == 1 ? 1.0f : 0.1f, k % 3 == 2 ? 1.0f : 0.1f);
        glVertex2f(0.6f * cosf(a), 0.6f * sinf(a));
    }
    glEnd();
    if (line) {
        glLoadIdentity();
        glColor3f(1, 1, 1);
        glBegin(GL_LINES);
        glVertex2f(-0.95f, -0.2f); glVertex2f(-0.45f, -0.2f);
        glEnd();
    }
}

int main(int argc, char **argv)
{
    struct app_args a;
    core_bind = app_take_flag(&argc, &argv, "--core-bind");
    line = app_take_flag(&argc, &argv, "--line");
    app_parse_args("fbo_ext", argc, argv, &a);
    int attribs[] = {GLX_RGBA, GLX_DOUBLEBUFFER, GLX_RED_SIZE, 8, GLX_GREEN_SIZE, 8, GLX_BLUE_SIZE, 8, None};
    struct glx_window w = glx_window_open("fbo_ext", &a, attribs, "double-buffered RGB");
    if (!strstr((const char *)glGetString(GL_EXTENSIONS), "GL_EXT_framebuffer_object")) {
        fprintf(stderr, "fbo_ext: GL_EXT_framebuffer_object missing\n");
        return 1;
    }

    GLuint tex, fbo;
    glGenTextures(1, &tex);
    glBindTexture(GL_TEXTURE_2D, tex);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, TEX, TEX, 0, GL_RGBA, GL_UNSIGNED_BYTE, NULL);
    glBindTexture(GL_TEXTURE_2D, 0);
    glGenFramebuffersEXT(1, &fbo);
    glBindFramebufferEXT(GL_FRAMEBUFFER_EXT, fbo);
    glFramebufferTexture2DEXT(GL_FRAMEBUFFER_EXT, GL_COLOR_ATTACHMENT0_EXT, GL_TEXTURE_2D, tex, 0);
    const GLenum status = glCheckFramebufferStatusEXT(GL_FRAMEBUFFER_EXT);
    glBindFramebufferEXT(GL_FRAMEBUFFER_EXT, 0);
    if (status != GL_FRAMEBUFFER_COMPLETE_EXT) {
        fprintf(stderr, "fbo_ext: framebuffer incomplete (0x%x)\n", status);
        return 1;
    }

    for (int f = 0; f < a.frames; f++) {
        bind_fbo(fbo);
        draw_offscreen(f);
        bind_fbo(0);

        glViewport(0, 0, a.width, a.height);
        glClearColor(0.05f, 0.05f, 0.08f, 1);
        glClear(GL_COLOR_BUFFER_BIT);
        glMatrixMode(GL_PROJECTION);
        glLoadIdentity();
        glMatrixMode(GL_MODELVIEW);
        glLoadIdentity();
        /* the texture on a quad over the left part of the window */
        glEnable(GL_TEXTURE_2D);
        glBindTexture(GL_TEXTURE_2D, tex);
        glColor3f(1, 1, 1);
        glBegin(GL_QUADS);
        glTexCoord2f(0, 0); glVertex2f(-0.9f, -0.85f);
        glTexCoord2f(1, 0); glVertex2f(0.35f, -0.85f);
        glTexCoord2f(1, 1); glVertex2f(0.35f, 0.85f);
        glTexCoord2f(0, 1); glVertex2f(-0.9f, 0.85f);
        glEnd();
        glBindTexture(GL_TEXTURE_2D, 0);
        glDisable(GL_TEXTURE_2D);
        /* and a window-only marker on the right, so the window pass is seen apart from it */
        glBegin(GL_TRIANGLES);
        glColor3f(0.9f, 0.6f, 0.1f);
        glVertex2f(0.5f, -0.5f); glVertex2f(0.9f, -0.5f); glVertex2f(0.7f, 0.5f);
        glEnd();
        if (line) glLineWidth(3);  /* with the window bound; the next frame's texture draws with it */

        if (a.screenshot && f == a.frames - 1 && app_screenshot("fbo_ext", &a) != 0)
            return 1;
        glXSwapBuffers(w.dpy, w.win);
        const GLenum err = glGetError();
        if (err != GL_NO_ERROR) {
            fprintf(stderr, "fbo_ext: GL error 0x%x in frame %d\n", err, f);
            return 1;
        }
    }
    glDeleteFramebuffersEXT(1, &fbo);
    glDeleteTextures(1, &tex);
    glx_window_close(&w);
    return 0;
}
