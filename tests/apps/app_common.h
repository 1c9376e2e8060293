/*
 * app_common.h - shared helpers for the glcast test applications:
 * command line parsing and PPM writing. Header only, no GL calls (so the
 * GLFW app that does not link libGL can use it too).
 *
 * Command line (all apps):
 *   --frames N          render exactly N frames (default 120, N >= 1)
 *   --size WxH          window size (default 320x240)
 *   --screenshot PATH   on the last frame, read the back buffer before the
 *                       swap and write it as a binary PPM (P6)
 *   --help              print usage, exit 0
 * Bad arguments: a message naming the argument on stderr, exit 2.
 */
#ifndef GLCAST_TEST_APP_COMMON_H
#define GLCAST_TEST_APP_COMMON_H

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define APP_PI 3.14159265358979323846f

struct app_args {
    int frames;
    int width;
    int height;
    const char *screenshot;
    int dolly; /* --camera dolly: the camera moves straight forward (apps that have a camera) */
};

static void app_usage(FILE *f, const char *prog)
{
    fprintf(f,
            "usage: %s [--frames N] [--size WxH] [--screenshot PATH.ppm] [--camera orbit|dolly]\n"
            "  --frames N         frames to render, each ending in a swap (default 120)\n"
            "  --size WxH         window size in pixels (default 320x240)\n"
            "  --screenshot PATH  write the last frame (back buffer, before the swap) as PPM\n"
            "  --camera MODE      orbit (default) or dolly: straight forward (scenes with a camera)\n",
            prog);
}

static int app_parse_int(const char *s, long lo, long hi, int *out)
{
    char *end = NULL;
    long v;
    if (s == NULL || *s == '\0')
        return -1;
    errno = 0;
    v = strtol(s, &end, 10);
    if (errno != 0 || end == s || v < lo || v > hi)
        return -1;
    if (out != NULL)
        *out = (int)v;
    /* allow the caller to continue parsing after the number */
    return (int)(end - s);
}

/* Parses argv; on error prints a message naming the argument and exits 2. */
/* A program's own first argument (e.g. --plain), taken off before app_parse_args: 1 if it was there. */
__attribute__((unused)) static int app_take_flag(int *argc, char ***argv, const char *flag)
{
    if (*argc < 2 || strcmp((*argv)[1], flag) != 0)
        return 0;
    (*argv)[1] = (*argv)[0];
    (*argv)++;
    (*argc)--;
    return 1;
}

static void app_parse_args(const char *prog, int argc, char **argv, struct app_args *a)
{
    int i;
    a->frames = 120;
    a->width = 320;
    a->height = 240;
    a->screenshot = NULL;
    a->dolly = 0;
    for (i = 1; i < argc; i++) {
        const char *arg = argv[i];
        if (strcmp(arg, "--help") == 0 || strcmp(arg, "-h") == 0) {
            app_usage(stdout, prog);
            exit(0);
        } else if (strcmp(arg, "--frames") == 0 || strcmp(arg, "--size") == 0 ||
                   strcmp(arg, "--screenshot") == 0) {
            const char *val;
            if (i + 1 >= argc) {
                fprintf(stderr, "%s: argument %s needs a value\n", prog, arg);
                app_usage(stderr, prog);
                exit(2);
            }
            val = argv[++i];
            if (strcmp(arg, "--frames") == 0) {
                int n = app_parse_int(val, 1, 100000000L, &a->frames);
                if (n < 0 || val[n] != '\0') {
                    fprintf(stderr, "%s: bad value for --frames: '%s' (want an integer >= 1)\n",
                            prog, val);
                    exit(2);
                }
            } else if (strcmp(arg, "--size") == 0) {
                int n = app_parse_int(val, 1, 8192, &a->width);
                int m = -1;
                if (n > 0 && (val[n] == 'x' || val[n] == 'X'))
                    m = app_parse_int(val + n + 1, 1, 8192, &a->height);
                if (n < 0 || m < 0 || val[n + 1 + m] != '\0') {
                    fprintf(stderr, "%s: bad value for --size: '%s' (want WxH, e.g. 320x240)\n",
                            prog, val);
                    exit(2);
                }
            } else {
                if (val[0] == '\0') {
                    fprintf(stderr, "%s: bad value for --screenshot: empty path\n", prog);
                    exit(2);
                }
                a->screenshot = val;
            }
        } else if (strcmp(arg, "--camera") == 0 && i + 1 < argc &&
                   (strcmp(argv[i + 1], "orbit") == 0 || strcmp(argv[i + 1], "dolly") == 0)) {
            a->dolly = strcmp(argv[++i], "dolly") == 0;
        } else {
            fprintf(stderr, "%s: unknown argument '%s'\n", prog, arg);
            app_usage(stderr, prog);
            exit(2);
        }
    }
}

/* rgb: width*height*3 bytes, rows bottom-up as glReadPixels returns them
 * (with GL_PACK_ALIGNMENT 1). Written top-down as P6. Returns 0 or -1. */
static int app_write_ppm(const char *path, int w, int h, const unsigned char *rgb)
{
    FILE *f = fopen(path, "wb");
    int y;
    if (f == NULL)
        return -1;
    fprintf(f, "P6\n%d %d\n255\n", w, h);
    for (y = h - 1; y >= 0; y--) {
        if (fwrite(rgb + (size_t)y * (size_t)w * 3u, 1, (size_t)w * 3u, f) != (size_t)w * 3u) {
            fclose(f);
            return -1;
        }
    }
    return fclose(f) == 0 ? 0 : -1;
}

/* Prints "prog: what -> n1 n2 ..." once, to stdout (flushed, so the line is
 * there even if the app dies later). */
static void app_print_names(const char *prog, const char *what, const unsigned int *names, int n)
{
    int i;
    printf("%s: %s ->", prog, what);
    for (i = 0; i < n; i++)
        printf(" %u", names[i]);
    printf("\n");
    fflush(stdout);
}

#endif
