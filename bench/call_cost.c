/*
 * call_cost.c - the time a GL call costs the calling thread (bench/call_cost_bench.py).
 *
 * An 8x8 GLX window; each frame issues CALLS immediate-mode calls (glColor3f, glVertex3f in a
 * glBegin(GL_POINTS)/glEnd block: the calls a display-list or immediate-mode program makes by
 * the thousand) whose values change a little every frame, then swaps. The window is too small
 * for llvmpipe's rasterizer to matter, so what the thread spends is the calls. Prints the
 * thread's CPU time (CLOCK_THREAD_CPUTIME_ID) per call over the frames after the first 10:
 *
 *     call_cost: ns_per_call <x> frames <n> calls_per_frame <k>
 *
 *     call_cost [FRAMES [CALLS]]      (defaults 200 and 20000)
 */
#include <GL/gl.h>
#include <GL/glx.h>
#include <X11/Xlib.h>
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

static double thread_seconds(void)
{
    struct timespec t;
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
    return (double)t.tv_sec + (double)t.tv_nsec * 1e-9;
}

int main(int argc, char **argv)
{
    const int frames = argc > 1 ? atoi(argv[1]) : 200;
    const int calls = argc > 2 ? atoi(argv[2]) : 20000;
    int attribs[] = {GLX_RGBA, GLX_DOUBLEBUFFER, GLX_DEPTH_SIZE, 24, None};
    Display *dpy = XOpenDisplay(NULL);
    if (dpy == NULL || frames <= 10 || calls < 2) {
        fprintf(stderr, "call_cost: no X display, or FRAMES <= 10 or CALLS < 2\n");
        return 1;
    }
    XVisualInfo *vi = glXChooseVisual(dpy, DefaultScreen(dpy), attribs);
    if (vi == NULL) {
        fprintf(stderr, "call_cost: no double-buffered RGBA visual\n");
        return 1;
    }
    XSetWindowAttributes swa = {0};
    swa.colormap = XCreateColormap(dpy, RootWindow(dpy, vi->screen), vi->visual, AllocNone);
    Window win = XCreateWindow(dpy, RootWindow(dpy, vi->screen), 0, 0, 8, 8, 0, vi->depth, InputOutput, vi->visual,
                               CWColormap, &swa);
    XMapWindow(dpy, win);
    GLXContext ctx = glXCreateContext(dpy, vi, NULL, True);
    if (ctx == NULL || !glXMakeCurrent(dpy, win, ctx)) {
        fprintf(stderr, "call_cost: no GLX context\n");
        return 1;
    }
    double spent = 0;
    for (int f = 0; f < frames; ++f) {
        const double start = thread_seconds();
        glClear(GL_COLOR_BUFFER_BIT);
        glBegin(GL_POINTS);
        for (int i = 0; i < calls / 2; ++i) {
            const float x = (float)(i % 97) / 97.0f - 0.5f + 0.001f * (float)f;
            glColor3f(x, 0.5f, (float)(i & 255) / 255.0f);
            glVertex3f(x, (float)(i % 89) / 89.0f - 0.5f, 0.0f);
        }
        glEnd();
        if (f >= 10) spent += thread_seconds() - start;
        glXSwapBuffers(dpy, win);
    }
    printf("call_cost: ns_per_call %.2f frames %d calls_per_frame %d\n",
           spent * 1e9 / ((double)(frames - 10) * (double)(calls + 3)), frames - 10, calls + 3);
    glXMakeCurrent(dpy, None, NULL);
    glXDestroyContext(dpy, ctx);
    XCloseDisplay(dpy);
    return 0;
}
