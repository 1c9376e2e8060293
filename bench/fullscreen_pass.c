/* The least a full-screen pass can cost on this driver (docs/performance.md, "A projector's warp
 * and blend"): PASSES draws of one textured quad over a WIDTHxHEIGHT pbuffer with a depth buffer
 * (a slave's window), one texture of that size read with nearest texels by the simplest fragment
 * shader, each finished (glFinish) as a frame's last pass is before it is shown. Prints the
 * process's CPU time (user + system) per pass, after a few passes left out (the shader's compile).
 *
 *   fullscreen_pass [PASSES] [WIDTHxHEIGHT]
 */
#define GL_GLEXT_PROTOTYPES 1
#include <EGL/egl.h>
#include <EGL/eglext.h>
#include <GL/gl.h>
#include <GL/glext.h>
#include <stdio.h>
#include <stdlib.h>
#include <sys/resource.h>

static double cpu_seconds(void)
{
    struct rusage u;
    getrusage(RUSAGE_SELF, &u);
    return (double)u.ru_utime.tv_sec + u.ru_utime.tv_usec * 1e-6 + (double)u.ru_stime.tv_sec + u.ru_stime.tv_usec * 1e-6;
}

static GLuint shader(GLenum kind, const char *text)
{
    GLuint s = glCreateShader(kind);
    GLint ok = 0;
    glShaderSource(s, 1, &text, NULL);
    glCompileShader(s);
    glGetShaderiv(s, GL_COMPILE_STATUS, &ok);
    if (!ok) {
        fprintf(stderr, "fullscreen_pass: a shader does not compile\n");
        exit(1);
    }
    return s;
}

int main(int argc, char **argv)
{
    const int passes = argc > 1 ? atoi(argv[1]) : 300;
    int width = 1920, height = 1080;
    if (argc > 2 && sscanf(argv[2], "%dx%d", &width, &height) != 2) {
        fprintf(stderr, "fullscreen_pass: WIDTHxHEIGHT, not %s\n", argv[2]);
        return 2;
    }
    if (passes < 1 || width < 1 || height < 1 || width > 16384 || height > 16384) {
        fprintf(stderr, "fullscreen_pass: PASSES >= 1 and a size up to 16384x16384\n");
        return 2;
    }
    PFNEGLGETPLATFORMDISPLAYEXTPROC get_display =
        (PFNEGLGETPLATFORMDISPLAYEXTPROC)eglGetProcAddress("eglGetPlatformDisplayEXT");
    EGLDisplay dpy = get_display ? get_display(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, NULL) : EGL_NO_DISPLAY;
    if (dpy == EGL_NO_DISPLAY || !eglInitialize(dpy, NULL, NULL) || !eglBindAPI(EGL_OPENGL_API)) {
        fprintf(stderr, "fullscreen_pass: no surfaceless EGL display\n");
        return 1;
    }
    const EGLint config_attribs[] = {EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_SURFACE_TYPE, EGL_PBUFFER_BIT, EGL_RED_SIZE, 8,
                                     EGL_GREEN_SIZE, 8, EGL_BLUE_SIZE, 8, EGL_DEPTH_SIZE, 24, EGL_NONE};
    const EGLint surface_attribs[] = {EGL_WIDTH, width, EGL_HEIGHT, height, EGL_NONE};
    EGLConfig config;
    EGLint n = 0;
    if (!eglChooseConfig(dpy, config_attribs, &config, 1, &n) || n < 1) {
        fprintf(stderr, "fullscreen_pass: no config\n");
        return 1;
    }
    EGLSurface surface = eglCreatePbufferSurface(dpy, config, surface_attribs);
    EGLContext context = eglCreateContext(dpy, config, EGL_NO_CONTEXT, NULL);
    if (surface == EGL_NO_SURFACE || context == EGL_NO_CONTEXT || !eglMakeCurrent(dpy, surface, surface, context)) {
        fprintf(stderr, "fullscreen_pass: no context\n");
        return 1;
    }
    GLuint program = glCreateProgram();
    glAttachShader(program, shader(GL_VERTEX_SHADER, "#version 130\nin vec2 p; out vec2 uv;\n"
                                                      "void main() { uv = p * 0.5 + 0.5; gl_Position = vec4(p, 0.0, 1.0); }\n"));
    glAttachShader(program, shader(GL_FRAGMENT_SHADER, "#version 130\nin vec2 uv; uniform sampler2D picture; out vec4 colour;\n"
                                                        "void main() { colour = texture(picture, uv); }\n"));
    glBindAttribLocation(program, 0, "p");
    glLinkProgram(program);
    glUseProgram(program);
    unsigned char *pixels = malloc((size_t)width * height * 4);
    if (!pixels)
        return 1;
    for (size_t i = 0; i < (size_t)width * height * 4; i++)
        pixels[i] = (unsigned char)(i * 7);
    GLuint texture, buffer, vertex_array;
    glGenTextures(1, &texture);
    glBindTexture(GL_TEXTURE_2D, texture);
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, width, height, 0, GL_RGBA, GL_UNSIGNED_BYTE, pixels);
    free(pixels);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    const float quad[] = {-1, -1, 1, -1, -1, 1, 1, 1};
    glGenVertexArrays(1, &vertex_array);
    glBindVertexArray(vertex_array);
    glGenBuffers(1, &buffer);
    glBindBuffer(GL_ARRAY_BUFFER, buffer);
    glBufferData(GL_ARRAY_BUFFER, sizeof quad, quad, GL_STATIC_DRAW);
    glVertexAttribPointer(0, 2, GL_FLOAT, GL_FALSE, 0, NULL);
    glEnableVertexAttribArray(0);
    glDisable(GL_DEPTH_TEST);
    glViewport(0, 0, width, height);
    for (int i = 0; i < 5; i++)
        glDrawArrays(GL_TRIANGLE_STRIP, 0, 4);
    glFinish();
    const double start = cpu_seconds();
    for (int i = 0; i < passes; i++) {
        glDrawArrays(GL_TRIANGLE_STRIP, 0, 4);
        glFinish();
    }
    const double per_pass = (cpu_seconds() - start) / passes;
    if (glGetError() != GL_NO_ERROR) {
        fprintf(stderr, "fullscreen_pass: GL error\n");
        return 1;
    }
    printf("%.6f\n", per_pass);
    eglMakeCurrent(dpy, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    eglTerminate(dpy);
    return 0;
}
