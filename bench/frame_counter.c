/* Benchmark helper, preloaded before whatever is measured: counts glXSwapBuffers and
 * eglSwapBuffers, and after FRAME_COUNTER_EXIT frames prints the time from frame
 * FRAME_COUNTER_SKIP to the last one, and the CPU time the whole process (every thread: the
 * program's, the driver's, glcast's writer) spent in those frames, and ends the program. Start-up
 * (context creation, the driver's shader compiles) is left out of both. Costs one clock read per
 * frame. FRAME_COUNTER_FPS=N paces the program to N frames a second (it sleeps after each swap
 * until the next tick), as a program held by a display's refresh would be. */
#define _GNU_SOURCE
#include <dlfcn.h>
#include <stdio.h>
#include <stdlib.h>
#include <sys/resource.h>
#include <time.h>
#include <unistd.h>

static long frames, skip = 10, stop;
static double t0, cpu0;

static double now(void) {
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ts.tv_sec + ts.tv_nsec * 1e-9;
}

static double process_cpu(void) {
    struct rusage r;
    getrusage(RUSAGE_SELF, &r);
    return r.ru_utime.tv_sec + r.ru_utime.tv_usec * 1e-6 + r.ru_stime.tv_sec + r.ru_stime.tv_usec * 1e-6;
}

static void pace(void) {
    static double period = -1, next;
    if (period < 0) {
        const char* f = getenv("FRAME_COUNTER_FPS");
        period = f && atof(f) > 0 ? 1.0 / atof(f) : 0;
        next = now();
    }
    if (period == 0) return;
    next += period;
    const double wait = next - now();
    if (wait > 0) {
        struct timespec ts = {(time_t)wait, (long)((wait - (time_t)wait) * 1e9)};
        nanosleep(&ts, NULL);
    } else {
        next = now();  /* late: from now on, not a burst to make up */
    }
}

static void frame(void) {
    pace();
    if (!stop) {
        const char* s = getenv("FRAME_COUNTER_EXIT");
        const char* k = getenv("FRAME_COUNTER_SKIP");
        stop = s ? atol(s) : 1000000000L;
        if (k) skip = atol(k);
    }
    if (++frames == skip) {
        t0 = now();
        cpu0 = process_cpu();
    }
    if (frames == stop) {
        const double dt = now() - t0, cpu = process_cpu() - cpu0;
        fprintf(stderr, "frame_counter: %ld frames in %.4f s = %.2f fps, cpu %.4f s\n", frames - skip, dt,
                (frames - skip) / dt, cpu);
        fflush(stderr);
        _exit(0);
    }
}

void glXSwapBuffers(void* dpy, unsigned long drawable) {
    static void (*real)(void*, unsigned long);
    if (!real) real = (void (*)(void*, unsigned long))dlsym(RTLD_NEXT, "glXSwapBuffers");
    real(dpy, drawable);
    frame();
}

unsigned eglSwapBuffers(void* dpy, void* surface) {
    static unsigned (*real)(void*, void*);
    if (!real) real = (unsigned (*)(void*, void*))dlsym(RTLD_NEXT, "eglSwapBuffers");
    unsigned r = real(dpy, surface);
    frame();
    return r;
}
