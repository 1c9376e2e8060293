/*
 * gles_errors.c - an OpenGL ES program that checks glGetError after every call whose data a
 * capture must size (glReadPixels, glTexImage2D, glTexSubImage2D), as Mesa's piglit does. For
 * glcast's tests: the shim's own queries (pixel-store state, texture levels) must ask only what
 * the context's API has; a value OpenGL ES lacks left GL_INVALID_ENUM for the program's next
 * glGetError, and piglit's ES tests failed under the shim. It also asks what only an ES context
 * answers so (its version strings, its extensions, a shader that ES refuses for want of a
 * precision): a replay in a desktop context answered otherwise under --verify.
 *
 *   gles_errors 2|3 [--frames N]    an ES 2.0 or 3.0 context on a headless EGL pbuffer
 * Exits 0 when every glGetError said GL_NO_ERROR, 1 (naming the call) otherwise.
 */
#include <EGL/egl.h>
#include <EGL/eglext.h>
#include <GLES3/gl3.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../apps/app_common.h"

static int check(const char *call, int frame)
{
    const GLenum e = glGetError();
    if (e == GL_NO_ERROR) return 0;
    fprintf(stderr, "gles_errors: frame %d: %s left GL error 0x%x\n", frame, call, e);
    return 1;
}

int main(int argc, char **argv)
{
    int failed_at_start = 0;
    const int version = argc > 1 ? atoi(argv[1]) : 0;
    if (version != 2 && version != 3) {
        fprintf(stderr, "gles_errors: the first argument is the ES version, 2 or 3\n");
        return 2;
    }
    argv[1] = argv[0];
    struct app_args a;
    app_parse_args("gles_errors", argc - 1, argv + 1, &a);
    EGLDisplay dpy = eglGetDisplay(EGL_DEFAULT_DISPLAY);
    if (!eglInitialize(dpy, NULL, NULL)) {
        fprintf(stderr, "gles_errors: no EGL display (eglInitialize: EGL error 0x%x)\n", eglGetError());
        return 1;
    }
    const EGLint config_attribs[] = {EGL_SURFACE_TYPE, EGL_PBUFFER_BIT, EGL_RENDERABLE_TYPE,
                                     version == 3 ? EGL_OPENGL_ES3_BIT : EGL_OPENGL_ES2_BIT, EGL_RED_SIZE, 8,
                                     EGL_GREEN_SIZE, 8, EGL_BLUE_SIZE, 8, EGL_NONE};
    EGLConfig config;
    EGLint n = 0;
    if (!eglChooseConfig(dpy, config_attribs, &config, 1, &n) || n < 1) {
        fprintf(stderr, "gles_errors: no ES %d pbuffer config\n", version);
        return 1;
    }
    const EGLint surface_attribs[] = {EGL_WIDTH, a.width, EGL_HEIGHT, a.height, EGL_NONE};
    EGLSurface surface = eglCreatePbufferSurface(dpy, config, surface_attribs);
    eglBindAPI(EGL_OPENGL_ES_API);
    const EGLint context_attribs[] = {EGL_CONTEXT_CLIENT_VERSION, version, EGL_NONE};
    EGLContext ctx = eglCreateContext(dpy, config, EGL_NO_CONTEXT, context_attribs);
    if (!ctx || !eglMakeCurrent(dpy, surface, surface, ctx)) {
        fprintf(stderr, "gles_errors: no ES %d context\n", version);
        return 1;
    }
    printf("gles_errors: %s; %s\n", (const char *)glGetString(GL_VERSION),
           (const char *)glGetString(GL_SHADING_LANGUAGE_VERSION));
    const char *extensions = (const char *)glGetString(GL_EXTENSIONS);
    printf("gles_errors: %zu bytes of extensions\n", extensions ? strlen(extensions) : 0);
    if (version == 3) {
        GLint count = 0;
        glGetIntegerv(GL_NUM_EXTENSIONS, &count);
        for (GLint i = 0; i < count; i++) glGetStringi(GL_EXTENSIONS, (GLuint)i);
    }
    /* ES asks a fragment shader for a default float precision; desktop GL does not. */
    static const char *const imprecise = "void main() { float half_ = 0.5; gl_FragColor = vec4(half_); }\n";
    GLuint shader = glCreateShader(GL_FRAGMENT_SHADER);
    glShaderSource(shader, 1, &imprecise, NULL);
    glCompileShader(shader);
    GLint compiled = -1;
    glGetShaderiv(shader, GL_COMPILE_STATUS, &compiled);
    printf("gles_errors: a shader without a float precision %s\n", compiled ? "compiled" : "was refused");
    glDeleteShader(shader);
    failed_at_start = check("the queries", -1);
    unsigned char *pixels = malloc((size_t)a.width * (size_t)a.height * 4);
    GLuint texture;
    glGenTextures(1, &texture);
    glBindTexture(GL_TEXTURE_2D, texture);
    int failed = failed_at_start;
    for (int f = 0; f < a.frames && !failed; f++) {
        glClearColor(0.2f + 0.1f * (float)(f % 5), 0.4f, 0.6f, 1);
        glClear(GL_COLOR_BUFFER_BIT);
        failed |= check("glClear", f);
        glReadPixels(0, 0, a.width, a.height, GL_RGBA, GL_UNSIGNED_BYTE, pixels);
        failed |= check("glReadPixels", f);
        glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA, 16, 16, 0, GL_RGBA, GL_UNSIGNED_BYTE, pixels);
        failed |= check("glTexImage2D", f);
        glTexSubImage2D(GL_TEXTURE_2D, 0, 4, 4, 8, 8, GL_RGBA, GL_UNSIGNED_BYTE, pixels);
        failed |= check("glTexSubImage2D", f);
        eglSwapBuffers(dpy, surface);
    }
    free(pixels);
    eglMakeCurrent(dpy, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    eglDestroyContext(dpy, ctx);
    eglDestroySurface(dpy, surface);
    eglTerminate(dpy);
    if (!failed) printf("gles_errors: ES %d: every glGetError said GL_NO_ERROR\n", version);
    return failed;
}
