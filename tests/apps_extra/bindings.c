/*
 * bindings.c - a program that asks GL which objects are bound, as toolkits and engines do to save
 * and restore state: every frame draws a floor and a box in perspective (fixed function, GLX),
 * then makes one object of each kind (a shader program, a texture, a buffer, a renderbuffer, a
 * framebuffer, a vertex array, a sampler), binds them, asks glGetIntegerv for each binding, and
 * deletes them again; then asks glIs* about names nobody made and names just deleted (none is
 * an object); then makes two textures under names it chose itself (bound first, never generated:
 * compatibility GL makes them so), copies one into the other with glCopyImageSubData (whose
 * names' kind its target parameters say) and reads the copy back.
 *
 * For tests/e2e/verify_names_test.py: a slave whose passes make objects of their own in the
 * program's context (after the first frame) gives the program's later objects other names than
 * the master's driver did, so its answers to these queries are its own names. `glcast replay
 * --verify` must compare them with the master's answers mapped to the slave's names.
 *
 *   bindings [--frames N] [--size WxH]
 */
#define GL_GLEXT_PROTOTYPES 1
#include <GL/gl.h>
#include <GL/glext.h>
#include <GL/glx.h>
#include <stdio.h>
#include <string.h>

#include "../apps/app_common.h"
#include "glx_window.h"

static const char *VERTEX = "#version 120\nvoid main() { gl_Position = ftransform(); }\n";
static const char *FRAGMENT = "#version 120\nvoid main() { gl_FragColor = vec4(1.0); }\n";

static void draw_scene(int f)
{
    glClearColor(0.2f, 0.3f, 0.45f, 1);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    glEnable(GL_DEPTH_TEST);
    glMatrixMode(GL_PROJECTION);
    glLoadIdentity();
    glFrustum(-0.6, 0.6, -0.45, 0.45, 1, 50);
    glMatrixMode(GL_MODELVIEW);
    glLoadIdentity();
    glTranslatef(0, -1.5f, -6);
    glRotatef(10.0f * (float)f, 0, 1, 0);
    glColor3f(0.35f, 0.5f, 0.3f);  /* the floor */
    glBegin(GL_QUADS);
    glVertex3f(-4, 0, -4); glVertex3f(-4, 0, 4); glVertex3f(4, 0, 4); glVertex3f(4, 0, -4);
    glEnd();
    glColor3f(0.7f, 0.4f, 0.3f);  /* the box's top and two sides */
    glBegin(GL_QUADS);
    glVertex3f(-1, 1, -1); glVertex3f(-1, 1, 1); glVertex3f(1, 1, 1); glVertex3f(1, 1, -1);
    glVertex3f(-1, 0, 1); glVertex3f(1, 0, 1); glVertex3f(1, 1, 1); glVertex3f(-1, 1, 1);
    glVertex3f(1, 0, -1); glVertex3f(1, 1, -1); glVertex3f(1, 1, 1); glVertex3f(1, 0, 1);
    glEnd();
}

static GLuint shader(GLenum type, const char *source)
{
    GLuint s = glCreateShader(type);
    glShaderSource(s, 1, &source, NULL);
    glCompileShader(s);
    return s;
}

/* One object of each kind, bound and asked about, then deleted: 0 if every answer named it. */
static int ask_bindings(void)
{
    GLuint program = glCreateProgram(), vs = shader(GL_VERTEX_SHADER, VERTEX), fs = shader(GL_FRAGMENT_SHADER, FRAGMENT);
    glAttachShader(program, vs);
    glAttachShader(program, fs);
    glLinkProgram(program);
    GLuint texture, buffer, renderbuffer, framebuffer, vao, sampler;
    glGenTextures(1, &texture);
    glGenBuffers(1, &buffer);
    glGenRenderbuffers(1, &renderbuffer);
    glGenFramebuffers(1, &framebuffer);
    glGenVertexArrays(1, &vao);
    glGenSamplers(1, &sampler);
    glUseProgram(program);
    glBindTexture(GL_TEXTURE_2D, texture);
    glBindBuffer(GL_ARRAY_BUFFER, buffer);
    glBindRenderbuffer(GL_RENDERBUFFER, renderbuffer);
    glBindFramebuffer(GL_READ_FRAMEBUFFER, framebuffer);
    glBindVertexArray(vao);
    glBindSampler(0, sampler);
    const struct { GLenum pname; GLuint expected; } asked[] = {
        {GL_CURRENT_PROGRAM, program}, {GL_TEXTURE_BINDING_2D, texture}, {GL_ARRAY_BUFFER_BINDING, buffer},
        {GL_RENDERBUFFER_BINDING, renderbuffer}, {GL_READ_FRAMEBUFFER_BINDING, framebuffer},
        {GL_DRAW_FRAMEBUFFER_BINDING, 0}, {GL_VERTEX_ARRAY_BINDING, vao}, {GL_SAMPLER_BINDING, sampler}};
    int wrong = 0;
    for (size_t i = 0; i < sizeof asked / sizeof asked[0]; i++) {
        GLint name = -1;
        glGetIntegerv(asked[i].pname, &name);
        wrong += (GLuint)name != asked[i].expected;
    }
    glUseProgram(0);
    glBindTexture(GL_TEXTURE_2D, 0);
    glBindBuffer(GL_ARRAY_BUFFER, 0);
    glBindRenderbuffer(GL_RENDERBUFFER, 0);
    glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
    glBindVertexArray(0);
    glBindSampler(0, 0);
    glDeleteSamplers(1, &sampler);
    glDeleteVertexArrays(1, &vao);
    glDeleteFramebuffers(1, &framebuffer);
    glDeleteRenderbuffers(1, &renderbuffer);
    glDeleteBuffers(1, &buffer);
    glDeleteTextures(1, &texture);
    glDeleteShader(vs);
    glDeleteShader(fs);
    glDeleteProgram(program);
    /* Names nobody made, and names just deleted, are no objects (Mesa's piglit asks so). */
    const GLuint never = 900;
    wrong += glIsTexture(never) || glIsBuffer(never + 1) || glIsFramebuffer(never + 2) || glIsRenderbuffer(never + 3);
    wrong += glIsTexture(texture) || glIsBuffer(buffer);
    return wrong;
}

/* Textures under names the program chose, copied: 0 if the copy holds. */
static int copy_own_textures(int f)
{
    const GLuint own[2] = {600, 601};
    unsigned char texels[4 * 4 * 4], copied[4 * 4 * 4];
    for (int i = 0; i < (int)sizeof texels; i++) texels[i] = (unsigned char)(i * 7 + f * 31);
    glBindTexture(GL_TEXTURE_2D, own[0]);
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, 4, 4, 0, GL_RGBA, GL_UNSIGNED_BYTE, texels);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);  /* complete: copyable */
    glBindTexture(GL_TEXTURE_2D, own[1]);
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, 4, 4, 0, GL_RGBA, GL_UNSIGNED_BYTE, NULL);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glCopyImageSubData(own[0], GL_TEXTURE_2D, 0, 0, 0, 0, own[1], GL_TEXTURE_2D, 0, 0, 0, 0, 4, 4, 1);
    glGetTexImage(GL_TEXTURE_2D, 0, GL_RGBA, GL_UNSIGNED_BYTE, copied);
    const int wrong = (glGetError() != GL_NO_ERROR) + (memcmp(texels, copied, sizeof texels) != 0);
    glBindTexture(GL_TEXTURE_2D, 0);
    glDeleteTextures(2, own);
    return wrong;
}

int main(int argc, char **argv)
{
    struct app_args a;
    app_parse_args("bindings", argc, argv, &a);
    int attribs[] = {GLX_RGBA, GLX_DOUBLEBUFFER, GLX_RED_SIZE, 8, GLX_GREEN_SIZE, 8, GLX_BLUE_SIZE, 8,
                     GLX_DEPTH_SIZE, 24, None};
    struct glx_window w = glx_window_open("bindings", &a, attribs, "double-buffered RGB with depth");
    glViewport(0, 0, a.width, a.height);
    for (int f = 0; f < a.frames; f++) {
        draw_scene(f);
        const int wrong = ask_bindings() + copy_own_textures(f);
        if (wrong) {
            fprintf(stderr, "bindings: %d answers of frame %d name another object\n", wrong, f);
            return 1;
        }
        glXSwapBuffers(w.dpy, w.win);
    }
    glx_window_close(&w);
    return 0;
}
