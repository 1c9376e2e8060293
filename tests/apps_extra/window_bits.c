/*
 * window_bits.c - a program whose window framebuffer has alpha and a depth and stencil buffer of
 * other sizes than most (8 alpha, 16 depth, no stencil), as Mesa's piglit asks for: every frame
 * it clears to a translucent colour, reads the pixels back with their alpha, and asks the sizes
 * of the window's buffers.
 *
 * For glcast's replay tests: a slave's window framebuffer was always 8-bit RGB without alpha, 24
 * depth and 8 stencil bits, so what the program read of alpha and asked of the sizes differed
 * under --verify (piglit's primitive-restart and fast_color_clear tests).
 *
 *   window_bits [--frames N] [--size WxH]
 */
#define GL_GLEXT_PROTOTYPES 1
#include <GL/gl.h>
#include <GL/glext.h>
#include <GL/glx.h>
#include <stdio.h>
#include <stdlib.h>

#include "../apps/app_common.h"
#include "glx_window.h"

/* glXChooseVisual prefers the deepest depth buffer: the visual with exactly these bits instead. */
static XVisualInfo *exact_visual(Display *dpy)
{
    XVisualInfo template_ = {.screen = DefaultScreen(dpy)}, *chosen = NULL;
    int count = 0;
    XVisualInfo *all = XGetVisualInfo(dpy, VisualScreenMask, &template_, &count);
    for (int i = 0; i < count && !chosen; i++) {
        int rgba = 0, db = 0, r = 0, alpha = -1, depth = -1, stencil = -1, samples = 0;
        glXGetConfig(dpy, &all[i], GLX_RGBA, &rgba);
        glXGetConfig(dpy, &all[i], GLX_DOUBLEBUFFER, &db);
        glXGetConfig(dpy, &all[i], GLX_RED_SIZE, &r);
        glXGetConfig(dpy, &all[i], GLX_ALPHA_SIZE, &alpha);
        glXGetConfig(dpy, &all[i], GLX_DEPTH_SIZE, &depth);
        glXGetConfig(dpy, &all[i], GLX_STENCIL_SIZE, &stencil);
        glXGetConfig(dpy, &all[i], GLX_SAMPLES, &samples);
        if (rgba && db && r == 8 && alpha == 8 && depth == 16 && stencil == 0 && samples <= 1) {
            chosen = malloc(sizeof *chosen);
            *chosen = all[i];
        }
    }
    XFree(all);
    return chosen;
}

int main(int argc, char **argv)
{
    struct app_args a;
    app_parse_args("window_bits", argc, argv, &a);
    struct glx_window w;
    w.dpy = XOpenDisplay(NULL);
    XVisualInfo *vi = w.dpy ? exact_visual(w.dpy) : NULL;
    if (!vi) {
        fprintf(stderr, "window_bits: no display, or no double-buffered RGBA visual of 8 alpha, 16 depth, 0 stencil bits\n");
        return 1;
    }
    XSetWindowAttributes swa;
    swa.colormap = XCreateColormap(w.dpy, RootWindow(w.dpy, vi->screen), vi->visual, AllocNone);
    w.win = XCreateWindow(w.dpy, RootWindow(w.dpy, vi->screen), 0, 0, a.width, a.height, 0, vi->depth, InputOutput,
                          vi->visual, CWColormap, &swa);
    XMapWindow(w.dpy, w.win);
    w.ctx = glXCreateContext(w.dpy, vi, NULL, True);
    glXMakeCurrent(w.dpy, w.win, w.ctx);
    unsigned char *pixels = malloc((size_t)a.width * (size_t)a.height * 4);
    for (int f = 0; f < a.frames; f++) {
        glClearColor(0.2f, 0.4f, 0.1f * (float)(f % 10), 0.25f + 0.05f * (float)(f % 10));
        glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
        glReadPixels(0, 0, a.width, a.height, GL_RGBA, GL_UNSIGNED_BYTE, pixels);
        GLint alpha = -1, depth = -1, stencil = -1;
        glGetFramebufferAttachmentParameteriv(GL_DRAW_FRAMEBUFFER, GL_BACK_LEFT, GL_FRAMEBUFFER_ATTACHMENT_ALPHA_SIZE,
                                              &alpha);
        glGetFramebufferAttachmentParameteriv(GL_DRAW_FRAMEBUFFER, GL_DEPTH, GL_FRAMEBUFFER_ATTACHMENT_DEPTH_SIZE,
                                              &depth);
        glGetIntegerv(GL_STENCIL_BITS, &stencil);
        if (f == 0)
            printf("window_bits: alpha %d, depth %d, stencil %d bits; first pixel's alpha %d\n", alpha, depth, stencil,
                   pixels[3]);
        glXSwapBuffers(w.dpy, w.win);
    }
    free(pixels);
    glx_window_close(&w);
    return 0;
}
