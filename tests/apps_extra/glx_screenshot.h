/*
 * glx_screenshot.h - --screenshot for the small GLX test programs of apps_extra/: the last
 * frame's back buffer, read before the swap, as a binary PPM. Include after GL/gl.h and
 * ../apps/app_common.h.
 */
#ifndef GLCAST_TEST_GLX_SCREENSHOT_H
#define GLCAST_TEST_GLX_SCREENSHOT_H

static int app_screenshot(const char *prog, const struct app_args *a)
{
    unsigned char *rgb = malloc((size_t)a->width * (size_t)a->height * 3u);
    if (!rgb)
        return -1;
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glReadBuffer(GL_BACK);
    glReadPixels(0, 0, a->width, a->height, GL_RGB, GL_UNSIGNED_BYTE, rgb);
    const int r = app_write_ppm(a->screenshot, a->width, a->height, rgb);
    free(rgb);
    if (r != 0)
        fprintf(stderr, "%s: cannot write %s\n", prog, a->screenshot);
    return r;
}

#endif
