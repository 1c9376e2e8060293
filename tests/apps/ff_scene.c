/*
 * ff_scene.c - glcast test app: OpenGL 1.x fixed function through Xlib + GLX.
 *
 * A small lit 3D scene: a large textured ground plane (immediate mode), boxes
 * standing on it (display list, client vertex arrays), a sphere floating above
 * the ground (glDrawRangeElements), and a waving flag whose client arrays
 * change every frame (glDrawArrays with GL_COLOR_ARRAY). The camera orbits
 * slowly (or, with --camera dolly, moves straight forward), driven by the frame index only,
 * so every frame is reproducible.
 *
 * Exercised on purpose (for the capture side):
 *  - glGenTextures / glTexImage2D (all mip levels) / glTexParameteri, GL_MODULATE
 *  - glGenLists / glNewList(GL_COMPILE) / glCallList
 *  - GL_LIGHTING, GL_LIGHT0 positional, glLightfv, glMaterialfv, glColorMaterial
 *  - client arrays: glDrawElements with an out-of-order GLushort index array
 *    whose range (24..47) is not [0, count/2): the used range must come from
 *    the min/max index; glDrawArrays with first != 0 and == 0;
 *    glDrawRangeElements; glLockArraysEXT/glUnlockArraysEXT if present
 *  - arrays whose content changes every frame (flag positions, normals) next
 *    to arrays that never change (flag colours, boxes, sphere)
 *
 * With --hud (a first argument) every frame ends with a game's HUD over the scene: the depth
 * test and lighting off, an orthographic projection, an opaque panel (window pixels 8..136 x
 * 8..40, colour 230,50,40), and a row of glBitmap glyphs at (12, 52) in white (docs/effects.md:
 * overlays stay untouched by the passes).
 *
 * With --hud --dim the HUD starts with a full-window black quad of alpha 0.27 blended over the
 * scene, as a game's menu dims the scene behind it (neverball's title screen).
 *
 * With --backdrop a star-field box (unlit, no depth writes) is drawn around the world first; its
 * floor shows beyond the ground's far edge (docs/effects.md: backdrops are not surfaces).
 *
 * With --reflection the crates are first drawn mirrored below the ground (glScalef(1, -1, 1)
 * before their own glPushMatrix, with depth writes, as neverball draws its level's reflection),
 * then the depth buffer is cleared; the opaque ground hides them (docs/effects.md: a mirrored
 * view is not the main view).
 *
 * With --weapon a first-person view model is drawn among the scene's draws, after the crates: a
 * level box placed in eye space (lower right, about 1.3 units in front of the eye) with
 * glDepthRange(0, 0.3), as Quake 3 draws its weapon, so that no wall can hide it
 * (docs/effects.md: a view model is not the scene).
 *
 * With --culled a quad facing away from the eye is drawn over the lower half of the view, 4 units in
 * front of it, with back faces culled (so the program never shows it), and culling is off again
 * for the frame's last draws, as neverball culls its level and then draws its menu
 * (docs/effects.md: a redraw culls what the program culled).
 *
 * With --widget the scene is drawn as a Qt program's QOpenGLWidget draws it: by a second context
 * (sharing objects with the window's, current on a 1x1 pbuffer) into a framebuffer object of the
 * widget's size (5/8 x 3/4 of the window, its colour a texture, depth and stencil one
 * renderbuffer), and only every WIDGET_REDRAW-th frame (the frame's scene is that of the last
 * multiple of it: a viewer redraws when its view changes). Every frame the window's context
 * composites: a grey background, the widget's texture at (width/4, height/8) with a
 * fixed-function textured quad over a viewport of the widget's rectangle, then the toolkit's widgets over it: a blue toolbar along the top
 * of the window and a label inside the widget's lower left corner (docs/effects.md: a scene
 * drawn by another context). --widget-samples N (implies --widget): the scene is drawn with N
 * samples into renderbuffers and its colour resolved into the texture with glBlitFramebuffer.
 * --widget-post (after --widget): the widget's context then copies its picture by a fixed-function
 * textured quad into a second texture of its size (a framebuffer object without depth), and the
 * window shows that one, as Blender's draw manager copies its viewport's picture through
 * post-processing targets before the window's context composites it.
 * --widget-swaps (implies --widget): the widget's context swaps its pbuffer once when it is made, as
 * Blender's draw manager's hidden window does; it never presents again.
 * --widget-wire (implies --widget, not --widget-samples): after the scene, the widget's context
 * draws a wire-frame box (yellow lines 3 pixels wide, beside the crates) with the scene's camera,
 * the depth test on, into a framebuffer object with a colour texture of its own (cleared
 * transparent) and the widget's depth; the window's context blends that texture over the widget's
 * picture: as Blender's overlay engine draws its cameras' wire frames over its viewport's depth
 * from a context that presents only to a hidden window of a pixel.
 * --preview (implies --widget): the window's context draws that texture small in the top left
 * corner of its sky, then its own scene over the window without clearing the colour: a picture
 * in the program's own scene, not the scene (docs/effects.md).
 *
 * Prints to stdout:
 *   ff_scene: GL_RENDERER <string>
 *   ff_scene: GL_VERSION <string>
 *   ff_scene: GL_EXT_compiled_vertex_array <yes|no>
 *   ff_scene: glGenTextures -> <ground> <crate>
 *   ff_scene: glGenLists -> <base>
 *   ff_scene: frames <N>
 */
#include <GL/gl.h>
#include <GL/glx.h>
#include <X11/Xlib.h>
#include <X11/Xutil.h>
#include <math.h>
#include <string.h>

#include "app_common.h"

static const char *PROG = "ff_scene";

/* ---------------------------------------------------------------- geometry */

/* Unit cube (-0.5..0.5), 6 quads, CCW from outside. */
static GLfloat box_pos[24][3], box_nrm[24][3], box_tc[24][2];

static void build_unit_box(void)
{
    /* per face: normal n, tangents u, v with u x v = n */
    static const float f[6][3][3] = {
        {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}},  {{-1, 0, 0}, {0, 0, 1}, {0, 1, 0}},
        {{0, 1, 0}, {0, 0, 1}, {1, 0, 0}},  {{0, -1, 0}, {1, 0, 0}, {0, 0, 1}},
        {{0, 0, 1}, {1, 0, 0}, {0, 1, 0}},  {{0, 0, -1}, {0, 1, 0}, {1, 0, 0}},
    };
    static const float cu[4] = {-1, 1, 1, -1}, cv[4] = {-1, -1, 1, 1};
    int i, k, c;
    for (i = 0; i < 6; i++) {
        for (k = 0; k < 4; k++) {
            int v = i * 4 + k;
            for (c = 0; c < 3; c++) {
                box_pos[v][c] = 0.5f * (f[i][0][c] + cu[k] * f[i][1][c] + cv[k] * f[i][2][c]);
                box_nrm[v][c] = f[i][0][c];
            }
            box_tc[v][0] = (cu[k] + 1) * 0.5f;
            box_tc[v][1] = (cv[k] + 1) * 0.5f;
        }
    }
}

/*
 * Client-array boxes: 48 vertices in one array.
 *   0..23  small box (0.6 cube, base at y=0)   -> glDrawArrays(GL_QUADS, 0, 24)
 *   24..47 tall box (0.8 x 2.0 x 0.8, base y=0) -> glDrawElements, 36 indices
 * The index array references only 24..47, faces in a shuffled order and each
 * triangle rotated, so indices are not sorted and max index (47) is far above
 * count/2 (18).
 */
#define CB_VERTS 48
#define CB_INDICES 36
static GLfloat cb_pos[CB_VERTS][3], cb_nrm[CB_VERTS][3];
static GLushort cb_idx[CB_INDICES];

static void build_client_boxes(void)
{
    static const int face_order[6] = {4, 1, 5, 0, 3, 2};
    int v, c, i, n = 0;
    for (v = 0; v < 24; v++) {
        for (c = 0; c < 3; c++) {
            float small = box_pos[v][c] * 0.6f;
            float tall = box_pos[v][c] * (c == 1 ? 2.0f : 0.8f);
            cb_pos[v][c] = small + (c == 1 ? 0.3f : 0.0f);
            cb_pos[24 + v][c] = tall + (c == 1 ? 1.0f : 0.0f);
            cb_nrm[v][c] = cb_nrm[24 + v][c] = box_nrm[v][c];
        }
    }
    for (i = 0; i < 6; i++) {
        GLushort b = (GLushort)(24 + face_order[i] * 4);
        /* (b+2, b+3, b+0) and (b+0, b+1, b+2): same winding as the quad */
        cb_idx[n++] = (GLushort)(b + 2);
        cb_idx[n++] = (GLushort)(b + 3);
        cb_idx[n++] = b;
        cb_idx[n++] = b;
        cb_idx[n++] = (GLushort)(b + 1);
        cb_idx[n++] = (GLushort)(b + 2);
    }
}

/* Sphere for the floating occluder: glDrawRangeElements. */
#define SP_STACKS 10
#define SP_SLICES 16
#define SP_VERTS ((SP_STACKS + 1) * (SP_SLICES + 1))
#define SP_INDICES (SP_STACKS * SP_SLICES * 6)
static GLfloat sp_pos[SP_VERTS][3], sp_nrm[SP_VERTS][3];
static GLushort sp_idx[SP_INDICES];

static void build_sphere(float r)
{
    int i, j, n = 0;
    for (i = 0; i <= SP_STACKS; i++) {
        float phi = APP_PI * (float)i / SP_STACKS; /* 0 at top */
        for (j = 0; j <= SP_SLICES; j++) {
            float th = 2.0f * APP_PI * (float)j / SP_SLICES;
            int v = i * (SP_SLICES + 1) + j;
            sp_nrm[v][0] = sinf(phi) * cosf(th);
            sp_nrm[v][1] = cosf(phi);
            sp_nrm[v][2] = -sinf(phi) * sinf(th);
            sp_pos[v][0] = r * sp_nrm[v][0];
            sp_pos[v][1] = r * sp_nrm[v][1];
            sp_pos[v][2] = r * sp_nrm[v][2];
        }
    }
    for (i = 0; i < SP_STACKS; i++) {
        for (j = 0; j < SP_SLICES; j++) {
            GLushort a = (GLushort)(i * (SP_SLICES + 1) + j);
            GLushort b = (GLushort)(a + SP_SLICES + 1);
            sp_idx[n++] = a;
            sp_idx[n++] = b;
            sp_idx[n++] = (GLushort)(b + 1);
            sp_idx[n++] = a;
            sp_idx[n++] = (GLushort)(b + 1);
            sp_idx[n++] = (GLushort)(a + 1);
        }
    }
}

/* Waving flag: grid expanded to a triangle list, drawn with glDrawArrays.
 * Positions and normals change every frame, colours never change. */
#define FL_W 16
#define FL_H 10
#define FL_VERTS ((FL_W - 1) * (FL_H - 1) * 6)
static GLfloat fl_pos[FL_VERTS][3], fl_nrm[FL_VERTS][3];
static GLubyte fl_col[FL_VERTS][4];

static void flag_point(float u, float v, int frame, float *p, float *nrm)
{
    const float A = 0.22f;
    float ph = 6.0f * u - 0.15f * (float)frame;
    float z = A * u * sinf(ph);
    float dz = A * (sinf(ph) + 6.0f * u * cosf(ph)); /* d z / d u */
    float nx = -1.2f * dz, nz = 2.4f, len = sqrtf(nx * nx + nz * nz);
    p[0] = 2.0f * u;
    p[1] = 1.2f * v;
    p[2] = z;
    nrm[0] = nx / len;
    nrm[1] = 0.0f;
    nrm[2] = nz / len;
}

static void build_flag(int frame, int with_colours)
{
    static const int corner[6][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 0}, {1, 1}, {0, 1}};
    int i, j, k, n = 0;
    for (j = 0; j < FL_H - 1; j++) {
        for (i = 0; i < FL_W - 1; i++) {
            for (k = 0; k < 6; k++) {
                int gi = i + corner[k][0], gj = j + corner[k][1];
                flag_point((float)gi / (FL_W - 1), (float)gj / (FL_H - 1), frame, fl_pos[n],
                           fl_nrm[n]);
                if (with_colours) {
                    /* three horizontal stripes by the quad's row */
                    int stripe = (j * 3) / (FL_H - 1);
                    static const GLubyte cols[3][4] = {
                        {200, 30, 40, 255}, {235, 235, 235, 255}, {30, 60, 190, 255}};
                    memcpy(fl_col[n], cols[stripe], 4);
                }
                n++;
            }
        }
    }
}

/* ---------------------------------------------------------------- textures */

#define CHECK_SIZE 64
static void make_checker(GLubyte *img, int size)
{
    int x, y;
    for (y = 0; y < size; y++) {
        for (x = 0; x < size; x++) {
            int on = ((x * 8 / size) + (y * 8 / size)) & 1;
            GLubyte *p = img + (y * size + x) * 3;
            p[0] = on ? 205 : 95;
            p[1] = on ? 205 : 120;
            p[2] = on ? 195 : 85;
        }
    }
}

#define CRATE_SIZE 32
static void make_crate(GLubyte *img)
{
    int x, y;
    for (y = 0; y < CRATE_SIZE; y++) {
        for (x = 0; x < CRATE_SIZE; x++) {
            int border = x < 3 || y < 3 || x >= CRATE_SIZE - 3 || y >= CRATE_SIZE - 3;
            int diag = abs(x - y) < 2 || abs(x + y - (CRATE_SIZE - 1)) < 2;
            int grain = ((y * 7) / CRATE_SIZE) & 1;
            GLubyte *p = img + (y * CRATE_SIZE + x) * 4;
            if (border || diag) {
                p[0] = 120; p[1] = 75; p[2] = 35;
            } else {
                p[0] = grain ? 210 : 190; p[1] = grain ? 160 : 145; p[2] = grain ? 95 : 85;
            }
            p[3] = 255;
        }
    }
}

/* Uploads a GL_RGB image and all of its mip levels (2x2 box filter). */
static void upload_mipmapped_rgb(GLubyte *img, int size)
{
    GLubyte *buf = malloc((size_t)size * (size_t)size * 3u);
    int level = 0, x, y, c;
    memcpy(buf, img, (size_t)size * (size_t)size * 3u);
    for (;;) {
        glTexImage2D(GL_TEXTURE_2D, level, GL_RGB8, size, size, 0, GL_RGB, GL_UNSIGNED_BYTE, buf);
        if (size == 1)
            break;
        for (y = 0; y < size / 2; y++)
            for (x = 0; x < size / 2; x++)
                for (c = 0; c < 3; c++) {
                    int s = buf[((2 * y) * size + 2 * x) * 3 + c] +
                            buf[((2 * y) * size + 2 * x + 1) * 3 + c] +
                            buf[((2 * y + 1) * size + 2 * x) * 3 + c] +
                            buf[((2 * y + 1) * size + 2 * x + 1) * 3 + c];
                    buf[(y * (size / 2) + x) * 3 + c] = (GLubyte)((s + 2) / 4);
                }
        size /= 2;
        level++;
    }
    free(buf);
}

/* ---------------------------------------------------------------- misc */

static int has_extension(const char *list, const char *name)
{
    size_t n = strlen(name);
    const char *p = list;
    if (list == NULL)
        return 0;
    while ((p = strstr(p, name)) != NULL) {
        if ((p == list || p[-1] == ' ') && (p[n] == ' ' || p[n] == '\0'))
            return 1;
        p += n;
    }
    return 0;
}

static void check_gl_errors(int frame)
{
    GLenum e;
    int bad = 0;
    while ((e = glGetError()) != GL_NO_ERROR) {
        fprintf(stderr, "%s: GL error 0x%04x in frame %d\n", PROG, e, frame);
        bad = 1;
    }
    if (bad)
        exit(1);
}

static Bool wait_for_map(Display *d, XEvent *e, XPointer arg)
{
    (void)d;
    return e->type == MapNotify && e->xmap.window == *(Window *)arg;
}

/* ---------------------------------------------------------------- drawing */

static void draw_ground(void)
{
    const float half = 18.0f, step = 3.0f, tscale = 1.0f / 8.0f;
    float x, z;
    glBegin(GL_QUADS);
    for (z = -half; z < half - 0.001f; z += step) {
        for (x = -half; x < half - 0.001f; x += step) {
            /* CCW seen from above (+y) */
            glNormal3f(0, 1, 0); glTexCoord2f(x * tscale, (z + step) * tscale); glVertex3f(x, 0, z + step);
            glNormal3f(0, 1, 0); glTexCoord2f((x + step) * tscale, (z + step) * tscale); glVertex3f(x + step, 0, z + step);
            glNormal3f(0, 1, 0); glTexCoord2f((x + step) * tscale, z * tscale); glVertex3f(x + step, 0, z);
            glNormal3f(0, 1, 0); glTexCoord2f(x * tscale, z * tscale); glVertex3f(x, 0, z);
        }
    }
    glEnd();
}

/* --backdrop: a game's star-field box around the world, drawn first, unlit, without depth
 * writes (as neverball draws its back sphere): its floor (y = -1, inside normal up) shows
 * beyond the ground's far edge. */
static int backdrop;
static int reflection;
static int weapon;
static int culled;
static int widget;
static GLfloat scene_view[16];  /* the modelview of draw_frame's camera (--widget-wire) */
#define WIDGET_REDRAW 4
/* --preview: the window's context draws the widget's texture small first, then its own scene */
static int preview, preview_first;

static void draw_backdrop(void)
{
    /* From client arrays, as a game draws its sky (the redraw replays their tuple without the
     * draw). */
    const float h = 80.0f, b = -1.0f;
    static const float n[6][3] = {{0, 1, 0}, {0, -1, 0}, {1, 0, 0}, {-1, 0, 0}, {0, 0, 1}, {0, 0, -1}};
    const float v[6][4][3] = {
        {{-h, b, -h}, {-h, b, h}, {h, b, h}, {h, b, -h}},     /* floor, seen from inside */
        {{-h, h, -h}, {h, h, -h}, {h, h, h}, {-h, h, h}},     /* ceiling */
        {{-h, b, -h}, {-h, h, -h}, {-h, h, h}, {-h, b, h}},
        {{h, b, -h}, {h, b, h}, {h, h, h}, {h, h, -h}},
        {{-h, b, -h}, {h, b, -h}, {h, h, -h}, {-h, h, -h}},
        {{-h, b, h}, {-h, h, h}, {h, h, h}, {h, b, h}},
    };
    float normals[6][4][3];
    int f, k;
    for (f = 0; f < 6; f++)
        for (k = 0; k < 4; k++)
            memcpy(normals[f][k], n[f], sizeof n[f]);
    glDisable(GL_LIGHTING);
    glDisable(GL_TEXTURE_2D);
    glDepthMask(GL_FALSE);
    glColor3f(0.08f, 0.08f, 0.24f);
    glEnableClientState(GL_VERTEX_ARRAY);
    glEnableClientState(GL_NORMAL_ARRAY);
    glVertexPointer(3, GL_FLOAT, 0, v);
    glNormalPointer(GL_FLOAT, 0, normals);
    glDrawArrays(GL_QUADS, 0, 24);
    glDisableClientState(GL_NORMAL_ARRAY);
    glDisableClientState(GL_VERTEX_ARRAY);
    glDepthMask(GL_TRUE);
    glEnable(GL_LIGHTING);
}

static void draw_frame(int frame, int dolly, int w, int h, GLuint tex_ground, GLuint tex_crate, GLuint box_list,
                       PFNGLLOCKARRAYSEXTPROC lock, PFNGLUNLOCKARRAYSEXTPROC unlock)
{
    const GLfloat light_pos[4] = {5.0f, 10.0f, 4.0f, 1.0f};
    const GLfloat no_spec[4] = {0, 0, 0, 1}, spec[4] = {0.6f, 0.6f, 0.6f, 1};
    const float aspect = (float)w / (float)h, znear = 0.5f;
    const float top = znear * tanf(22.5f * APP_PI / 180.0f);
    const float orbit = 20.0f + 0.5f * (float)frame; /* degrees, frame-driven */

    glViewport(0, 0, w, h);
    glClearColor(0.53f, 0.75f, 0.95f, 1.0f);
    glClear(preview_first ? GL_DEPTH_BUFFER_BIT : GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);

    glMatrixMode(GL_PROJECTION);
    glLoadIdentity();
    glFrustum(-top * aspect, top * aspect, -top, top, znear, 100.0f);

    glMatrixMode(GL_MODELVIEW);
    glLoadIdentity();
    if (dolly) {
        /* camera: 1.5 units above the ground, 16 units in front of the origin, moving straight
         * forward (-z) by 0.2 units a frame */
        glTranslatef(0.0f, -1.5f, -16.0f + 0.2f * (float)frame);
    } else {
        /* camera: 13 units from (0,1,0), pitched down 30 degrees, orbiting */
        glTranslatef(0.0f, 0.0f, -13.0f);
        glRotatef(30.0f, 1.0f, 0.0f, 0.0f);
        glRotatef(-orbit, 0.0f, 1.0f, 0.0f);
        glTranslatef(0.0f, -1.0f, 0.0f);
    }
    glGetFloatv(GL_MODELVIEW_MATRIX, scene_view);

    /* light position is transformed by the current modelview: world space */
    glLightfv(GL_LIGHT0, GL_POSITION, light_pos);

    glMaterialfv(GL_FRONT_AND_BACK, GL_SPECULAR, no_spec);
    if (backdrop)
        draw_backdrop();
    if (reflection) {
        glPushMatrix();
        glScalef(1.0f, -1.0f, 1.0f);
        glFrontFace(GL_CW);
        glEnable(GL_TEXTURE_2D);
        glBindTexture(GL_TEXTURE_2D, tex_crate);
        glColor3f(1.0f, 1.0f, 1.0f);
        glPushMatrix();
        glTranslatef(-2.5f, 0.75f, -1.5f);
        glRotatef(20.0f, 0.0f, 1.0f, 0.0f);
        glScalef(1.5f, 1.5f, 1.5f);
        glCallList(box_list);
        glPopMatrix();
        glDisable(GL_TEXTURE_2D);
        glFrontFace(GL_CCW);
        glPopMatrix();
        glClear(GL_DEPTH_BUFFER_BIT);
    }

    /* ground: immediate mode, checker texture modulated by lighting */
    glEnable(GL_TEXTURE_2D);
    glBindTexture(GL_TEXTURE_2D, tex_ground);
    glColor3f(1.0f, 1.0f, 1.0f);
    draw_ground();

    /* crates: display list, textured */
    glBindTexture(GL_TEXTURE_2D, tex_crate);
    glPushMatrix();
    glTranslatef(-2.5f, 0.75f, -1.5f);
    glRotatef(20.0f, 0.0f, 1.0f, 0.0f);
    glScalef(1.5f, 1.5f, 1.5f);
    glCallList(box_list);
    glPopMatrix();

    glColor3f(0.85f, 0.9f, 1.0f);
    glPushMatrix();
    glTranslatef(2.5f, 0.5f, -0.5f);
    glRotatef(-35.0f, 0.0f, 1.0f, 0.0f);
    glScalef(2.0f, 1.0f, 1.2f);
    glCallList(box_list);
    glPopMatrix();
    glDisable(GL_TEXTURE_2D);

    if (weapon) {
        glColor3f(0.25f, 0.25f, 0.3f);
        glPushMatrix();
        glLoadIdentity();
        glTranslatef(0.55f, -0.45f, -1.3f);
        glRotatef(30.0f, 1.0f, 0.0f, 0.0f); /* the camera's pitch: its top is level, facing up */
        glRotatef(-8.0f, 0.0f, 1.0f, 0.0f);
        glScalef(0.22f, 0.2f, 0.9f);
        glDepthRange(0.0, 0.3);
        glCallList(box_list);
        glDepthRange(0.0, 1.0);
        glPopMatrix();
    }

    if (culled) {
        glEnable(GL_CULL_FACE);
        glCullFace(GL_BACK);
        glPushMatrix();
        glLoadIdentity();
        glColor3f(1.0f, 0.0f, 1.0f);
        glBegin(GL_QUADS); /* clockwise as the eye sees it: a back face */
        glNormal3f(0.0f, 0.0f, -1.0f);
        glVertex3f(-3.0f, -2.0f, -4.0f);
        glVertex3f(-3.0f, 0.0f, -4.0f);
        glVertex3f(3.0f, 0.0f, -4.0f);
        glVertex3f(3.0f, -2.0f, -4.0f);
        glEnd();
        glPopMatrix();
        glDisable(GL_CULL_FACE);
    }

    /* flag pole: same display list, untextured */
    glColor3f(0.55f, 0.55f, 0.6f);
    glPushMatrix();
    glTranslatef(-3.5f, 1.6f, 2.0f);
    glScalef(0.1f, 3.2f, 0.1f);
    glCallList(box_list);
    glPopMatrix();

    /* client-array boxes */
    glEnableClientState(GL_VERTEX_ARRAY);
    glEnableClientState(GL_NORMAL_ARRAY);
    glVertexPointer(3, GL_FLOAT, 0, cb_pos);
    glNormalPointer(GL_FLOAT, 0, cb_nrm);

    glColor3f(0.95f, 0.55f, 0.15f);
    glPushMatrix();
    glTranslatef(1.0f, 0.0f, 2.5f);
    glRotatef(10.0f, 0.0f, 1.0f, 0.0f);
    if (lock != NULL)
        lock(24, 24);
    glDrawElements(GL_TRIANGLES, CB_INDICES, GL_UNSIGNED_SHORT, cb_idx);
    if (unlock != NULL)
        unlock();
    glPopMatrix();

    glColor3f(0.3f, 0.75f, 0.35f);
    glPushMatrix();
    glTranslatef(-0.8f, 0.0f, 3.2f);
    glRotatef(45.0f, 0.0f, 1.0f, 0.0f);
    glDrawArrays(GL_QUADS, 0, 24);
    glPopMatrix();

    /* floating occluder: sphere, clearly above everything */
    glVertexPointer(3, GL_FLOAT, 0, sp_pos);
    glNormalPointer(GL_FLOAT, 0, sp_nrm);
    glMaterialfv(GL_FRONT_AND_BACK, GL_SPECULAR, spec);
    glMaterialf(GL_FRONT_AND_BACK, GL_SHININESS, 32.0f);
    glColor3f(0.8f, 0.2f, 0.6f);
    glPushMatrix();
    glTranslatef(-0.3f, 3.2f, 0.0f);
    glDrawRangeElements(GL_TRIANGLES, 0, SP_VERTS - 1, SP_INDICES, GL_UNSIGNED_SHORT, sp_idx);
    glPopMatrix();
    glMaterialfv(GL_FRONT_AND_BACK, GL_SPECULAR, no_spec);

    /* waving flag: positions/normals change every frame, colours do not */
    build_flag(frame, 0);
    glEnableClientState(GL_COLOR_ARRAY);
    glVertexPointer(3, GL_FLOAT, 0, fl_pos);
    glNormalPointer(GL_FLOAT, 0, fl_nrm);
    glColorPointer(4, GL_UNSIGNED_BYTE, 0, fl_col);
    glLightModeli(GL_LIGHT_MODEL_TWO_SIDE, GL_TRUE);
    glPushMatrix();
    glTranslatef(-3.45f, 1.9f, 2.0f);
    glDrawArrays(GL_TRIANGLES, 0, FL_VERTS);
    glPopMatrix();
    glLightModeli(GL_LIGHT_MODEL_TWO_SIDE, GL_FALSE);
    glDisableClientState(GL_COLOR_ARRAY);
    glDisableClientState(GL_NORMAL_ARRAY);
    glDisableClientState(GL_VERTEX_ARRAY);
}

/* ---------------------------------------------------------------- --widget */

struct widget_target {
    GLXContext context;
    GLXPbuffer pbuffer;
    GLuint framebuffer, texture, depth;
    /* --widget-samples N: the scene is drawn into multisampled renderbuffers (framebuffer
     * `framebuffer`) and resolved into the texture's framebuffer `resolved`, as a QOpenGLWidget
     * with samples does */
    int samples;
    GLuint resolved, color;
    /* --widget-post: the picture copied into post_texture, which the window shows */
    int post;
    GLuint post_framebuffer, post_texture;
    /* --widget-wire: the box's colour, over the scene's depth */
    int wire;
    GLuint wire_framebuffer, wire_texture;
    int x, y, width, height; /* where the window shows it */
};

static PFNGLGENFRAMEBUFFERSPROC gen_framebuffers;
static PFNGLBINDFRAMEBUFFERPROC bind_framebuffer;
static PFNGLFRAMEBUFFERTEXTURE2DPROC framebuffer_texture;
static PFNGLGENRENDERBUFFERSPROC gen_renderbuffers;
static PFNGLBINDRENDERBUFFERPROC bind_renderbuffer;
static PFNGLRENDERBUFFERSTORAGEMULTISAMPLEPROC renderbuffer_storage_multisample;
static PFNGLFRAMEBUFFERRENDERBUFFERPROC framebuffer_renderbuffer;
static PFNGLCHECKFRAMEBUFFERSTATUSPROC check_status;
static PFNGLBLITFRAMEBUFFERPROC blit_framebuffer;

#define GL_PROC(type, name) (type)glXGetProcAddressARB((const GLubyte *)name)

/* A colour texture of the widget's size, read with nearest texels. */
static GLuint widget_texture(const struct widget_target *t)
{
    GLuint texture = 0;
    glGenTextures(1, &texture);
    glBindTexture(GL_TEXTURE_2D, texture);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, t->width, t->height, 0, GL_RGBA, GL_UNSIGNED_BYTE, NULL);
    glBindTexture(GL_TEXTURE_2D, 0);
    return texture;
}

/* A framebuffer object of `texture` alone; -1 (said) when it is not complete. Leaves it bound. */
static int colour_framebuffer(GLuint texture, GLuint *framebuffer, const char *what)
{
    gen_framebuffers(1, framebuffer);
    bind_framebuffer(GL_FRAMEBUFFER, *framebuffer);
    framebuffer_texture(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, texture, 0);
    if (check_status(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) {
        fprintf(stderr, "%s: %s framebuffer object is not complete\n", PROG, what);
        return -1;
    }
    return 0;
}

/* The scene's context: shares objects with `window_context`, current on a 1x1 pbuffer of the
 * window's visual, with a framebuffer object of the widget's size. Leaves it current. */
static int widget_create(Display *dpy, XVisualInfo *vi, GLXContext window_context, int w, int h,
                         struct widget_target *t)
{
    static const int pbuffer_attribs[] = {GLX_PBUFFER_WIDTH, 1, GLX_PBUFFER_HEIGHT, 1, None};
    GLXFBConfig *configs, config = NULL;
    int n = 0, i;
    gen_framebuffers = GL_PROC(PFNGLGENFRAMEBUFFERSPROC, "glGenFramebuffers");
    bind_framebuffer = GL_PROC(PFNGLBINDFRAMEBUFFERPROC, "glBindFramebuffer");
    framebuffer_texture = GL_PROC(PFNGLFRAMEBUFFERTEXTURE2DPROC, "glFramebufferTexture2D");
    gen_renderbuffers = GL_PROC(PFNGLGENRENDERBUFFERSPROC, "glGenRenderbuffers");
    bind_renderbuffer = GL_PROC(PFNGLBINDRENDERBUFFERPROC, "glBindRenderbuffer");
    renderbuffer_storage_multisample =
        GL_PROC(PFNGLRENDERBUFFERSTORAGEMULTISAMPLEPROC, "glRenderbufferStorageMultisample");
    framebuffer_renderbuffer = GL_PROC(PFNGLFRAMEBUFFERRENDERBUFFERPROC, "glFramebufferRenderbuffer");
    check_status = GL_PROC(PFNGLCHECKFRAMEBUFFERSTATUSPROC, "glCheckFramebufferStatus");
    blit_framebuffer = GL_PROC(PFNGLBLITFRAMEBUFFERPROC, "glBlitFramebuffer");
    configs = glXGetFBConfigs(dpy, vi->screen, &n);
    for (i = 0; i < n && config == NULL; i++) {
        int visual = 0, types = 0;
        glXGetFBConfigAttrib(dpy, configs[i], GLX_VISUAL_ID, &visual);
        glXGetFBConfigAttrib(dpy, configs[i], GLX_DRAWABLE_TYPE, &types);
        if ((VisualID)visual == vi->visualid && (types & GLX_PBUFFER_BIT))
            config = configs[i];
    }
    if (configs != NULL)
        XFree(configs);
    if (config == NULL || gen_framebuffers == NULL || check_status == NULL || blit_framebuffer == NULL) {
        fprintf(stderr, "%s: --widget: no pbuffer config for the window's visual, or no framebuffer objects\n", PROG);
        return -1;
    }
    t->context = glXCreateNewContext(dpy, config, GLX_RGBA_TYPE, window_context, True);
    t->pbuffer = glXCreatePbuffer(dpy, config, pbuffer_attribs);
    if (t->context == NULL || !glXMakeContextCurrent(dpy, t->pbuffer, t->pbuffer, t->context)) {
        fprintf(stderr, "%s: --widget: cannot make the scene's context current\n", PROG);
        return -1;
    }
    t->width = w * 5 / 8, t->height = h * 3 / 4, t->x = w / 4, t->y = h / 8;
    t->texture = widget_texture(t);
    gen_renderbuffers(1, &t->depth);
    bind_renderbuffer(GL_RENDERBUFFER, t->depth);
    renderbuffer_storage_multisample(GL_RENDERBUFFER, t->samples, GL_DEPTH24_STENCIL8, t->width, t->height);
    gen_framebuffers(1, &t->framebuffer);
    bind_framebuffer(GL_FRAMEBUFFER, t->framebuffer);
    if (t->samples) {
        gen_renderbuffers(1, &t->color);
        bind_renderbuffer(GL_RENDERBUFFER, t->color);
        renderbuffer_storage_multisample(GL_RENDERBUFFER, t->samples, GL_RGBA8, t->width, t->height);
        framebuffer_renderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, t->color);
    } else {
        framebuffer_texture(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, t->texture, 0);
    }
    framebuffer_renderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, t->depth);
    framebuffer_renderbuffer(GL_FRAMEBUFFER, GL_STENCIL_ATTACHMENT, GL_RENDERBUFFER, t->depth);
    if (check_status(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) {
        fprintf(stderr, "%s: --widget: the widget's framebuffer object is not complete\n", PROG);
        return -1;
    }
    if (t->samples && colour_framebuffer(t->texture, &t->resolved, "--widget: the resolve") != 0)
        return -1;
    if (t->wire) {  /* (a texture of the widget's size over the widget's depth) */
        t->wire_texture = widget_texture(t);
        if (colour_framebuffer(t->wire_texture, &t->wire_framebuffer, "--widget-wire: the box's target") != 0)
            return -1;
        bind_framebuffer(GL_FRAMEBUFFER, t->wire_framebuffer);
        framebuffer_renderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, t->depth);
        if (check_status(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) {
            fprintf(stderr, "%s: --widget-wire: the box's framebuffer object is not complete\n", PROG);
            return -1;
        }
    }
    if (t->post) {  /* (a texture of the widget's size, in a framebuffer object without depth) */
        t->post_texture = widget_texture(t);
        if (colour_framebuffer(t->post_texture, &t->post_framebuffer, "--widget-post: the copy") != 0)
            return -1;
    }
    bind_framebuffer(GL_FRAMEBUFFER, 0);
    return 0;
}

static void draw_viewport_quad(void);

/* --widget-post: the widget's picture copied into post_texture by a full-target quad. */
static void widget_copy(const struct widget_target *t)
{
    bind_framebuffer(GL_FRAMEBUFFER, t->post_framebuffer);
    glPushAttrib(GL_ALL_ATTRIB_BITS);
    glViewport(0, 0, t->width, t->height);
    glDisable(GL_DEPTH_TEST);
    glDisable(GL_LIGHTING);
    glDisable(GL_FOG);
    glDisable(GL_BLEND);
    glMatrixMode(GL_PROJECTION);
    glPushMatrix();
    glLoadIdentity();
    glMatrixMode(GL_MODELVIEW);
    glPushMatrix();
    glLoadIdentity();
    glEnable(GL_TEXTURE_2D);
    glBindTexture(GL_TEXTURE_2D, t->texture);
    glTexEnvi(GL_TEXTURE_ENV, GL_TEXTURE_ENV_MODE, GL_REPLACE);
    draw_viewport_quad();
    glBindTexture(GL_TEXTURE_2D, 0);
    glPopMatrix();
    glMatrixMode(GL_PROJECTION);
    glPopMatrix();
    glMatrixMode(GL_MODELVIEW);
    glPopAttrib();
}

/* --widget-wire: the box's twelve edges into the box's target with the scene's camera. */

static void widget_wire_box(const struct widget_target *t)
{
    static const float centre[3] = {2.5f, 0.8f, 1.5f}, half = 0.6f;
    bind_framebuffer(GL_FRAMEBUFFER, t->wire_framebuffer);
    glPushAttrib(GL_ALL_ATTRIB_BITS);
    glClearColor(0, 0, 0, 0);
    glClear(GL_COLOR_BUFFER_BIT);
    glDisable(GL_LIGHTING);
    glDisable(GL_TEXTURE_2D);
    glDisable(GL_FOG);
    glEnable(GL_DEPTH_TEST);
    glDepthMask(GL_TRUE);
    glLineWidth(3);
    glColor3ub(250, 250, 120);
    glMatrixMode(GL_MODELVIEW);
    glPushMatrix();
    glLoadMatrixf(scene_view);
    glBegin(GL_LINES);
    for (int axis = 0; axis < 3; axis++)
        for (int k = 0; k < 4; k++)
            for (int end = -1; end <= 1; end += 2) {
                float v[3];
                v[axis] = (float)end * half;
                v[(axis + 1) % 3] = (k & 1 ? 1.0f : -1.0f) * half;
                v[(axis + 2) % 3] = (k & 2 ? 1.0f : -1.0f) * half;
                glVertex3f(centre[0] + v[0], centre[1] + v[1], centre[2] + v[2]);
            }
    glEnd();
    glPopMatrix();
    glPopAttrib();
}

/* Before the scene (bind), after it (unbind; multisampled: its colour resolved into the texture). */
static void widget_bind(const struct widget_target *t, int bind)
{
    if (!bind && t->samples) {
        bind_framebuffer(GL_READ_FRAMEBUFFER, t->framebuffer);
        bind_framebuffer(GL_DRAW_FRAMEBUFFER, t->resolved);
        blit_framebuffer(0, 0, t->width, t->height, 0, 0, t->width, t->height, GL_COLOR_BUFFER_BIT, GL_NEAREST);
    }
    if (!bind && t->wire)
        widget_wire_box(t);
    if (!bind && t->post)
        widget_copy(t);
    bind_framebuffer(GL_FRAMEBUFFER, bind ? t->framebuffer : 0);
}

/* The bound texture over the whole viewport (the matrices are the identity). */
static void draw_viewport_quad(void)
{
    glBegin(GL_QUADS);
    glTexCoord2f(0, 0); glVertex2f(-1, -1);
    glTexCoord2f(1, 0); glVertex2f(1, -1);
    glTexCoord2f(1, 1); glVertex2f(1, 1);
    glTexCoord2f(0, 1); glVertex2f(-1, 1);
    glEnd();
}

/* The window's context: the toolkit's frame around the widget's picture. */
static void widget_composite(const struct widget_target *t, int w, int h)
{
    glViewport(0, 0, w, h);
    glClearColor(0.78f, 0.78f, 0.78f, 1.0f);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    glMatrixMode(GL_PROJECTION);
    glLoadIdentity();
    glMatrixMode(GL_MODELVIEW);
    glLoadIdentity();
    glDisable(GL_DEPTH_TEST);
    glEnable(GL_TEXTURE_2D);
    glBindTexture(GL_TEXTURE_2D, t->post ? t->post_texture : t->texture);
    glTexEnvi(GL_TEXTURE_ENV, GL_TEXTURE_ENV_MODE, GL_REPLACE);
    /* placed by the viewport: a quad over all of it */
    glViewport(t->x, t->y, t->width, t->height);
    draw_viewport_quad();
    if (t->wire) {
        glBindTexture(GL_TEXTURE_2D, t->wire_texture);
        glEnable(GL_BLEND);
        glBlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
        draw_viewport_quad();
        glDisable(GL_BLEND);
    }
    glBindTexture(GL_TEXTURE_2D, 0);
    glDisable(GL_TEXTURE_2D);
    glViewport(0, 0, w, h);
    glMatrixMode(GL_PROJECTION);
    glOrtho(0, w, 0, h, -1, 1);
    glMatrixMode(GL_MODELVIEW);
    glColor3ub(40, 90, 200);
    glRecti(0, h - 16, w, h);                          /* toolbar */
    glRecti(t->x + 4, t->y + 4, t->x + 64, t->y + 20); /* label over the widget */
}

/* --preview: the widget's picture drawn small in the top left corner of the sky, before the
 * window's own scene (which does not clear the colour): a picture in the program's own scene. */
static void widget_preview(const struct widget_target *t, int w, int h)
{
    glClearColor(0.53f, 0.75f, 0.95f, 1.0f);
    glClear(GL_COLOR_BUFFER_BIT);
    glPushAttrib(GL_ENABLE_BIT | GL_TEXTURE_BIT);
    glDisable(GL_DEPTH_TEST);
    glDisable(GL_LIGHTING);
    glMatrixMode(GL_PROJECTION);
    glLoadIdentity();
    glMatrixMode(GL_MODELVIEW);
    glLoadIdentity();
    glEnable(GL_TEXTURE_2D);
    glBindTexture(GL_TEXTURE_2D, t->texture);
    glTexEnvi(GL_TEXTURE_ENV, GL_TEXTURE_ENV_MODE, GL_REPLACE);
    glViewport(4, h - 4 - h / 5, w / 5, h / 5);
    draw_viewport_quad();
    glBindTexture(GL_TEXTURE_2D, 0);
    glPopAttrib();
    glViewport(0, 0, w, h);
}

static void init_fixed_state(void)
{
    const GLfloat amb[4] = {0.25f, 0.25f, 0.28f, 1.0f};
    const GLfloat dif[4] = {0.9f, 0.9f, 0.85f, 1.0f};
    const GLfloat spc[4] = {0.7f, 0.7f, 0.7f, 1.0f};
    const GLfloat global_amb[4] = {0.1f, 0.1f, 0.12f, 1.0f};
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glEnable(GL_LIGHTING);
    glEnable(GL_LIGHT0);
    glEnable(GL_NORMALIZE);
    glLightfv(GL_LIGHT0, GL_AMBIENT, amb);
    glLightfv(GL_LIGHT0, GL_DIFFUSE, dif);
    glLightfv(GL_LIGHT0, GL_SPECULAR, spc);
    glLightModelfv(GL_LIGHT_MODEL_AMBIENT, global_amb);
    glColorMaterial(GL_FRONT_AND_BACK, GL_AMBIENT_AND_DIFFUSE);
    glEnable(GL_COLOR_MATERIAL);
    glShadeModel(GL_SMOOTH);
}

/* ---------------------------------------------------------------- main */

/* A game's HUD: 2D, drawn last, without depth; --dim: the scene dimmed under it first. */
static int dim;
static void draw_hud(int width, int height, int frame)
{
    static const GLubyte glyph[8] = {0x7e, 0x42, 0x5a, 0x5a, 0x5a, 0x42, 0x7e, 0x00};
    glPushAttrib(GL_ENABLE_BIT | GL_CURRENT_BIT | GL_TEXTURE_BIT);
    glDisable(GL_DEPTH_TEST);
    glDisable(GL_LIGHTING);
    glDisable(GL_TEXTURE_2D);
    glMatrixMode(GL_PROJECTION);
    glPushMatrix();
    glLoadIdentity();
    glOrtho(0, width, 0, height, -1, 1);
    glMatrixMode(GL_MODELVIEW);
    glPushMatrix();
    glLoadIdentity();
    if (dim) {
        glPushAttrib(GL_COLOR_BUFFER_BIT);
        glEnable(GL_BLEND);
        glBlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
        glColor4f(0, 0, 0, 0.27f);
        glRecti(0, 0, width, height);
        glPopAttrib();
    }
    glColor3ub(230, 50, 40);
    glRecti(8, 8, 136, 40);
    glColor3ub(255, 255, 255);
    glRasterPos2i(12, 52);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    for (int i = 0; i < 6 + frame % 3; i++)
        glBitmap(8, 8, 0, 0, 10, 0, glyph);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
    glPopMatrix();
    glMatrixMode(GL_PROJECTION);
    glPopMatrix();
    glMatrixMode(GL_MODELVIEW);
    glPopAttrib();
}

int main(int argc, char **argv)
{
    struct app_args args;
    Display *dpy;
    XVisualInfo *vi;
    Colormap cmap;
    XSetWindowAttributes swa;
    Window win;
    XEvent ev;
    GLXContext ctx;
    struct widget_target target;
    GLuint tex[2], box_list;
    PFNGLLOCKARRAYSEXTPROC lock = NULL;
    PFNGLUNLOCKARRAYSEXTPROC unlock = NULL;
    unsigned char *shot = NULL;
    int have_cva, frame;
    int attribs[] = {GLX_RGBA, GLX_DOUBLEBUFFER, GLX_RED_SIZE, 8, GLX_GREEN_SIZE, 8,
                     GLX_BLUE_SIZE, 8, GLX_DEPTH_SIZE, 24, None};

    const int hud = app_take_flag(&argc, &argv, "--hud");
    dim = hud && app_take_flag(&argc, &argv, "--dim");
    backdrop = app_take_flag(&argc, &argv, "--backdrop");
    reflection = app_take_flag(&argc, &argv, "--reflection");
    weapon = app_take_flag(&argc, &argv, "--weapon");
    culled = app_take_flag(&argc, &argv, "--culled");
    widget = app_take_flag(&argc, &argv, "--widget");
    preview = app_take_flag(&argc, &argv, "--preview");
    target.post = widget && app_take_flag(&argc, &argv, "--widget-post");
    const int widget_swaps = app_take_flag(&argc, &argv, "--widget-swaps");
    target.wire = app_take_flag(&argc, &argv, "--widget-wire");
    widget = widget || preview || widget_swaps || target.wire;
    target.samples = 0;
    for (int i = 1; i + 1 < argc; i++)
        if (strcmp(argv[i], "--widget-samples") == 0) {
            target.samples = atoi(argv[i + 1]);
            memmove(&argv[i], &argv[i + 2], (size_t)(argc - i - 1) * sizeof argv[0]);
            argc -= 2;
            widget = 1;
            break;
        }
    if (target.wire && target.samples) {
        fprintf(stderr, "%s: --widget-wire draws over a single-sampled depth: not with --widget-samples\n", PROG);
        return 2;
    }
    app_parse_args(PROG, argc, argv, &args);

    dpy = XOpenDisplay(NULL);
    if (dpy == NULL) {
        fprintf(stderr, "%s: cannot open X display\n", PROG);
        return 1;
    }
    vi = glXChooseVisual(dpy, DefaultScreen(dpy), attribs);
    if (vi == NULL) {
        fprintf(stderr, "%s: glXChooseVisual: no RGBA double-buffered visual with depth 24\n", PROG);
        return 1;
    }
    cmap = XCreateColormap(dpy, RootWindow(dpy, vi->screen), vi->visual, AllocNone);
    memset(&swa, 0, sizeof swa);
    swa.colormap = cmap;
    swa.event_mask = StructureNotifyMask | ExposureMask;
    win = XCreateWindow(dpy, RootWindow(dpy, vi->screen), 0, 0, (unsigned)args.width,
                        (unsigned)args.height, 0, vi->depth, InputOutput, vi->visual,
                        CWColormap | CWEventMask, &swa);
    XStoreName(dpy, win, "glcast ff_scene");
    XMapWindow(dpy, win);
    XIfEvent(dpy, &ev, wait_for_map, (XPointer)&win);

    ctx = glXCreateContext(dpy, vi, NULL, True);
    if (ctx == NULL) {
        fprintf(stderr, "%s: glXCreateContext failed\n", PROG);
        return 1;
    }
    if (!glXMakeCurrent(dpy, win, ctx)) {
        fprintf(stderr, "%s: glXMakeCurrent failed\n", PROG);
        return 1;
    }

    printf("%s: GL_RENDERER %s\n", PROG, (const char *)glGetString(GL_RENDERER));
    printf("%s: GL_VERSION %s\n", PROG, (const char *)glGetString(GL_VERSION));
    have_cva = has_extension((const char *)glGetString(GL_EXTENSIONS), "GL_EXT_compiled_vertex_array");
    if (have_cva) {
        lock = (PFNGLLOCKARRAYSEXTPROC)glXGetProcAddressARB((const GLubyte *)"glLockArraysEXT");
        unlock = (PFNGLUNLOCKARRAYSEXTPROC)glXGetProcAddressARB((const GLubyte *)"glUnlockArraysEXT");
        if (lock == NULL || unlock == NULL)
            lock = NULL, unlock = NULL, have_cva = 0;
    }
    printf("%s: GL_EXT_compiled_vertex_array %s\n", PROG, have_cva ? "yes" : "no");
    /* --widget: the scene's objects and state are made in the scene's context */
    if (widget && widget_create(dpy, vi, ctx, args.width, args.height, &target) != 0)
        return 1;
    if (widget_swaps)
        glXSwapBuffers(dpy, target.pbuffer);

    build_unit_box();
    build_client_boxes();
    build_sphere(0.75f);
    build_flag(0, 1);

    /* textures */
    glGenTextures(2, tex);
    app_print_names(PROG, "glGenTextures", tex, 2);
    {
        GLubyte checker[CHECK_SIZE * CHECK_SIZE * 3];
        GLubyte crate[CRATE_SIZE * CRATE_SIZE * 4];
        glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
        make_checker(checker, CHECK_SIZE);
        glBindTexture(GL_TEXTURE_2D, tex[0]);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_REPEAT);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_REPEAT);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_LINEAR);
        upload_mipmapped_rgb(checker, CHECK_SIZE);

        make_crate(crate);
        glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
        glBindTexture(GL_TEXTURE_2D, tex[1]);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
        glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, CRATE_SIZE, CRATE_SIZE, 0, GL_RGBA,
                     GL_UNSIGNED_BYTE, crate);
        glTexEnvi(GL_TEXTURE_ENV, GL_TEXTURE_ENV_MODE, GL_MODULATE);
    }

    /* display list: unit box with normals and texcoords */
    box_list = glGenLists(1);
    app_print_names(PROG, "glGenLists", &box_list, 1);
    glNewList(box_list, GL_COMPILE);
    {
        int v;
        glBegin(GL_QUADS);
        for (v = 0; v < 24; v++) {
            glNormal3fv(box_nrm[v]);
            glTexCoord2fv(box_tc[v]);
            glVertex3fv(box_pos[v]);
        }
        glEnd();
    }
    glEndList();

    init_fixed_state();
    if (preview) { /* the window's context draws the scene too */
        glXMakeCurrent(dpy, win, ctx);
        init_fixed_state();
    }
    check_gl_errors(-1);

    printf("%s: frames %d\n", PROG, args.frames);
    fflush(stdout);

    for (frame = 0; frame < args.frames; frame++) {
        while (XPending(dpy) > 0)
            XNextEvent(dpy, &ev);
        if (widget) {
            if (frame % WIDGET_REDRAW == 0) {
                glXMakeContextCurrent(dpy, target.pbuffer, target.pbuffer, target.context);
                widget_bind(&target, 1);
                draw_frame(frame, args.dolly, target.width, target.height, tex[0], tex[1], box_list, lock, unlock);
                widget_bind(&target, 0);
                glFlush();
                check_gl_errors(frame);
            }
            glXMakeCurrent(dpy, win, ctx);
            if (preview) {
                widget_preview(&target, args.width, args.height);
                preview_first = 1;
                draw_frame(frame, args.dolly, args.width, args.height, tex[0], tex[1], box_list, lock, unlock);
                preview_first = 0;
            } else {
                widget_composite(&target, args.width, args.height);
            }
        } else {
            draw_frame(frame, args.dolly, args.width, args.height, tex[0], tex[1], box_list, lock, unlock);
        }
        if (hud)
            draw_hud(args.width, args.height, frame);
        if (frame == args.frames - 1 && args.screenshot != NULL) {
            shot = malloc((size_t)args.width * (size_t)args.height * 3u);
            glReadBuffer(GL_BACK);
            glPixelStorei(GL_PACK_ALIGNMENT, 1);
            glReadPixels(0, 0, args.width, args.height, GL_RGB, GL_UNSIGNED_BYTE, shot);
        }
        check_gl_errors(frame);
        glXSwapBuffers(dpy, win);
    }

    glDeleteLists(box_list, 1);
    glDeleteTextures(2, tex);
    check_gl_errors(args.frames);
    glXMakeCurrent(dpy, None, NULL);
    if (widget) {
        glXDestroyPbuffer(dpy, target.pbuffer);
        glXDestroyContext(dpy, target.context);
    }
    glXDestroyContext(dpy, ctx);
    XDestroyWindow(dpy, win);
    XFreeColormap(dpy, cmap);
    XFree(vi);
    XCloseDisplay(dpy);

    if (shot != NULL) {
        if (app_write_ppm(args.screenshot, args.width, args.height, shot) != 0) {
            fprintf(stderr, "%s: cannot write screenshot '%s'\n", PROG, args.screenshot);
            free(shot);
            return 1;
        }
        free(shot);
    }
    return 0;
}
