/*
 * glx_window.h - the window of the small GLX test programs of apps_extra/: a display, a window of
 * --size with a visual of the given attributes, and a context current on it. Exits with a
 * message naming the program when there is none. Include after GL/glx.h and ../apps/app_common.h.
 */
#ifndef GLCAST_TEST_GLX_WINDOW_H
#define GLCAST_TEST_GLX_WINDOW_H

struct glx_window {
    Display *dpy;
    Window win;
    GLXContext ctx;
};

/* `visual` says what the attributes ask for, for the message when no visual has them. */
static struct glx_window glx_window_open(const char *prog, const struct app_args *a, int *attribs, const char *visual)
{
    struct glx_window w;
    w.dpy = XOpenDisplay(NULL);
    if (!w.dpy) {
        fprintf(stderr, "%s: cannot open display\n", prog);
        exit(1);
    }
    XVisualInfo *vi = glXChooseVisual(w.dpy, DefaultScreen(w.dpy), attribs);
    if (!vi) {
        fprintf(stderr, "%s: no %s visual\n", prog, visual);
        exit(1);
    }
    XSetWindowAttributes swa;
    swa.colormap = XCreateColormap(w.dpy, RootWindow(w.dpy, vi->screen), vi->visual, AllocNone);
    w.win = XCreateWindow(w.dpy, RootWindow(w.dpy, vi->screen), 0, 0, a->width, a->height, 0, vi->depth, InputOutput,
                          vi->visual, CWColormap, &swa);
    XMapWindow(w.dpy, w.win);
    w.ctx = glXCreateContext(w.dpy, vi, NULL, True);
    glXMakeCurrent(w.dpy, w.win, w.ctx);
    return w;
}

static void glx_window_close(struct glx_window *w)
{
    glXMakeCurrent(w->dpy, None, NULL);
    glXDestroyContext(w->dpy, w->ctx);
    XCloseDisplay(w->dpy);
}

#endif
