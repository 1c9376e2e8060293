/*
 * shadow_occluder.c - glcast test app for the soft-shadow pass: OpenGL 1.x fixed function
 * through Xlib + GLX, a lit scene that draws no shadows of its own.
 *
 * A grey ground quad (y = 0, tessellated 1 x 1 so vertex lighting varies), a red slab floating
 * above it (x -1..1, y 1.4..1.6, z -1..1), a blue cube standing on it (x 1.8..2.8, y 0..1,
 * z -0.5..0.5), lit by GL_LIGHT0 at world (0.5, 6, 1, 1) (positional, set under the view
 * transform so its GL_POSITION is in eye space as GL stores it). The camera looks from
 * (0, 5, 8) at (0, 0.5, 0), 45 degrees vertically, near 0.5, far 60; it does not move, so
 * every frame is the same. tests/effects/shadows/shadows_e2e_test.py predicts where the
 * slab's shadow falls from these numbers.
 *
 *   shadow_occluder [--frames N] [--size WxH] [--screenshot PATH.ppm]
 */
#include <GL/gl.h>
#include <GL/glx.h>
#include <X11/Xlib.h>
#include <X11/Xutil.h>
#include <math.h>

#include "app_common.h"

static const char *PROG = "shadow_occluder";

static void box(float x0, float y0, float z0, float x1, float y1, float z1)
{
    glBegin(GL_QUADS);
    glNormal3f(0, 1, 0);
    glVertex3f(x0, y1, z1); glVertex3f(x1, y1, z1); glVertex3f(x1, y1, z0); glVertex3f(x0, y1, z0);
    glNormal3f(0, -1, 0);
    glVertex3f(x0, y0, z0); glVertex3f(x1, y0, z0); glVertex3f(x1, y0, z1); glVertex3f(x0, y0, z1);
    glNormal3f(1, 0, 0);
    glVertex3f(x1, y0, z1); glVertex3f(x1, y0, z0); glVertex3f(x1, y1, z0); glVertex3f(x1, y1, z1);
    glNormal3f(-1, 0, 0);
    glVertex3f(x0, y0, z0); glVertex3f(x0, y0, z1); glVertex3f(x0, y1, z1); glVertex3f(x0, y1, z0);
    glNormal3f(0, 0, 1);
    glVertex3f(x0, y0, z1); glVertex3f(x1, y0, z1); glVertex3f(x1, y1, z1); glVertex3f(x0, y1, z1);
    glNormal3f(0, 0, -1);
    glVertex3f(x1, y0, z0); glVertex3f(x0, y0, z0); glVertex3f(x0, y1, z0); glVertex3f(x1, y1, z0);
    glEnd();
}

static void draw_frame(int w, int h)
{
    const GLfloat light[4] = {0.5f, 6.0f, 1.0f, 1.0f};
    const float aspect = (float)w / (float)h, znear = 0.5f;
    const float top = znear * tanf(22.5f * APP_PI / 180.0f);
    int i, j;

    glViewport(0, 0, w, h);
    glClearColor(0.55f, 0.72f, 0.92f, 1.0f);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    glMatrixMode(GL_PROJECTION);
    glLoadIdentity();
    glFrustum(-top * aspect, top * aspect, -top, top, znear, 60.0f);
    glMatrixMode(GL_MODELVIEW);
    glLoadIdentity();
    /* gluLookAt((0, 5, 8), (0, 0.5, 0), up y) as a rotation about x and a translation */
    glRotatef((float)(atan2(4.5, 8.0) * 180.0 / APP_PI), 1.0f, 0.0f, 0.0f);
    glTranslatef(0.0f, -5.0f, -8.0f);
    glLightfv(GL_LIGHT0, GL_POSITION, light);

    glColor3f(0.8f, 0.8f, 0.76f);
    glBegin(GL_QUADS);
    glNormal3f(0, 1, 0);
    for (j = -10; j < 10; j++)
        for (i = -10; i < 10; i++) {
            glVertex3f((float)i, 0, (float)j + 1);
            glVertex3f((float)i + 1, 0, (float)j + 1);
            glVertex3f((float)i + 1, 0, (float)j);
            glVertex3f((float)i, 0, (float)j);
        }
    glEnd();
    glColor3f(0.85f, 0.3f, 0.25f);
    box(-1.0f, 1.4f, -1.0f, 1.0f, 1.6f, 1.0f);
    glColor3f(0.3f, 0.45f, 0.85f);
    box(1.8f, 0.0f, -0.5f, 2.8f, 1.0f, 0.5f);
}

static Bool wait_for_map(Display *d, XEvent *e, XPointer arg)
{
    (void)d;
    return e->type == MapNotify && e->xmap.window == *(Window *)arg;
}

int main(int argc, char **argv)
{
    struct app_args args;
    Display *dpy;
    XVisualInfo *vi;
    XSetWindowAttributes swa;
    Window win;
    XEvent ev;
    GLXContext ctx;
    unsigned char *shot = NULL;
    int frame;
    int attribs[] = {GLX_RGBA, GLX_DOUBLEBUFFER, GLX_RED_SIZE, 8, GLX_GREEN_SIZE, 8,
                     GLX_BLUE_SIZE, 8, GLX_DEPTH_SIZE, 24, None};
    const GLfloat ambient[4] = {0.3f, 0.3f, 0.33f, 1.0f}, diffuse[4] = {0.9f, 0.9f, 0.85f, 1.0f};

    app_parse_args(PROG, argc, argv, &args);
    dpy = XOpenDisplay(NULL);
    if (dpy == NULL) {
        fprintf(stderr, "%s: cannot open X display\n", PROG);
        return 1;
    }
    vi = glXChooseVisual(dpy, DefaultScreen(dpy), attribs);
    if (vi == NULL) {
        fprintf(stderr, "%s: glXChooseVisual: no RGBA double-buffered visual with depth 24\n", PROG);
        return 1;
    }
    memset(&swa, 0, sizeof swa);
    swa.colormap = XCreateColormap(dpy, RootWindow(dpy, vi->screen), vi->visual, AllocNone);
    swa.event_mask = StructureNotifyMask;
    win = XCreateWindow(dpy, RootWindow(dpy, vi->screen), 0, 0, (unsigned)args.width, (unsigned)args.height, 0,
                        vi->depth, InputOutput, vi->visual, CWColormap | CWEventMask, &swa);
    XStoreName(dpy, win, "glcast shadow_occluder");
    XMapWindow(dpy, win);
    XIfEvent(dpy, &ev, wait_for_map, (XPointer)&win);
    ctx = glXCreateContext(dpy, vi, NULL, True);
    if (ctx == NULL || !glXMakeCurrent(dpy, win, ctx)) {
        fprintf(stderr, "%s: cannot create or bind a GLX context\n", PROG);
        return 1;
    }

    glEnable(GL_DEPTH_TEST);
    glEnable(GL_LIGHTING);
    glEnable(GL_LIGHT0);
    glEnable(GL_NORMALIZE);
    glEnable(GL_COLOR_MATERIAL);
    glColorMaterial(GL_FRONT_AND_BACK, GL_AMBIENT_AND_DIFFUSE);
    glLightfv(GL_LIGHT0, GL_AMBIENT, ambient);
    glLightfv(GL_LIGHT0, GL_DIFFUSE, diffuse);

    for (frame = 0; frame < args.frames; frame++) {
        while (XPending(dpy) > 0)
            XNextEvent(dpy, &ev);
        draw_frame(args.width, args.height);
        if (frame == args.frames - 1 && args.screenshot != NULL) {
            shot = malloc((size_t)args.width * (size_t)args.height * 3u);
            glReadBuffer(GL_BACK);
            glPixelStorei(GL_PACK_ALIGNMENT, 1);
            glReadPixels(0, 0, args.width, args.height, GL_RGB, GL_UNSIGNED_BYTE, shot);
        }
        if (glGetError() != GL_NO_ERROR) {
            fprintf(stderr, "%s: GL error in frame %d\n", PROG, frame);
            return 1;
        }
        glXSwapBuffers(dpy, win);
    }
    glXMakeCurrent(dpy, None, NULL);
    glXDestroyContext(dpy, ctx);
    XDestroyWindow(dpy, win);
    XCloseDisplay(dpy);
    if (shot != NULL) {
        int bad = app_write_ppm(args.screenshot, args.width, args.height, shot);
        free(shot);
        if (bad != 0) {
            fprintf(stderr, "%s: cannot write screenshot '%s'\n", PROG, args.screenshot);
            return 1;
        }
    }
    return 0;
}
