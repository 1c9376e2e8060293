/*
 * exit_paths.c - a GL program that ends in each of the ways real programs end, making GL and GLX
 * calls on the way out as toolkits do (SDL_Quit under atexit, a singleton that owns the context,
 * a thread that releases its context as it exits). For glcast's tests: the program must end
 * exactly as it does without glcast, and its capture must be complete, with every call made on
 * the way out, or (for _exit and a fatal signal) readable to its last whole message.
 *
 *   exit_paths MODE [--frames N]
 *
 * Every mode draws N frames (a clear whose colour moves, and a triangle), then leaves an open
 * frame: a clear to the colour (0.25, 0.5, 0.75) and a glFinish, not swapped. Then, by MODE:
 *   return        main returns
 *   atexit        exit(0); an atexit handler makes the context current again, clears to
 *                 (0.125, 0.25, 0.375), releases and destroys it (after glibc's thread-local
 *                 destructors have run)
 *   destructor    main returns; a destructor of a shared library the program links (a toolkit's
 *                 singleton) clears, releases and destroys the context
 *   thread        the frames are drawn by a second thread; a pthread key's destructor of the
 *                 program, run as that thread exits, clears and releases its context; a third
 *                 thread makes its first GL call of all in its key destructor; main returns
 *   last-thread   the frames are drawn by a second thread; main calls pthread_exit, so the
 *                 process ends when the drawing thread returns (glibc's exit from the last thread;
 *                 with the driver's own threads off: LP_NUM_THREADS=0 MESA_SHADER_CACHE_DISABLE=true)
 *   threads-exit  three threads, each with a window and a context of its own, draw the frames
 *                 together; then the first leaves its open frame and calls exit(0) while the
 *                 other two wait, their contexts released; main waits on the first
 *   fork          after half the frames the program forks: the child sets the clear colour to
 *                 (1, 0, 1) and calls exit(0); the parent waits for it (a nonzero status of the
 *                 child's becomes the program's) and draws the rest
 *   dlclose       the program does not link libGL: it opens it with dlopen, draws half the
 *                 frames, destroys its context and dlcloses it, then opens it again and draws
 *                 the rest (the other modes open libGL with dlopen too, and keep it)
 *   _exit         _exit(0) after the open frame: no exit handler runs
 *   signal        raise(SIGSEGV) after the open frame, as a crashing program does
 * Prints "exit_paths: MODE done" before it ends.
 */
#include <GL/gl.h>
#include <GL/glx.h>
#include <X11/Xlib.h>
#include <dlfcn.h>
#include <pthread.h>
#include <signal.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

#include "../apps/app_common.h"
#include "exit_paths_teardown.h"

/* The GL and GLX functions the program calls, from dlopen's handle: the program does not link libGL, so
 * that dlclose can unload it. */
struct gl {
    void *library;
    XVisualInfo *(*ChooseVisual)(Display *, int, int *);
    GLXContext (*CreateContext)(Display *, XVisualInfo *, GLXContext, Bool);
    Bool (*MakeCurrent)(Display *, GLXDrawable, GLXContext);
    void (*DestroyContext)(Display *, GLXContext);
    void (*SwapBuffers)(Display *, GLXDrawable);
    void (*ClearColor)(GLfloat, GLfloat, GLfloat, GLfloat);
    void (*Clear)(GLbitfield);
    void (*Begin)(GLenum);
    void (*Vertex2f)(GLfloat, GLfloat);
    void (*End)(void);
    void (*Finish)(void);
};

static struct gl gl;
static Display *dpy;
static XVisualInfo *vi;
static Window win;
static GLXContext ctx;
static struct app_args args;
static const char *mode;

static void *must(void *p, const char *name)
{
    if (!p) {
        fprintf(stderr, "exit_paths: %s: %s\n", name, dlerror());
        exit(1);
    }
    return p;
}

#define LOAD(field, name) *(void **)&gl.field = must(dlsym(gl.library, name), name)

static void opened_gl(void)
{
    gl.library = must(dlopen("libGL.so.1", RTLD_NOW | RTLD_LOCAL), "libGL.so.1");
    LOAD(ChooseVisual, "glXChooseVisual");
    LOAD(CreateContext, "glXCreateContext");
    LOAD(MakeCurrent, "glXMakeCurrent");
    LOAD(DestroyContext, "glXDestroyContext");
    LOAD(SwapBuffers, "glXSwapBuffers");
    LOAD(ClearColor, "glClearColor");
    LOAD(Clear, "glClear");
    LOAD(Begin, "glBegin");
    LOAD(Vertex2f, "glVertex2f");
    LOAD(End, "glEnd");
    LOAD(Finish, "glFinish");
}

static void open_window(void)
{
    dpy = XOpenDisplay(NULL);
    if (!dpy) {
        fprintf(stderr, "exit_paths: cannot open display\n");
        exit(1);
    }
    int attribs[] = {GLX_RGBA, GLX_DOUBLEBUFFER, GLX_RED_SIZE, 8, GLX_GREEN_SIZE, 8, GLX_BLUE_SIZE, 8, None};
    vi = gl.ChooseVisual(dpy, DefaultScreen(dpy), attribs);
    if (!vi) {
        fprintf(stderr, "exit_paths: no RGBA double-buffered visual\n");
        exit(1);
    }
    XSetWindowAttributes swa;
    swa.colormap = XCreateColormap(dpy, RootWindow(dpy, vi->screen), vi->visual, AllocNone);
    win = XCreateWindow(dpy, RootWindow(dpy, vi->screen), 0, 0, args.width, args.height, 0, vi->depth, InputOutput,
                        vi->visual, CWColormap, &swa);
    XMapWindow(dpy, win);
    XSync(dpy, False);
}

static void draw_frames(int from, int to)
{
    for (int f = from; f < to; f++) {
        const float t = (float)f / (float)args.frames;
        gl.ClearColor(0.1f + 0.5f * t, 0.2f, 0.3f, 1);
        gl.Clear(GL_COLOR_BUFFER_BIT);
        gl.Begin(GL_TRIANGLES);
        gl.Vertex2f(-0.5f, -0.5f);
        gl.Vertex2f(0.5f, -0.5f);
        gl.Vertex2f(0.0f, 0.2f + 0.6f * t);
        gl.End();
        gl.SwapBuffers(dpy, win);
    }
}

static void open_frame(void)
{
    gl.ClearColor(0.25f, 0.5f, 0.75f, 1);
    gl.Clear(GL_COLOR_BUFFER_BIT);
    gl.Finish();
}

/* What a toolkit does on the way out: the context current once more, a last clear, then gone. */
static void teardown(float shade)
{
    gl.MakeCurrent(dpy, win, ctx);
    gl.ClearColor(shade, 2 * shade, 3 * shade, 1);
    gl.Clear(GL_COLOR_BUFFER_BIT);
    gl.MakeCurrent(dpy, None, NULL);
    gl.DestroyContext(dpy, ctx);
}

static void teardown_at_exit(void) { teardown(0.125f); }

static void library_teardown(void) { teardown(0.0625f); }

/* --- thread modes ------------------------------------------------------------------------ */

static pthread_key_t release_key;
static GLXContext second_ctx;

/* Run as a thread exits, after its thread-local destructors. */
static void release_at_thread_exit(void *which)
{
    if (which == (void *)1) { /* the drawing thread: its context released on its way out */
        gl.ClearColor(0.125f, 0.25f, 0.375f, 1);
        gl.Clear(GL_COLOR_BUFFER_BIT);
        gl.MakeCurrent(dpy, None, NULL);
    } else { /* a thread whose first GL call of all is made as it exits */
        gl.MakeCurrent(dpy, win, second_ctx);
        gl.ClearColor(0.0625f, 0.125f, 0.1875f, 1);
        gl.Clear(GL_COLOR_BUFFER_BIT);
        gl.Finish();
        gl.MakeCurrent(dpy, None, NULL);
    }
}

static void *drawing_thread(void *unused)
{
    (void)unused;
    gl.MakeCurrent(dpy, win, ctx);
    pthread_setspecific(release_key, (void *)1);
    draw_frames(0, args.frames);
    open_frame();
    if (strcmp(mode, "last-thread") == 0) printf("exit_paths: %s done\n", mode);
    fflush(stdout);
    return NULL;
}

static void *exiting_thread(void *unused)
{
    (void)unused;
    pthread_setspecific(release_key, (void *)2);
    return NULL;
}

static void run_threads(void)
{
    pthread_key_create(&release_key, release_at_thread_exit);
    second_ctx = gl.CreateContext(dpy, vi, ctx, True);
    pthread_t t;
    pthread_create(&t, NULL, drawing_thread, NULL);
    if (strcmp(mode, "last-thread") == 0) pthread_exit(NULL);
    pthread_join(t, NULL);
    pthread_create(&t, NULL, exiting_thread, NULL);
    pthread_join(t, NULL);
    gl.DestroyContext(dpy, second_ctx);
}

/* --- several contexts, exit from a thread -------------------------------------------------- */

enum { kDrawers = 3 };
static Display *drawer_displays[kDrawers];  /* a connection each, as toolkits' threads have */
static Window drawer_windows[kDrawers];
static GLXContext drawer_contexts[kDrawers];
static pthread_barrier_t drawn;

static void *drawer(void *which)
{
    const int i = (int)(intptr_t)which;
    Display *const own = drawer_displays[i];
    gl.MakeCurrent(own, drawer_windows[i], drawer_contexts[i]);
    for (int f = 0; f < args.frames; f++) {
        gl.ClearColor(0.1f * (float)(i + 1), 0.2f, 0.3f + 0.05f * (float)f, 1);
        gl.Clear(GL_COLOR_BUFFER_BIT);
        gl.SwapBuffers(own, drawer_windows[i]);
    }
    pthread_barrier_wait(&drawn);
    if (i == 0) {
        open_frame();
        printf("exit_paths: %s done\n", mode);
        fflush(stdout);
        exit(0);
    }
    /* Its context released, it waits for the process to end (drawing on as another thread
     * calls exit races the libraries' destructors, alone too: 2 of 20 runs died so). */
    gl.MakeCurrent(own, None, NULL);
    for (;;) pause();
    return NULL;
}

static void run_threads_exit(void)
{
    pthread_barrier_init(&drawn, NULL, kDrawers);
    pthread_t threads[kDrawers];
    for (int i = 0; i < kDrawers; i++) {
        if (i > 0) open_window();  /* the first is main's */
        drawer_displays[i] = dpy;
        drawer_windows[i] = win;
        drawer_contexts[i] = gl.CreateContext(dpy, vi, NULL, True);
    }
    for (int i = 0; i < kDrawers; i++) pthread_create(&threads[i], NULL, drawer, (void *)(intptr_t)i);
    pthread_join(threads[0], NULL);  /* never returns: the thread ends the process */
}

/* --- fork -------------------------------------------------------------------------------- */

/* A forked child cannot draw with its parent's context (the driver's threads stayed in the parent),
 * but it runs code that calls GL: here a state change, then exit, whose handlers are its parent's. */
static int child_calls(void)
{
    gl.ClearColor(1, 0, 1, 1);
    return 0;
}

static int run_fork(void)
{
    draw_frames(0, args.frames / 2);
    fflush(stdout);
    const pid_t child = fork();
    if (child < 0) return 6;
    if (child == 0) exit(child_calls()); /* exit, not _exit: the child's exit handlers run too */
    int status = 0;
    if (waitpid(child, &status, 0) != child) return 7;
    if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) {
        fprintf(stderr, "exit_paths: the forked child ended with status 0x%x\n", status);
        return 8;
    }
    draw_frames(args.frames / 2, args.frames);
    return 0;
}

/* --- dlclose ----------------------------------------------------------------------------- */

static void run_dlclose(void)
{
    for (int round = 0; round < 2; round++) {
        opened_gl();
        if (round == 0) open_window();
        ctx = gl.CreateContext(dpy, vi, NULL, True);
        gl.MakeCurrent(dpy, win, ctx);
        draw_frames(round * args.frames / 2, round ? args.frames : args.frames / 2);
        gl.MakeCurrent(dpy, None, NULL);
        gl.DestroyContext(dpy, ctx);
        if (dlclose(gl.library) != 0) {
            fprintf(stderr, "exit_paths: dlclose: %s\n", dlerror());
            exit(1);
        }
    }
}

int main(int argc, char **argv)
{
    static const char *const modes[] = {"return", "atexit", "destructor", "thread", "last-thread",
                                        "threads-exit", "fork", "dlclose", "_exit", "signal"};
    mode = argc > 1 ? argv[1] : "";
    int known = 0;
    for (size_t i = 0; i < sizeof modes / sizeof *modes; i++) known |= strcmp(mode, modes[i]) == 0;
    if (!known) {
        fprintf(stderr, "exit_paths: unknown mode '%s' (return, atexit, destructor, thread, last-thread, threads-exit, fork, "
                        "dlclose, _exit or signal)\n", mode);
        return 2;
    }
    argv[1] = argv[0];
    app_parse_args("exit_paths", argc - 1, argv + 1, &args);
    if (strcmp(mode, "dlclose") == 0) {
        run_dlclose();
        printf("exit_paths: %s done\n", mode);
        return 0;
    }
    const int threaded = strcmp(mode, "thread") == 0 || strcmp(mode, "last-thread") == 0 ||
                         strcmp(mode, "threads-exit") == 0;
    if (threaded) XInitThreads();
    opened_gl();
    open_window();
    if (strcmp(mode, "threads-exit") == 0) run_threads_exit();
    ctx = gl.CreateContext(dpy, vi, NULL, True);
    if (threaded) {
        run_threads();
        printf("exit_paths: %s done\n", mode);
        return 0;
    }
    gl.MakeCurrent(dpy, win, ctx);
    if (strcmp(mode, "fork") == 0) {
        const int status = run_fork();
        printf("exit_paths: %s done\n", mode);
        return status;
    }
    draw_frames(0, args.frames);
    open_frame();
    printf("exit_paths: %s done\n", mode);
    fflush(stdout);
    if (strcmp(mode, "atexit") == 0) {
        atexit(teardown_at_exit);
        exit(0);
    }
    if (strcmp(mode, "destructor") == 0) exit_paths_teardown_at_unload(library_teardown);
    if (strcmp(mode, "_exit") == 0) _exit(0);
    if (strcmp(mode, "signal") == 0) {
        signal(SIGSEGV, SIG_DFL);
        raise(SIGSEGV);
    }
    return 0;
}
