/*
 * threads_buffers.c - two threads, each with its own window and GL context (the second
 * sharing objects with the first), rendering from buffers written through mapped ranges:
 * thread A through a persistent, coherent map it writes every frame without unmapping;
 * thread B through glMapBufferRange(GL_MAP_FLUSH_EXPLICIT_BIT) + glFlushMappedBufferRange.
 * For glcast's tests: tuples carry two context ids, and both kinds of mapped writes reach the
 * stream. GL 4.5 compatibility (llvmpipe), fixed-function drawing from buffer objects.
 *
 *   threads_buffers [--frames N]     each thread renders N frames; prints the buffer names
 */
#define GL_GLEXT_PROTOTYPES 1
#include <GL/gl.h>
#include <GL/glext.h>
#include <GL/glx.h>
#include <X11/Xlib.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../apps/app_common.h"

static Display *dpy;
static XVisualInfo *vi;
static GLXContext shared_root;
static int frames = 30;
static pthread_mutex_t create_lock = PTHREAD_MUTEX_INITIALIZER;
static pthread_cond_t created = PTHREAD_COND_INITIALIZER;

struct worker {
    int id;
    int persistent; /* 1: persistent coherent map; 0: explicit flush */
    GLuint buffer;
    int failed;
};

static Window make_window(int x)
{
    XSetWindowAttributes swa;
    swa.colormap = XCreateColormap(dpy, RootWindow(dpy, vi->screen), vi->visual, AllocNone);
    swa.event_mask = 0;
    Window w = XCreateWindow(dpy, RootWindow(dpy, vi->screen), x, 0, 160, 120, 0, vi->depth, InputOutput,
                             vi->visual, CWColormap | CWEventMask, &swa);
    XMapWindow(dpy, w);
    XSync(dpy, False);
    return w;
}

static void *run(void *arg)
{
    struct worker *wk = arg;
    pthread_mutex_lock(&create_lock);
    Window win = make_window(wk->id * 200);
    GLXContext ctx = glXCreateContext(dpy, vi, wk->id ? shared_root : NULL, True);
    if (!wk->id) {
        shared_root = ctx;
        pthread_cond_broadcast(&created);
    }
    glXMakeCurrent(dpy, win, ctx);
    pthread_mutex_unlock(&create_lock);

    const int verts = 3;
    const GLsizeiptr bytes = verts * 2 * sizeof(GLfloat);
    glGenBuffers(1, &wk->buffer);
    glBindBuffer(GL_ARRAY_BUFFER, wk->buffer);
    GLfloat *map = NULL;
    if (wk->persistent) {
        const GLbitfield flags = GL_MAP_WRITE_BIT | GL_MAP_PERSISTENT_BIT | GL_MAP_COHERENT_BIT;
        glBufferStorage(GL_ARRAY_BUFFER, bytes, NULL, flags);
        map = glMapBufferRange(GL_ARRAY_BUFFER, 0, bytes, flags);
    } else {
        glBufferData(GL_ARRAY_BUFFER, bytes, NULL, GL_DYNAMIC_DRAW);
    }
    glEnableClientState(GL_VERTEX_ARRAY);
    glVertexPointer(2, GL_FLOAT, 0, (const void *)0);
    for (int f = 0; f < frames; f++) {
        const float s = 0.2f + 0.7f * (float)f / (float)frames;
        const GLfloat tri[6] = {-s, -s, s, -s, 0, s};
        if (wk->persistent) {
            memcpy(map, tri, sizeof tri);
        } else {
            GLfloat *p = glMapBufferRange(GL_ARRAY_BUFFER, 0, bytes, GL_MAP_WRITE_BIT | GL_MAP_FLUSH_EXPLICIT_BIT);
            memcpy(p, tri, sizeof tri);
            glFlushMappedBufferRange(GL_ARRAY_BUFFER, 0, bytes);
            glUnmapBuffer(GL_ARRAY_BUFFER);
        }
        glClearColor(wk->id ? 0.1f : 0.4f, 0.2f, 0.3f, 1);
        glClear(GL_COLOR_BUFFER_BIT);
        glColor3f(1, wk->id ? 1.0f : 0.5f, 0);
        glDrawArrays(GL_TRIANGLES, 0, verts);
        glXSwapBuffers(dpy, win);
        GLenum err = glGetError();
        if (err != GL_NO_ERROR) {
            fprintf(stderr, "threads_buffers: thread %d frame %d: GL error 0x%x\n", wk->id, f, err);
            wk->failed = 1;
            break;
        }
    }
    if (wk->persistent) glUnmapBuffer(GL_ARRAY_BUFFER);
    glXMakeCurrent(dpy, None, NULL);
    return NULL;
}

int main(int argc, char **argv)
{
    struct app_args a;
    app_parse_args("threads_buffers", argc, argv, &a);
    frames = a.frames;
    XInitThreads();
    dpy = XOpenDisplay(NULL);
    if (!dpy) {
        fprintf(stderr, "threads_buffers: cannot open display\n");
        return 1;
    }
    int attribs[] = {GLX_RGBA, GLX_DOUBLEBUFFER, GLX_RED_SIZE, 8, GLX_GREEN_SIZE, 8, GLX_BLUE_SIZE, 8, None};
    vi = glXChooseVisual(dpy, DefaultScreen(dpy), attribs);
    if (!vi) {
        fprintf(stderr, "threads_buffers: no visual\n");
        return 1;
    }
    struct worker w[2] = {{0, 1, 0, 0}, {1, 0, 0, 0}};
    pthread_t t[2];
    pthread_create(&t[0], NULL, run, &w[0]);
    pthread_mutex_lock(&create_lock);
    while (!shared_root) pthread_cond_wait(&created, &create_lock);
    pthread_mutex_unlock(&create_lock);
    pthread_create(&t[1], NULL, run, &w[1]);
    pthread_join(t[0], NULL);
    pthread_join(t[1], NULL);
    printf("threads_buffers: persistent buffer %u, explicit-flush buffer %u\n", w[0].buffer, w[1].buffer);
    return w[0].failed || w[1].failed;
}
