/*
 * trails.c - a program that draws each frame over its last: it clears the window once, in its
 * first frame, then adds one coloured square a frame along a line (as paint programs, plotters
 * and some screensavers do, relying on the back buffer keeping what was drawn). Fixed function,
 * GLX. Every tenth frame (5, 15, ...) begins with a clear inside a scissor box, a band along the
 * bottom: a clear, but not of the whole window.
 *
 * For the projector test (tests/e2e/projectors_test.py, case trails): a slave that warps its
 * output in the window must give the program its own frame back before it draws the next one, or
 * the squares land on the warped picture and are warped again.
 *
 *   trails [--frames N] [--size WxH]
 */
#include <GL/gl.h>
#include <GL/glx.h>
#include <stdio.h>

#include "../apps/app_common.h"
#include "glx_window.h"

int main(int argc, char **argv)
{
    struct app_args a;
    app_parse_args("trails", argc, argv, &a);
    int attribs[] = {GLX_RGBA, GLX_DOUBLEBUFFER, GLX_RED_SIZE, 8, GLX_GREEN_SIZE, 8, GLX_BLUE_SIZE, 8, None};
    struct glx_window w = glx_window_open("trails", &a, attribs, "double-buffered RGB");
    glViewport(0, 0, a.width, a.height);
    glMatrixMode(GL_PROJECTION);
    glLoadIdentity();
    glOrtho(0, 1, 0, 1, -1, 1);
    for (int f = 0; f < a.frames; f++) {
        if (f % 10 == 5) {
            glEnable(GL_SCISSOR_TEST);  /* a band cleared, not the whole window */
            glScissor(0, 0, a.width, a.height / 8);
            glClearColor(0.3f + 0.05f * (float)(f / 10), 0.3f, 0.35f, 1);
            glClear(GL_COLOR_BUFFER_BIT);
            glDisable(GL_SCISSOR_TEST);
        }
        if (f == 0) {
            glClearColor(0.1f, 0.1f, 0.15f, 1);
            glClear(GL_COLOR_BUFFER_BIT);
        }
        const float x = 0.05f + 0.9f * (float)(f % 20) / 20.0f, y = 0.2f + 0.6f * (float)((f / 20) % 4) / 4.0f;
        glColor3f((f % 3) == 0 ? 1.0f : 0.2f, (f % 3) == 1 ? 1.0f : 0.2f, (f % 3) == 2 ? 1.0f : 0.2f);
        glBegin(GL_QUADS);
        glVertex2f(x, y); glVertex2f(x + 0.04f, y); glVertex2f(x + 0.04f, y + 0.12f); glVertex2f(x, y + 0.12f);
        glEnd();
        glXSwapBuffers(w.dpy, w.win);
        const GLenum err = glGetError();
        if (err != GL_NO_ERROR) {
            fprintf(stderr, "trails: GL error 0x%x in frame %d\n", err, f);
            return 1;
        }
    }
    glx_window_close(&w);
    return 0;
}
