/*
 * persistent_maps.c - streaming through persistent mapped buffers (glBufferStorage with
 * GL_MAP_PERSISTENT_BIT | GL_MAP_COHERENT_BIT, mapped once, written like a ring, never unmapped
 * between frames), the way GL 4.4 renderers stream per-draw data. Each shape is one way of writing
 * such a mapping that the stream must carry to the slaves at the point the GPU may read it:
 *
 *   ring     each draw writes its triangle at the next 4 KiB-aligned offset of one vertex ring
 *   uniform  each draw writes its colour and offset into a uniform ring read by a shader
 *   unpack   each frame writes an image into a pixel-unpack ring and streams it into a texture
 *   thread   a second thread (no context of its own) writes each frame's triangles into the ring
 *   rewrite  two draws of a frame read the same offset, written again between them (a fence
 *            between them, as GL asks): the second draw must show the second write
 *   sigsegv  the ring, and the program's own SIGSEGV handlers (one installed before the ring is
 *            mapped, one after) must still see the program's own faults
 *   several  three persistent mappings at once, each made visible its own way: positions in a
 *            coherent ring, colours in an explicit-flush ring (glFlushMappedBufferRange), indices
 *            in a small non-coherent ring (glMemoryBarrier(GL_CLIENT_MAPPED_BUFFER_BARRIER_BIT))
 *   contexts two threads, each with its own window, its own context (sharing nothing) and its own
 *            ring, in the ring's shape (frames counted per thread)
 *   crash    the ring for a frame, then a write into a read-only page of the program's own, with
 *            no handler of its own: the program must die of SIGSEGV as it would alone
 *   subdata  the ring's data and draws through glBufferSubData, no mapping: what the same stream
 *            costs without finding changes (bench/persistent_maps_bench.py)
 *
 *   persistent_maps [--shape S] [--ring-mb N] [--draws N] [--frames N] [--size WxH]
 *
 * Every shape checks its own picture at the end (pixels at known places) and prints
 * "persistent_maps: SHAPE ok, N bytes written a frame"; exit 1 on a wrong pixel or a GL error.
 */
#define _GNU_SOURCE
#define GL_GLEXT_PROTOTYPES 1
#include <GL/gl.h>
#include <GL/glext.h>
#include <GL/glx.h>
#include <pthread.h>
#include <setjmp.h>
#include <signal.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>
#include <unistd.h>

#include "../apps/app_common.h"
#include "glx_window.h"

#define SLOT 4096                     /* each draw's data starts on its own 4 KiB boundary */
#define VERTEX_BYTES (8 * sizeof(float)) /* x, y, pad, pad, r, g, b, a */

static const GLbitfield kStorage = GL_MAP_WRITE_BIT | GL_MAP_PERSISTENT_BIT | GL_MAP_COHERENT_BIT;

static int ring_mb = 4, draws = 100;
static const char *shape = "ring";
static size_t ring_bytes, slots;
static unsigned char *ring;
static long written_this_frame;
static int subdata; /* --shape subdata: no mapping, each write a glBufferSubData */

static void die(const char *what)
{
    fprintf(stderr, "persistent_maps: %s\n", what);
    exit(1);
}

static void check_gl(const char *where)
{
    GLenum e = glGetError();
    if (e != GL_NO_ERROR) {
        fprintf(stderr, "persistent_maps: GL error 0x%x %s\n", e, where);
        exit(1);
    }
}

/* Draw k of frame f: its place on a grid of the window and its colour. */
static void triangle_of(int f, int k, int n, float *xy, float *rgba)
{
    int cols = 1;
    while (cols * cols < n) cols++;
    const float cell = 2.0f / cols, x = -1 + cell * (k % cols), y = -1 + cell * (k / cols);
    const float grow = 0.5f + 0.4f * (float)((f + k) % 8) / 7.0f;
    xy[0] = x + 0.05f * cell, xy[1] = y + 0.05f * cell;
    xy[2] = x + cell * grow, xy[3] = y + 0.05f * cell;
    xy[4] = x + 0.05f * cell, xy[5] = y + cell * grow;
    rgba[0] = (float)((f * 7 + k * 3) % 11) / 10.0f;
    rgba[1] = (float)((f * 5 + k) % 13) / 12.0f;
    rgba[2] = (float)(k % 5) / 4.0f;
    rgba[3] = 1;
}

static void write_triangle(unsigned char *at, const float *xy, const float *rgba)
{
    float v[3][8];
    for (int i = 0; i < 3; i++) {
        v[i][0] = xy[2 * i], v[i][1] = xy[2 * i + 1], v[i][2] = 0, v[i][3] = 1;
        memcpy(&v[i][4], rgba, 4 * sizeof(float));
    }
    memcpy(at, v, sizeof v);
    if (subdata) glBufferSubData(GL_ARRAY_BUFFER, at - ring, sizeof v, v);
    __atomic_add_fetch(&written_this_frame, (long)sizeof v, __ATOMIC_RELAXED);
}

/* The pixel at the centre of draw k's triangle, as the program drew it. */
static void probe_of(int f, int k, int n, int w, int h, int *px, int *py, unsigned char *rgb)
{
    float xy[6], rgba[4];
    triangle_of(f, k, n, xy, rgba);
    const float cx = (xy[0] * 2 + xy[2]) / 3, cy = (xy[1] * 2 + xy[5]) / 3; /* inside, near the right angle */
    *px = (int)((cx + 1) / 2 * w), *py = (int)((cy + 1) / 2 * h);
    for (int i = 0; i < 3; i++) rgb[i] = (unsigned char)(rgba[i] * 255 + 0.5f);
}

static int pixel_is(int x, int y, const unsigned char *rgb, const char *what)
{
    unsigned char got[4];
    glReadPixels(x, y, 1, 1, GL_RGBA, GL_UNSIGNED_BYTE, got);
    for (int i = 0; i < 3; i++)
        if (abs(got[i] - rgb[i]) > 2) {
            fprintf(stderr, "persistent_maps: %s at %d,%d: %d %d %d, expected %d %d %d\n", what, x, y, got[0], got[1],
                    got[2], rgb[0], rgb[1], rgb[2]);
            return 0;
        }
    return 1;
}

/* Whether the frame shows draw k of frame f for every eighth k of n draws. */
static int frame_shows(int f, int n, const struct app_args *a, const char *what)
{
    for (int k = 0; k < n; k += (n + 7) / 8) {
        int x, y;
        unsigned char rgb[3];
        probe_of(f, k, n, a->width, a->height, &x, &y, rgb);
        if (!pixel_is(x, y, rgb, what)) return 0;
    }
    return 1;
}

/* --- frame fences: a slot of the ring is written again only after the GPU read it ----- */

static GLsync *fences;
static int fence_count;

static void wait_for_frame(int f)
{
    GLsync *s = &fences[f % fence_count];
    if (*s) {
        glClientWaitSync(*s, GL_SYNC_FLUSH_COMMANDS_BIT, 10000000000ull);
        glDeleteSync(*s);
        *s = 0;
    }
}

static void frame_done(int f) { fences[f % fence_count] = glFenceSync(GL_SYNC_GPU_COMMANDS_COMPLETE, 0); }

static GLuint make_ring(GLenum target)
{
    GLuint b;
    glGenBuffers(1, &b);
    glBindBuffer(target, b);
    if (subdata) {
        glBufferStorage(target, (GLsizeiptr)ring_bytes, NULL, GL_DYNAMIC_STORAGE_BIT);
        ring = malloc(ring_bytes);
    } else {
        glBufferStorage(target, (GLsizeiptr)ring_bytes, NULL, kStorage);
        ring = glMapBufferRange(target, 0, (GLsizeiptr)ring_bytes, kStorage);
    }
    if (!ring) die("glMapBufferRange returned NULL");
    check_gl("mapping the ring");
    slots = ring_bytes / SLOT;
    if (slots < (size_t)draws) die("--ring-mb too small for one frame of --draws");
    fence_count = (int)(slots / (size_t)draws);
    fences = calloc((size_t)fence_count, sizeof *fences);
    return b;
}

/* --- a second thread writes each frame's triangles ---------------------------------------- */

static pthread_mutex_t lock = PTHREAD_MUTEX_INITIALIZER;
static pthread_cond_t wake = PTHREAD_COND_INITIALIZER;
static int job_frame = -1, job_done = -1;

static void write_frame(int f)
{
    for (int k = 0; k < draws; k++) {
        float xy[6], rgba[4];
        triangle_of(f, k, draws, xy, rgba);
        write_triangle(ring + ((size_t)f * draws + k) % slots * SLOT, xy, rgba);
    }
}

static void *writer(void *arg)
{
    (void)arg;
    for (;;) {
        pthread_mutex_lock(&lock);
        while (job_frame == job_done) pthread_cond_wait(&wake, &lock);
        const int f = job_frame;
        pthread_mutex_unlock(&lock);
        if (f < 0) return NULL;
        write_frame(f);
        pthread_mutex_lock(&lock);
        job_done = f;
        pthread_cond_broadcast(&wake);
        pthread_mutex_unlock(&lock);
    }
}

static void ask_writer(int f)
{
    pthread_mutex_lock(&lock);
    job_frame = f;
    pthread_cond_broadcast(&wake);
    while (job_done != f) pthread_cond_wait(&wake, &lock);
    pthread_mutex_unlock(&lock);
}

/* --- the program's own faults ---------------------------------------------------------- */

static sigjmp_buf fault_return;
static volatile sig_atomic_t faults_before, faults_after;
static volatile unsigned char *guard; /* a PROT_NONE page of the program's own */

static void on_fault_before(int sig, siginfo_t *info, void *uc)
{
    (void)sig, (void)uc;
    if (info->si_addr == (void *)guard) faults_before++;
    siglongjmp(fault_return, 1);
}

static void on_fault_after(int sig)
{
    (void)sig;
    faults_after++;
    siglongjmp(fault_return, 1);
}

static void own_fault(void)
{
    if (!sigsetjmp(fault_return, 1)) guard[0] = 1;
}

static void install_before(void)
{
    guard = mmap(NULL, 4096, PROT_NONE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
    if (guard == MAP_FAILED) die("mmap");
    struct sigaction sa;
    memset(&sa, 0, sizeof sa);
    sa.sa_sigaction = on_fault_before;
    sa.sa_flags = SA_SIGINFO;
    sigaction(SIGSEGV, &sa, NULL);
    own_fault();
}

static void install_after(void)
{
    struct sigaction old;
    if (sigaction(SIGSEGV, NULL, &old) != 0 || old.sa_sigaction != on_fault_before)
        die("sigaction(SIGSEGV) does not answer the handler the program installed");
    void (*previous)(int) = signal(SIGSEGV, on_fault_after);
    if ((void *)previous != (void *)on_fault_before)
        die("signal(SIGSEGV) does not return the handler the program installed");
    own_fault();
}

/* --- shapes -------------------------------------------------------------------------------- */

static void setup_fixed_function(void)
{
    glEnableClientState(GL_VERTEX_ARRAY);
    glEnableClientState(GL_COLOR_ARRAY);
    glVertexPointer(2, GL_FLOAT, VERTEX_BYTES, (const void *)0);
    glColorPointer(4, GL_FLOAT, VERTEX_BYTES, (const void *)(4 * sizeof(float)));
}

static void draw_slot(size_t slot) { glDrawArrays(GL_TRIANGLES, (GLint)(slot * SLOT / VERTEX_BYTES), 3); }

static int run_ring(struct glx_window *w, const struct app_args *a, int threaded)
{
    make_ring(GL_ARRAY_BUFFER);
    setup_fixed_function();
    pthread_t t;
    if (threaded) pthread_create(&t, NULL, writer, NULL);
    int ok = 1;
    for (int f = 0; f < a->frames; f++) {
        written_this_frame = 0;
        wait_for_frame(f);
        glClearColor(0.1f, 0.1f, 0.12f, 1);
        glClear(GL_COLOR_BUFFER_BIT);
        if (threaded)
            ask_writer(f);
        for (int k = 0; k < draws; k++) {
            const size_t slot = ((size_t)f * draws + k) % slots;
            if (!threaded) {
                float xy[6], rgba[4];
                triangle_of(f, k, draws, xy, rgba);
                write_triangle(ring + slot * SLOT, xy, rgba);
            }
            draw_slot(slot);
        }
        frame_done(f);
        if (f == a->frames - 1)
            ok = frame_shows(f, draws, a, "a triangle of the last frame");
        glXSwapBuffers(w->dpy, w->win);
        check_gl("in a frame");
    }
    if (threaded) {
        pthread_mutex_lock(&lock);
        job_frame = -1;
        pthread_cond_broadcast(&wake);
        pthread_mutex_unlock(&lock);
        pthread_join(t, NULL);
    }
    return ok;
}

static GLuint compile(const char *vs, const char *fs)
{
    GLuint p = glCreateProgram();
    const char *src[2] = {vs, fs};
    const GLenum kinds[2] = {GL_VERTEX_SHADER, GL_FRAGMENT_SHADER};
    for (int i = 0; i < 2; i++) {
        GLuint s = glCreateShader(kinds[i]);
        glShaderSource(s, 1, &src[i], NULL);
        glCompileShader(s);
        GLint good = 0;
        glGetShaderiv(s, GL_COMPILE_STATUS, &good);
        if (!good) {
            char log[1024];
            glGetShaderInfoLog(s, sizeof log, NULL, log);
            fprintf(stderr, "persistent_maps: shader: %s\n", log);
            exit(1);
        }
        glAttachShader(p, s);
    }
    glLinkProgram(p);
    return p;
}

/* Each draw's uniform block (at the next 4 KiB slot): where its quad goes and its colour. */
static int run_uniform(struct glx_window *w, const struct app_args *a)
{
    GLuint program = compile("#version 140\n"
                             "in vec2 corner;\n"
                             "layout(std140) uniform Draw { vec4 place; vec4 colour; };\n"
                             "void main() { gl_Position = vec4(place.xy + corner * place.zw, 0, 1); }\n",
                             "#version 140\n"
                             "layout(std140) uniform Draw { vec4 place; vec4 colour; };\n"
                             "out vec4 result;\n"
                             "void main() { result = colour; }\n");
    glBindAttribLocation(program, 0, "corner");
    glLinkProgram(program);
    glUniformBlockBinding(program, glGetUniformBlockIndex(program, "Draw"), 0);
    glUseProgram(program);
    static const float corners[6] = {0, 0, 1, 0, 0, 1};
    GLuint vbo;
    glGenBuffers(1, &vbo);
    glBindBuffer(GL_ARRAY_BUFFER, vbo);
    glBufferData(GL_ARRAY_BUFFER, sizeof corners, corners, GL_STATIC_DRAW);
    glEnableVertexAttribArray(0);
    glVertexAttribPointer(0, 2, GL_FLOAT, GL_FALSE, 0, (const void *)0);
    GLuint ubo = make_ring(GL_UNIFORM_BUFFER);
    int ok = 1;
    for (int f = 0; f < a->frames; f++) {
        written_this_frame = 0;
        wait_for_frame(f);
        glClearColor(0.1f, 0.1f, 0.12f, 1);
        glClear(GL_COLOR_BUFFER_BIT);
        for (int k = 0; k < draws; k++) {
            const size_t slot = ((size_t)f * draws + k) % slots;
            float xy[6], block[8];
            triangle_of(f, k, draws, xy, block + 4);
            block[0] = xy[0], block[1] = xy[1], block[2] = xy[2] - xy[0], block[3] = xy[5] - xy[1];
            memcpy(ring + slot * SLOT, block, sizeof block);
            written_this_frame += (long)sizeof block;
            glBindBufferRange(GL_UNIFORM_BUFFER, 0, ubo, (GLintptr)(slot * SLOT), sizeof block);
            glDrawArrays(GL_TRIANGLES, 0, 3);
        }
        frame_done(f);
        if (f == a->frames - 1)
            ok = frame_shows(f, draws, a, "a uniform-ring quad of the last frame");
        glXSwapBuffers(w->dpy, w->win);
        check_gl("in a frame");
    }
    return ok;
}

/* Each frame writes a TEX x TEX image into the next slots of a pixel-unpack ring and uploads it. */
#define TEX 64
static int run_unpack(struct glx_window *w, const struct app_args *a)
{
    draws = 1;
    const size_t image = TEX * TEX * 4, per_frame = (image + SLOT - 1) / SLOT;
    make_ring(GL_PIXEL_UNPACK_BUFFER);
    fence_count = (int)(slots / per_frame);
    GLuint tex;
    glGenTextures(1, &tex);
    glBindTexture(GL_TEXTURE_2D, tex);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, TEX, TEX, 0, GL_RGBA, GL_UNSIGNED_BYTE, (const void *)0);
    glEnable(GL_TEXTURE_2D);
    int ok = 1;
    for (int f = 0; f < a->frames; f++) {
        written_this_frame = 0;
        wait_for_frame(f);
        const size_t at = ((size_t)f * per_frame) % (slots - slots % per_frame) * SLOT;
        unsigned char *p = ring + at;
        for (int y = 0; y < TEX; y++)
            for (int x = 0; x < TEX; x++, p += 4)
                p[0] = (unsigned char)(x * 4 + f), p[1] = (unsigned char)(y * 4), p[2] = (unsigned char)(f * 16),
                p[3] = 255;
        written_this_frame += (long)image;
        glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, TEX, TEX, GL_RGBA, GL_UNSIGNED_BYTE, (const void *)at);
        glClear(GL_COLOR_BUFFER_BIT);
        glBegin(GL_QUADS);
        glTexCoord2f(0, 0), glVertex2f(-0.9f, -0.9f);
        glTexCoord2f(1, 0), glVertex2f(0.9f, -0.9f);
        glTexCoord2f(1, 1), glVertex2f(0.9f, 0.9f);
        glTexCoord2f(0, 1), glVertex2f(-0.9f, 0.9f);
        glEnd();
        frame_done(f);
        if (f == a->frames - 1) {
            /* texel (10, 20) of the last image */
            const int x = (int)((-0.9f + 1.8f * (10.5f / TEX) + 1) / 2 * a->width);
            const int y = (int)((-0.9f + 1.8f * (20.5f / TEX) + 1) / 2 * a->height);
            const unsigned char rgb[3] = {(unsigned char)(40 + f), 80, (unsigned char)(f * 16)};
            ok = pixel_is(x, y, rgb, "the streamed texture");
        }
        glXSwapBuffers(w->dpy, w->win);
        check_gl("in a frame");
    }
    return ok;
}

static void *map_persistent(GLenum target, size_t bytes, GLbitfield flags, GLuint *name)
{
    glGenBuffers(1, name);
    glBindBuffer(target, *name);
    glBufferStorage(target, (GLsizeiptr)bytes, NULL, flags & ~GL_MAP_FLUSH_EXPLICIT_BIT);
    void *p = glMapBufferRange(target, 0, (GLsizeiptr)bytes, flags);
    if (!p) die("glMapBufferRange returned NULL");
    return p;
}

/* Draw k's three vertices are vertices slot * 256 + 0..2 of the position and colour rings (16 bytes
 * each, so that both index alike); its three indices are the 16 bytes at slot * 16 of the index ring. */
static int run_several(struct glx_window *w, const struct app_args *a)
{
    const GLbitfield write = GL_MAP_WRITE_BIT | GL_MAP_PERSISTENT_BIT;
    GLuint positions, colours, indices;
    float *pos = map_persistent(GL_ARRAY_BUFFER, ring_bytes, write | GL_MAP_COHERENT_BIT, &positions);
    glVertexPointer(2, GL_FLOAT, 16, (const void *)0);
    float *col = map_persistent(GL_ARRAY_BUFFER, ring_bytes, write | GL_MAP_FLUSH_EXPLICIT_BIT, &colours);
    glColorPointer(4, GL_FLOAT, 16, (const void *)0);
    slots = ring_bytes / SLOT;
    GLuint *idx = map_persistent(GL_ELEMENT_ARRAY_BUFFER, slots * 16, write, &indices);
    check_gl("mapping three rings");
    glEnableClientState(GL_VERTEX_ARRAY);
    glEnableClientState(GL_COLOR_ARRAY);
    if (slots < (size_t)draws) die("--ring-mb too small for one frame of --draws");
    fence_count = (int)(slots / (size_t)draws);
    fences = calloc((size_t)fence_count, sizeof *fences);
    int ok = 1;
    for (int f = 0; f < a->frames; f++) {
        written_this_frame = 0;
        wait_for_frame(f);
        glClearColor(0.1f, 0.1f, 0.12f, 1);
        glClear(GL_COLOR_BUFFER_BIT);
        for (int k = 0; k < draws; k++) {
            const size_t slot = ((size_t)f * draws + k) % slots, vertex = slot * SLOT / 16;
            float xy[6], rgba[4];
            triangle_of(f, k, draws, xy, rgba);
            for (int i = 0; i < 3; i++) {
                memcpy(pos + (vertex + i) * 4, xy + 2 * i, 2 * sizeof(float));
                memcpy(col + (vertex + i) * 4, rgba, sizeof rgba);
                idx[slot * 4 + i] = (GLuint)(vertex + i);
            }
            written_this_frame += 3 * (8 + 16 + 4);
            glBindBuffer(GL_ARRAY_BUFFER, colours);
            glFlushMappedBufferRange(GL_ARRAY_BUFFER, (GLintptr)(vertex * 16), 48);
            glMemoryBarrier(GL_CLIENT_MAPPED_BUFFER_BARRIER_BIT);
            glDrawElements(GL_TRIANGLES, 3, GL_UNSIGNED_INT, (const void *)(slot * 16));
        }
        frame_done(f);
        if (f == a->frames - 1)
            ok = frame_shows(f, draws, a, "a triangle of the last frame");
        glXSwapBuffers(w->dpy, w->win);
        check_gl("in a frame");
    }
    return ok;
}

/* One of two threads of --shape contexts: its own window, context and ring. */
struct context_thread {
    const struct app_args *a;
    int id, ok;
};
static pthread_mutex_t window_lock = PTHREAD_MUTEX_INITIALIZER;

static void *run_context(void *arg)
{
    struct context_thread *t = arg;
    const struct app_args *a = t->a;
    int attribs[] = {GLX_RGBA, GLX_DOUBLEBUFFER, GLX_RED_SIZE, 8, GLX_GREEN_SIZE, 8, GLX_BLUE_SIZE, 8, None};
    pthread_mutex_lock(&window_lock);
    struct glx_window w = glx_window_open("persistent_maps", a, attribs, "RGB");
    pthread_mutex_unlock(&window_lock);
    glViewport(0, 0, a->width, a->height);
    const GLbitfield flags = GL_MAP_WRITE_BIT | GL_MAP_PERSISTENT_BIT | GL_MAP_COHERENT_BIT;
    GLuint b;
    unsigned char *mine = map_persistent(GL_ARRAY_BUFFER, ring_bytes, flags, &b);
    setup_fixed_function();
    const size_t n = ring_bytes / SLOT;
    t->ok = 1;
    for (int f = 0; f < a->frames; f++) {
        glClearColor(0.1f, 0.1f * t->id, 0.12f, 1);
        glClear(GL_COLOR_BUFFER_BIT);
        for (int k = 0; k < draws; k++) {
            const size_t slot = ((size_t)f * draws + k) % n;
            float xy[6], rgba[4];
            triangle_of(f + 3 * t->id, k, draws, xy, rgba);
            write_triangle(mine + slot * SLOT, xy, rgba);
            draw_slot(slot);
        }
        glFinish(); /* the ring's next slots are written only after the GPU read these */
        if (f == a->frames - 1)
            t->ok = frame_shows(f + 3 * t->id, draws, a, "a triangle of a thread's last frame");
        glXSwapBuffers(w.dpy, w.win);
        check_gl("in a frame");
    }
    glUnmapBuffer(GL_ARRAY_BUFFER);
    pthread_mutex_lock(&window_lock);
    glx_window_close(&w);
    pthread_mutex_unlock(&window_lock);
    return NULL;
}

static int run_contexts(const struct app_args *a)
{
    struct context_thread t[2] = {{a, 0, 0}, {a, 1, 0}};
    pthread_t th[2];
    for (int i = 0; i < 2; i++) pthread_create(&th[i], NULL, run_context, &t[i]);
    for (int i = 0; i < 2; i++) pthread_join(th[i], NULL);
    written_this_frame /= a->frames * 2; /* a frame of one thread */
    return t[0].ok && t[1].ok;
}

/* Two draws of a frame read slot 0; between them (after a fence on the first) it is written again. */
static int run_rewrite(struct glx_window *w, const struct app_args *a)
{
    make_ring(GL_ARRAY_BUFFER);
    setup_fixed_function();
    int ok = 1;
    for (int f = 0; f < a->frames; f++) {
        written_this_frame = 0;
        glClearColor(0.1f, 0.1f, 0.12f, 1);
        glClear(GL_COLOR_BUFFER_BIT);
        for (int k = 0; k < 2; k++) {
            float xy[6], rgba[4];
            triangle_of(f, k, 2, xy, rgba);
            write_triangle(ring, xy, rgba);
            draw_slot(0);
            GLsync read = glFenceSync(GL_SYNC_GPU_COMMANDS_COMPLETE, 0);
            glClientWaitSync(read, GL_SYNC_FLUSH_COMMANDS_BIT, 10000000000ull);
            glDeleteSync(read);
        }
        if (f == a->frames - 1)
            for (int k = 0; k < 2 && ok; k++) {
                int x, y;
                unsigned char rgb[3];
                probe_of(f, k, 2, a->width, a->height, &x, &y, rgb);
                ok = pixel_is(x, y, rgb, k ? "the second draw (second write)" : "the first draw (first write)");
            }
        glXSwapBuffers(w->dpy, w->win);
        check_gl("in a frame");
    }
    return ok;
}

int main(int argc, char **argv)
{
    /* this program's own options first, then app_common's */
    int i = 1;
    for (; i + 1 < argc; i += 2) {
        if (strcmp(argv[i], "--shape") == 0)
            shape = argv[i + 1];
        else if (strcmp(argv[i], "--ring-mb") == 0)
            ring_mb = atoi(argv[i + 1]);
        else if (strcmp(argv[i], "--draws") == 0)
            draws = atoi(argv[i + 1]);
        else
            break;
    }
    argv[i - 1] = argv[0];
    struct app_args a;
    app_parse_args("persistent_maps", argc - (i - 1), argv + (i - 1), &a);
    if (ring_mb < 1 || ring_mb > 4096 || draws < 1 || draws > 100000) die("bad --ring-mb or --draws");
    ring_bytes = (size_t)ring_mb << 20;
    if (strcmp(shape, "contexts") == 0) {
        XInitThreads();
        if (!run_contexts(&a)) return 1;
        printf("persistent_maps: contexts ok, %ld bytes written a frame\n", written_this_frame);
        return 0;
    }
    int attribs[] = {GLX_RGBA, GLX_DOUBLEBUFFER, GLX_RED_SIZE, 8, GLX_GREEN_SIZE, 8, GLX_BLUE_SIZE, 8, None};
    struct glx_window w = glx_window_open("persistent_maps", &a, attribs, "RGB");
    glViewport(0, 0, a.width, a.height);
    const int sigsegv = strcmp(shape, "sigsegv") == 0;
    if (sigsegv) install_before();
    int ok;
    subdata = strcmp(shape, "subdata") == 0;
    if (strcmp(shape, "ring") == 0 || sigsegv || subdata) {
        if (sigsegv) {
            make_ring(GL_ARRAY_BUFFER); /* mapped: glcast's own handler (if any) is in place now */
            own_fault();
            install_after();
            a.frames = a.frames > 1 ? a.frames : 2;
            glUnmapBuffer(GL_ARRAY_BUFFER);
            ok = run_ring(&w, &a, 0);
            own_fault();
            if (faults_before != 2 || faults_after != 2) {
                fprintf(stderr, "persistent_maps: the program's own handlers saw %d and %d faults, expected 2 and 2\n",
                        (int)faults_before, (int)faults_after);
                ok = 0;
            }
        } else {
            ok = run_ring(&w, &a, 0);
        }
    } else if (strcmp(shape, "several") == 0) {
        ok = run_several(&w, &a);
    } else if (strcmp(shape, "crash") == 0) {
        a.frames = 1;
        ok = run_ring(&w, &a, 0);
        unsigned char *own = mmap(NULL, 4096, PROT_READ, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
        if (own == MAP_FAILED) die("mmap");
        printf("persistent_maps: crash: writing into a read-only page\n");
        fflush(stdout);
        own[0] = (unsigned char)ok;
        die("the write into a read-only page did not fault");
    } else if (strcmp(shape, "thread") == 0) {
        ok = run_ring(&w, &a, 1);
    } else if (strcmp(shape, "uniform") == 0) {
        ok = run_uniform(&w, &a);
    } else if (strcmp(shape, "unpack") == 0) {
        ok = run_unpack(&w, &a);
    } else if (strcmp(shape, "rewrite") == 0) {
        ok = run_rewrite(&w, &a);
    } else {
        die("unknown --shape (ring, uniform, unpack, thread, rewrite, sigsegv, several, contexts, crash, subdata)");
    }
    if (!ok) return 1;
    printf("persistent_maps: %s ok, %ld bytes written a frame\n", shape, written_this_frame);
    glx_window_close(&w);
    return 0;
}
