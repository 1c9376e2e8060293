/*
 * api_errors.c - a program that checks that GL refuses what it must, as Mesa's piglit does: every
 * frame it makes calls with arguments GL raises an error for, and asks queries whose output GL
 * leaves untouched when it refuses them or when the answer is shorter than the buffer. Its
 * output arrays start with a sentinel; it checks each error and each untouched sentinel itself
 * and exits 1 naming the first that is not so.
 *
 * For glcast's replay tests: the master's reply holds what the program's memory held where GL
 * wrote nothing, so the slave's output must start as the master's did for --verify to compare
 * what the drivers wrote (glGetFloati_v past the last viewport, glGetTransformFeedbackiv of a
 * pname it lacks, glGetInternalformativ with a bufSize shorter than its array); a negative count
 * with NULL is replayed for the error it raises (glViewportArrayv(0, -1, NULL): the slave
 * stopped, "cannot compute how much the call reads"), and so is a generator's
 * (glCreateTransformFeedbacks(-1): "the call generates -1 names, the reply has 0").
 *
 *   api_errors [--frames N] [--size WxH]
 */
#define GL_GLEXT_PROTOTYPES 1
#include <GL/gl.h>
#include <GL/glext.h>
#include <GL/glx.h>
#include <stdio.h>

#include "../apps/app_common.h"
#include "glx_window.h"

#define SENTINEL 0x5a5a5a5a

static int expect(GLenum wanted, const char *call, int frame)
{
    const GLenum e = glGetError();
    if (e == wanted) return 0;
    fprintf(stderr, "api_errors: frame %d: %s left GL error 0x%x, not 0x%x\n", frame, call, e, wanted);
    return 1;
}

static int untouched(const GLint *v, int from, int to, const char *call, int frame)
{
    for (int i = from; i < to; i++) {
        if (v[i] == SENTINEL) continue;
        fprintf(stderr, "api_errors: frame %d: %s wrote element %d of its output\n", frame, call, i);
        return 1;
    }
    return 0;
}

static int refusals(int frame)
{
    int wrong = 0;
    GLint max_viewports = 0;
    glGetIntegerv(GL_MAX_VIEWPORTS, &max_viewports);
    union { GLfloat f[4]; GLint i[4]; } viewport = {.i = {SENTINEL, SENTINEL, SENTINEL, SENTINEL}};
    glGetFloati_v(GL_VIEWPORT, (GLuint)max_viewports, viewport.f);
    wrong += expect(GL_INVALID_VALUE, "glGetFloati_v(GL_VIEWPORT, GL_MAX_VIEWPORTS)", frame);
    wrong += untouched(viewport.i, 0, 4, "glGetFloati_v(GL_VIEWPORT, GL_MAX_VIEWPORTS)", frame);
    glViewportArrayv(0, -1, NULL);
    wrong += expect(GL_INVALID_VALUE, "glViewportArrayv(0, -1, NULL)", frame);

    GLint feedback[1] = {SENTINEL};
    glGetTransformFeedbackiv(0, GL_TRANSFORM_FEEDBACK_BINDING, feedback);
    wrong += expect(GL_INVALID_ENUM, "glGetTransformFeedbackiv(GL_TRANSFORM_FEEDBACK_BINDING)", frame);
    wrong += untouched(feedback, 0, 1, "glGetTransformFeedbackiv(GL_TRANSFORM_FEEDBACK_BINDING)", frame);

    /* One value asked into an array of four: GL writes one (the answer is one value long). */
    GLint samples[4] = {SENTINEL, SENTINEL, SENTINEL, SENTINEL};
    glGetInternalformativ(GL_RENDERBUFFER, GL_RGBA8, GL_NUM_SAMPLE_COUNTS, 1, samples);
    wrong += expect(GL_NO_ERROR, "glGetInternalformativ(GL_NUM_SAMPLE_COUNTS)", frame);
    wrong += untouched(samples, 1, 4, "glGetInternalformativ(GL_NUM_SAMPLE_COUNTS, bufSize 1)", frame);
    /* A target it has no formats for: an error, nothing written. */
    GLint refused[2] = {SENTINEL, SENTINEL};
    glGetInternalformativ(GL_TEXTURE_BINDING_2D, GL_RGBA8, GL_NUM_SAMPLE_COUNTS, 2, refused);
    wrong += expect(GL_INVALID_ENUM, "glGetInternalformativ(GL_TEXTURE_BINDING_2D)", frame);
    wrong += untouched(refused, 0, 2, "glGetInternalformativ(GL_TEXTURE_BINDING_2D)", frame);

    /* A generator asked for a negative count: an error, no name made. */
    GLint generated[1] = {SENTINEL};
    glCreateTransformFeedbacks(-1, (GLuint *)generated);
    wrong += expect(GL_INVALID_VALUE, "glCreateTransformFeedbacks(-1)", frame);
    wrong += untouched(generated, 0, 1, "glCreateTransformFeedbacks(-1)", frame);
    return wrong;
}

int main(int argc, char **argv)
{
    struct app_args a;
    app_parse_args("api_errors", argc, argv, &a);
    int attribs[] = {GLX_RGBA, GLX_DOUBLEBUFFER, GLX_RED_SIZE, 8, GLX_GREEN_SIZE, 8, GLX_BLUE_SIZE, 8, None};
    struct glx_window w = glx_window_open("api_errors", &a, attribs, "double-buffered RGB");
    for (int f = 0; f < a.frames; f++) {
        glClearColor(0.1f * (float)(f % 8), 0.3f, 0.5f, 1);
        glClear(GL_COLOR_BUFFER_BIT);
        if (refusals(f)) return 1;
        glXSwapBuffers(w.dpy, w.win);
    }
    glx_window_close(&w);
    printf("api_errors: every refusal raised its error and left the output as it was\n");
    return 0;
}
