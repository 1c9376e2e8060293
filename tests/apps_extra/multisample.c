/*
 * multisample.c - a program that asks for a 4-sample window (GLX_SAMPLE_BUFFERS 1, GLX_SAMPLES 4)
 * and draws turning triangles whose edges the samples smooth: a slave must render with as many
 * samples to show the same edges (tests/e2e/multisample_test.py). Fixed-function GL, GLX.
 *
 *   multisample [--frames N] [--size WxH] [--screenshot PATH.ppm]
 * Prints "multisample: GL_SAMPLES N".
 */
#include <GL/gl.h>
#include <GL/glx.h>
#include <math.h>
#include <stdio.h>

#include "../apps/app_common.h"
#include "glx_screenshot.h"
#include "glx_window.h"

int main(int argc, char **argv)
{
    struct app_args a;
    app_parse_args("multisample", argc, argv, &a);
    int attribs[] = {GLX_RGBA, GLX_DOUBLEBUFFER, GLX_RED_SIZE, 8, GLX_GREEN_SIZE, 8, GLX_BLUE_SIZE, 8,
                     GLX_DEPTH_SIZE, 24, GLX_SAMPLE_BUFFERS, 1, GLX_SAMPLES, 4, None};
    struct glx_window w = glx_window_open("multisample", &a, attribs, "4-sample");
    GLint samples = 0;
    glGetIntegerv(GL_SAMPLES, &samples);
    printf("multisample: GL_SAMPLES %d\n", samples);
    fflush(stdout);
    glViewport(0, 0, a.width, a.height);
    for (int f = 0; f < a.frames; f++) {
        glClearColor(0.1f, 0.1f, 0.15f, 1);
        glClear(GL_COLOR_BUFFER_BIT);
        for (int k = 0; k < 5; k++) {
            const float angle = 0.03f * f + 1.25f * k, r = 0.2f + 0.13f * k;
            glColor3f(0.3f + 0.15f * k, 0.9f - 0.15f * k, 0.5f);
            glBegin(GL_TRIANGLES);
            for (int v = 0; v < 3; v++) {
                const float t = angle + 2.0944f * v;
                glVertex2f(r * cosf(t) + 0.1f * (k - 2), r * sinf(t));
            }
            glEnd();
        }
        if (a.screenshot && f == a.frames - 1 && app_screenshot("multisample", &a) != 0) return 1;
        glXSwapBuffers(w.dpy, w.win);
    }
    glx_window_close(&w);
    return 0;
}
