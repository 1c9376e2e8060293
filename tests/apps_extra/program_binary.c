/*
 * program_binary.c - a program with a shader cache, as Qt's and many games' are: it compiles its
 * GLSL program once, saves the driver's binary (glGetProgramBinary) to a file, and on later runs
 * loads that binary (glProgramBinary) instead of compiling; if the load fails (GL_LINK_STATUS
 * false) it compiles from source again. For docs/compatibility: a slave whose driver differs
 * from the program's cannot load the binary (tests/e2e/program_binary_test.py).
 *
 *   program_binary --cache PATH [--ask|--load] [--frames N] [--size WxH] [--screenshot PATH.ppm]
 *     --ask   use the cache only when the driver reports a binary format (Qt does)
 *     --load  load the cache whatever the driver reports (a program that kept the format too)
 * Prints "program_binary: formats N, compiled|loaded|load failed, compiled".
 * GLX, an OpenGL 3.3 compatibility context (GLSL 330), a turning triangle.
 */
#define GL_GLEXT_PROTOTYPES 1
#include <GL/gl.h>
#include <GL/glext.h>
#include <GL/glx.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../apps/app_common.h"
#include "glx_screenshot.h"
#include "glx_window.h"

static const char *vertex_source =
    "#version 330 core\n"
    "layout(location = 0) in vec2 position;\n"
    "uniform float angle;\n"
    "out vec3 colour;\n"
    "void main() {\n"
    "    float c = cos(angle), s = sin(angle);\n"
    "    gl_Position = vec4(c * position.x - s * position.y, s * position.x + c * position.y, 0.0, 1.0);\n"
    "    colour = vec3(position * 0.5 + 0.5, 0.7);\n"
    "}\n";
static const char *fragment_source =
    "#version 330 core\n"
    "in vec3 colour;\n"
    "out vec4 fragment;\n"
    "void main() { fragment = vec4(colour, 1.0); }\n";

static GLuint compile(GLenum type, const char *source)
{
    GLuint s = glCreateShader(type);
    glShaderSource(s, 1, &source, NULL);
    glCompileShader(s);
    GLint ok = 0;
    glGetShaderiv(s, GL_COMPILE_STATUS, &ok);
    if (!ok) {
        fprintf(stderr, "program_binary: a shader does not compile\n");
        exit(1);
    }
    return s;
}

static void link_from_source(GLuint program)
{
    GLuint vs = compile(GL_VERTEX_SHADER, vertex_source), fs = compile(GL_FRAGMENT_SHADER, fragment_source);
    glAttachShader(program, vs);
    glAttachShader(program, fs);
    glProgramParameteri(program, GL_PROGRAM_BINARY_RETRIEVABLE_HINT, GL_TRUE);
    glLinkProgram(program);
    glDetachShader(program, vs);
    glDetachShader(program, fs);
    glDeleteShader(vs);
    glDeleteShader(fs);
    GLint ok = 0;
    glGetProgramiv(program, GL_LINK_STATUS, &ok);
    if (!ok) {
        fprintf(stderr, "program_binary: the program does not link\n");
        exit(1);
    }
}

/* The cache file: the binary's format, then its bytes. */
static int load(GLuint program, const char *path)
{
    FILE *f = fopen(path, "rb");
    if (!f) return 0;
    GLenum format = 0;
    static unsigned char bytes[1 << 20];
    size_t n = 0;
    if (fread(&format, sizeof format, 1, f) == 1) n = fread(bytes, 1, sizeof bytes, f);
    fclose(f);
    if (n == 0) return 0;
    glProgramBinary(program, format, bytes, (GLsizei)n);
    GLint ok = 0;
    glGetProgramiv(program, GL_LINK_STATUS, &ok);
    return ok ? 1 : -1;
}

static void save(GLuint program, const char *path)
{
    GLint length = 0;
    glGetProgramiv(program, GL_PROGRAM_BINARY_LENGTH, &length);
    if (length <= 0) return;
    void *bytes = malloc((size_t)length);
    GLenum format = 0;
    GLsizei written = 0;
    glGetProgramBinary(program, length, &written, &format, bytes);
    FILE *f = fopen(path, "wb");
    if (f && written > 0) {
        fwrite(&format, sizeof format, 1, f);
        fwrite(bytes, 1, (size_t)written, f);
    }
    if (f) fclose(f);
    free(bytes);
}

int main(int argc, char **argv)
{
    const char *cache = NULL;
    int ask = 0, force = 0, rest = 1;
    char *kept[64];
    kept[0] = argv[0];
    for (int i = 1; i < argc; i++) {
        if (strcmp(argv[i], "--cache") == 0 && i + 1 < argc) cache = argv[++i];
        else if (strcmp(argv[i], "--ask") == 0) ask = 1;
        else if (strcmp(argv[i], "--load") == 0) force = 1;
        else if (rest < 63) kept[rest++] = argv[i];
    }
    if (!cache || ask == force) {
        fprintf(stderr, "usage: program_binary --cache PATH --ask|--load [--frames N] [--size WxH] "
                        "[--screenshot PATH.ppm]\n");
        return 2;
    }
    struct app_args a;
    app_parse_args("program_binary", rest, kept, &a);
    int attribs[] = {GLX_RGBA, GLX_DOUBLEBUFFER, GLX_RED_SIZE, 8, GLX_GREEN_SIZE, 8, GLX_BLUE_SIZE, 8, None};
    struct glx_window w = glx_window_open("program_binary", &a, attribs, "double-buffered RGB");

    GLint formats = 0;
    glGetIntegerv(GL_NUM_PROGRAM_BINARY_FORMATS, &formats);
    GLint *format_list = calloc((size_t)(formats > 0 ? formats : 0) + 1, sizeof(GLint));
    if (formats > 0) glGetIntegerv(GL_PROGRAM_BINARY_FORMATS, format_list);
    free(format_list);
    GLuint program = glCreateProgram();
    const char *how = "compiled";
    const int loaded = (force || (ask && formats > 0)) ? load(program, cache) : 0;
    if (loaded > 0) {
        how = "loaded";
    } else {
        if (loaded < 0) how = "load failed, compiled";
        link_from_source(program);
        if (formats > 0) save(program, cache);
    }
    printf("program_binary: formats %d, %s\n", formats, how);
    fflush(stdout);

    const float triangle[] = {-0.7f, -0.6f, 0.7f, -0.6f, 0.0f, 0.8f};
    GLuint vao, vbo;
    glGenVertexArrays(1, &vao);
    glBindVertexArray(vao);
    glGenBuffers(1, &vbo);
    glBindBuffer(GL_ARRAY_BUFFER, vbo);
    glBufferData(GL_ARRAY_BUFFER, sizeof triangle, triangle, GL_STATIC_DRAW);
    glVertexAttribPointer(0, 2, GL_FLOAT, GL_FALSE, 0, NULL);
    glEnableVertexAttribArray(0);
    glUseProgram(program);
    const GLint angle = glGetUniformLocation(program, "angle");
    glViewport(0, 0, a.width, a.height);
    for (int f = 0; f < a.frames; f++) {
        glClearColor(0.1f, 0.1f, 0.15f, 1);
        glClear(GL_COLOR_BUFFER_BIT);
        glUniform1f(angle, 0.05f * f);
        glDrawArrays(GL_TRIANGLES, 0, 3);
        if (a.screenshot && f == a.frames - 1 && app_screenshot("program_binary", &a) != 0) return 1;
        glXSwapBuffers(w.dpy, w.win);
    }
    glx_window_close(&w);
    return 0;
}
