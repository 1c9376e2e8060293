/*
 * pillars.c - a viewer in the middle of a ring of coloured pillars, for the rotated-view
 * tests (cylinder and CAVE walls). Fixed function, GLX. The camera sits at the origin looking
 * down -Z with a 60-degree horizontal field of view; pillar k stands at yaw k*30 degrees
 * (positive to the right), 6 units away, in a colour that encodes k: red = 40 + 16 k, green =
 * 200 - 12 k, blue = 255 - 20 k, unlit, so a tile that faces yaw k*30 shows that colour at its
 * centre. A grey floor below the horizon.
 *
 * With --shader (a first argument) the same picture comes from a GLSL 1.20 program whose
 * projection is a uniform: the stream then does not show it, and a rotated wall needs the
 * display config's program_projection (vertical field of view 2 atan(tan 30 deg * h / w)).
 *
 * With --builtins the shader reads the fixed-function matrices through GLSL's built-ins
 * (gl_ModelViewProjectionMatrix): the program sets GL_PROJECTION and GL_MODELVIEW as a fixed
 * function program does and has no matrix uniform at all (as voxel games written against
 * GLSL 1.20 do).
 *
 * With --mvp every draw uploads one premultiplied matrix, projection * view * model: each pillar
 * is modelled at the origin and placed by a model matrix of its own (a rotation about y and a
 * translation), under a view that looks slightly down.
 *
 * With --grow the window is made at 32x32, the viewport set once for the full size, and the
 * window then grown to it; no frame sets the viewport again (as apitrace's retrace does).
 *
 * With --fbo the scene is drawn into a framebuffer object (a colour texture and a depth
 * renderbuffer) and shown in the window by a full-window textured quad with the depth test off,
 * as engines show their scene after post-processing; --half makes that target half the window's
 * width and height (an engine's render scale), stretched to the window (nearest texels, so
 * colours stay exact).
 *
 * With --fbo --fragcoord (not --region or --mirror) the quad that shows the scene (and --post's
 * copy) is drawn by a GLSL program that reads the scene's texture at gl_FragCoord.xy divided by
 * the window's size, a uniform (SuperTuxKart's last pass does so): where a fragment lands in the
 * window says which texel it shows. With --shader --objects its vertex shader declares the view's
 * uniform block (bound, std140) and reads none of it.
 *
 * With --mvp --fbo --gbuffer the scene is drawn twice with one camera, as deferred renderers
 * (SuperTuxKart) draw theirs: first into a framebuffer object of its own (colour and depth) at the
 * window's size, then into the scene's by a program that takes each fragment's colour from the
 * first at gl_FragCoord over the window's size (a light buffer's lookup).
 *
 * With --hud --hud-vao (not --mvp) the HUD is drawn from a vertex-array object of its own, whose
 * vertex pointer is set once (as SuperTuxKart's 2D quads are), and the floor from a buffer with the
 * vertex-array object 0 bound, its vertex pointer set and its array enabled and disabled each frame.
 *
 * With --reversed the depth is reversed, as engines since 2015 keep it for precision: clip
 * control GL_ZERO_TO_ONE, a projection with an infinite far plane that maps the near plane to
 * depth 1 and infinity to 0 (loaded with glLoadMatrixd), depth cleared to 0 and tested
 * GL_GREATER.
 *
 * With --hud every frame ends with a HUD panel (230, 50, 40) over the scene, window pixels x 20..120,
 * y 220..280 of a 400x300 window (scaled with --size; GL: y up), drawn with the depth test off under
 * an orthographic projection: by fixed function, or by the shader program with the orthographic
 * matrix in its uniform (--shader, --mvp) or in GL_PROJECTION (--builtins).
 *
 * With --fbo --hud --in-scene the HUD is drawn into the scene's framebuffer object, after the
 * pillars and before the scene is shown (as VTK draws its text actors), and lower: window pixels
 * x 20..120, y 40..100 of 400x300, over the floor, where every pass decorates. With --depth-on after
 * it, the HUD is drawn with the depth test left on, as VTK leaves it for its 2D actors (the panel's
 * depth, 0.5, lies in front of the floor's there).
 *
 * With --fbo --depth-texture the scene's depth is a 32-bit float depth texture, as deferred
 * renderers keep it to sample it later, instead of a renderbuffer.
 *
 * With --fbo --mrt the scene's framebuffer object has a second colour attachment, written too (as
 * deferred renderers write several targets at once); with --fbo --msaa the scene is drawn into a
 * multisampled framebuffer object (4 samples) and resolved with glBlitFramebuffer into the
 * texture the window's quad shows.
 *
 * With --hand (not with --fbo) the scene is followed by a view model as voxel games draw their
 * player's hand: the window's depth cleared alone, then a square (200, 180, 150) under a
 * projection of its own (a wider field of view), writing depth, at window x 0.69..0.94 and
 * y 0.67..0.92 of the width and height (GL: y up), where the picture shows sky between pillars.
 *
 * With --left-handed the world and the eye space are left-handed, as Irrlicht's (minetest's) are:
 * every z is negated in the vertices and the projection has w = +z (glLoadMatrixd of the
 * standard one with its third column negated), so the picture is the standard one's. With
 * --mvp, the product of that projection and the view and model matrices written in left-handed
 * coordinates (S V S, S M S with S mirroring z) is uploaded: SuperTuxKart's u_projection_view_matrix,
 * with the floor's and pillars' vertices as they are (symmetric in z, or at z = 0). With
 * --builtins --mixed the floor is drawn by fixed function and the pillars by the shader program
 * (a sky or a cloud layer by fixed function, the terrain by built-ins, as minetest draws).
 *
 * With --builtins --foliage the pillars are alpha-tested cut-outs, as a voxel game's plants: a 2x1
 * texture, opaque on the left and transparent on the right, across each pillar, the fragment
 * shader writing its alpha and GL_ALPHA_TEST (GL_GREATER 0.5) on for the scene's draws, off
 * after them; each pillar shows its left half only.
 *
 * With --fbo --post a post-processing step follows the scene: a full-screen quad copies its
 * texture into a second framebuffer object of the window's size, with a depth buffer of its own
 * (as VTK's and many engines' are), and that one is shown in the window with the depth test on,
 * GL_ALWAYS and depth writes (VTK copies its scene's depth into the window so).
 *
 * With --fbo --region the window is a content suite's: a toolbar down its left fifth (60, 62, 70), a
 * header across its top 40 of 300 rows (45, 48, 55), and between them a 3D viewport, window pixels
 * x 80..400, y 0..260 of 400x300 (GL: y up), whose scene is drawn into a framebuffer object of that
 * region's size (its own aspect) and shown there by a fixed-function textured quad placed in window
 * pixels under an orthographic projection, drawn after the toolbar and before the header, as
 * Blender composites its regions (with a shader program of the scene's --shader, --builtins or --mvp:
 * a GLSL texture blit, as Blender's and Qt's are). With --hud a gizmo square (230, 50, 40) is drawn over the
 * viewport after it, at x 330..380, y 190..240. With --post the scene's colour is first copied by a
 * full-target draw into a second framebuffer object of the region's size that shares the scene's
 * depth renderbuffer (Blender's viewport resolves its engines' colour so), and that one is shown.
 * With --blit the viewport is shown by glBlitFramebuffer from its target into that rectangle of the
 * window instead of a quad (with --msaa straight from the multisampled target: the resolve is the
 * blit that shows it, as programs drawing with multisampling often show their scene).
 *
 * With --overlay the pillars are drawn after the floor with the depth test off (they stand on it and
 * do not hide one another); with --fbo (not --msaa) into a second framebuffer object that holds the
 * scene's colour texture and no depth, as Blender's overlay engine draws its grid, outlines and
 * object centres into a colour-only target of the viewport's size over the engines' picture.
 *
 * With --fbo --wire (fixed function, not --post) a wire-frame box (WIRE, lines 3
 * pixels wide) with a filled lid floats over the floor, left of pillar 0, drawn after the pillars with the main
 * view's camera into a second framebuffer object that holds a colour texture of its own (cleared
 * transparent every frame) and the scene's depth, the depth test and depth writes on; the window
 * shows the scene, then that texture blended over it: as Blender's overlay engine draws the camera's
 * and the light's wire frames and composites them over its engines' picture. With --region (not
 * --blit) the viewport is shown by one GLSL draw that samples both textures and mixes the box over
 * the scene by its alpha, as Blender's window composites its viewport's colour and overlay textures.
 * With --msaa (not --region) the box's target is multisampled too: a multisampled colour texture of
 * its own over the multisampled scene's depth, resolved into a texture by a blit before it is
 * blended over the scene. With --rect (not --msaa or --region) the box's colour is a rectangle
 * texture (GL_TEXTURE_RECTANGLE, which programs from before non-power-of-two textures keep their
 * window-sized targets in), blended over the scene by fixed function. Every frame with --wire asks glGetError once, as programs that check their
 * errors do (glcast replay --verify compares the slave's answer with the master's).
 *
 * With --fbo --mirror (fixed function, not --msaa, --region, --post or --wire) the scene is drawn
 * upside down into its target (glFrustum with its bottom and top swapped) and shown by a
 * glBlitFramebuffer into the window whose destination's rows are swapped, so that the picture is
 * the upright one: as a Direct3D program under Wine draws (its origin top left) and presents.
 * With --mirror-columns (the same conditions) it is drawn mirrored left to right instead (glFrustum
 * with its left and right swapped) and shown by a blit whose destination's columns are swapped.
 *
 * With --bbox (fixed function, --builtins or --mvp; not --left-handed or --scale) a bounding box's twelve
 * edges (BBOX, lines 2 pixels wide) around pillar 0, x -2..2, y -1.9..0.5, z -9..-5.5, are
 * drawn after the pillars with the main view's camera by the program that drew them, the depth test
 * and depth writes on, as view3dscene draws its scene's bounding box: lines over the floor, in front
 * of pillar 0 and across the sky.
 *
 * With --canopy (fixed function) a translucent white sheet (alpha 60/255) spans the sky at y = 8,
 * above the pillars' tops, drawn last with blending and the depth test and writes on, as minetest
 * draws its cloud layer.
 *
 * With --blended every draw is made with blending on (GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA) and opaque
 * colours, as openscad leaves GL_BLEND on for its whole scene: the picture is the one without it.
 *
 * With --reflection (not --mvp, --reversed or --foliage) the floor gets a reflection as neverball
 * draws its mirror: after the floor, with the depth test off and the main view's projection, a
 * quad in the floor's plane (the reflection's sky, REFLECTION's colour), then the floor again over
 * it with GL_LEQUAL (neverball blends its floor over the reflection; here it is opaque, so the
 * picture is the one without it). The quad writes no depth and is no overlay: the scene goes on.
 *
 * With --shader --objects the projection is in a uniform block of its own, declared before a block
 * of 512 per-object matrix pairs (model and its inverse; the first the identity, the rest zero), as
 * Blender's draw manager keeps its view and its objects: std140 makes every one of the 1,024
 * per-object matrices an active uniform of the program, and Mesa lists the later block's first.
 * Its shader also declares a block LightingData holding a sun_direction that no stage reads, left
 * at binding 0, where the objects' buffer is bound too (SuperTuxKart's geometry programs declare
 * its lighting block so: what it holds there is another block's data, no light).
 * Each frame the view's buffer is bound to GL_UNIFORM_BUFFER, its projection uploaded with
 * glBufferSubData, and the objects' bound to its binding point again by glBindBufferBase (which
 * binds GL_UNIFORM_BUFFER to it too), as SuperTuxKart updates its camera's block.
 *
 * With --fbo --grade a colour grade follows the scene in its target: a full-target triangle whose
 * vertex shader places it by gl_VertexID with no matrix at all, halving every pixel's colour by
 * blending (GL_DST_COLOR, GL_ZERO), as an engine's screen-space passes (an outline, a background,
 * a tone map) work on the picture in the scene's own target.
 *
 * With --markers the scene gets marker points (GL_POINTS of size 4, depth-tested, unlit) at known
 * positions of its eye space, one colour each, for the immersive-wall tests (units are metres there,
 * the camera at a room's origin): MARKERS below, the first straight ahead behind a CAVE's front wall.
 *
 * With --cull the program culls as engines do: a pillar wholly outside its own horizontal field of
 * view is not drawn at all (not by fixed function, --shader or --builtins). --fov DEG sets that
 * field of view (default 60; the picture is then wider, the pillars smaller).
 *
 * With --scale S (fixed function or --builtins) the program works at S times the scale: its frustum's
 * near and far planes S times as far, its view scaling the world by S (glScaled), the picture the
 * same; its eye-space distances are S times the others'.
 *
 * With --shader --fisheye the shader program projects the ring itself, not linearly (an equidistant
 * fisheye of 120 degrees across, as a planetarium projects its sky): no matrix of the program holds
 * a perspective projection, so no camera can be found; with --hud the panel is drawn by fixed
 * function over it.
 *
 * With --turn DEG the camera turns DEG degrees to the left (glRotated(DEG, 0, 1, 0) on the view: not
 * for --shader, whose only matrix is the projection), so that the world's space and the eye's differ.
 *
 * With --sun X,Y,Z (--builtins or --mvp) the shader program lights the scene itself from a sun
 * given in the world's space: `uniform vec3 sun_direction` (X,Y,Z as given: towards the sun or, with
 * its sign flipped, the way the light travels, as engines differ), each face lit by
 * 0.55 + 0.45 |N . sun|, as engines keep their sun. With --gl-light X,Y,Z (--builtins) the sun is
 * fixed-function light 0 instead (glLightfv(GL_POSITION) under the view, w = 0, GL_LIGHTING off),
 * which the shader reads through gl_LightSource[0]. The fixed-function program is unlit: the passes
 * then use their configured light. With --mvp --modelview the program keeps its camera as an engine
 * that lights in the eye's space does (Castle Game Engine's view3dscene): `uniform mat4 projection`
 * (alone) and `modelView` (view * model, per draw), and --sun's X,Y,Z is `uniform vec3
 * u_lightDirection` in the eye's space, as uploaded, each face lit by the eye-space normal.
 *
 *   pillars [--shader | --builtins | --mvp [--modelview]] [--grow] [--fbo [--half | --region [--blit]] [--mrt | --msaa] [--depth-texture] [--fragcoord] [--gbuffer]] [--reversed] [--hud [--in-scene [--depth-on]] [--hud-vao]]
 *           [--hand] [--left-handed] [--mixed] [--foliage] [--post] [--grade] [--markers] [--cull] [--overlay] [--wire [--rect]] [--mirror | --mirror-columns] [--reflection] [--bbox] [--canopy] [--blended] [--objects] [--fov DEG]
 *           [--fisheye] [--scale S] [--turn DEG] [--sun X,Y,Z | --gl-light X,Y,Z] [--frames N] [--size WxH]
 */
#define GL_GLEXT_PROTOTYPES 1
#include <GL/gl.h>
#include <GL/glext.h>
#include <GL/glx.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "../apps/app_common.h"

/* c = a * b, column-major 4x4 */
static void mul(double *c, const double *a, const double *b)
{
    for (int col = 0; col < 4; col++)
        for (int row = 0; row < 4; row++) {
            double v = 0;
            for (int k = 0; k < 4; k++) v += a[k * 4 + row] * b[col * 4 + k];
            c[col * 4 + row] = v;
        }
}

static void upload(GLint location, const double *m)
{
    GLfloat f[16];
    for (int i = 0; i < 16; i++) f[i] = (GLfloat)m[i];
    glUniformMatrix4fv(location, 1, GL_FALSE, f);
}

/* An option with a value, when it comes next: its value (and both taken off argv), else NULL. */
static const char *take_value(int *argc, char ***argv, const char *option)
{
    if (*argc < 3 || strcmp((*argv)[1], option) != 0) return NULL;
    const char *value = (*argv)[2];
    (*argv)[2] = (*argv)[0];
    *argv += 2;
    *argc -= 2;
    return value;
}

/* An RGBA8 texture of w x h, nearest texels (colours stay exact), left bound. */
static GLuint rgba8_texture_of(GLenum target, int w, int h)
{
    GLuint texture = 0;
    glGenTextures(1, &texture);
    glBindTexture(target, texture);
    glTexImage2D(target, 0, GL_RGBA8, w, h, 0, GL_RGBA, GL_UNSIGNED_BYTE, NULL);
    glTexParameteri(target, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTexParameteri(target, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    return texture;
}

static GLuint rgba8_texture(int w, int h)
{
    return rgba8_texture_of(GL_TEXTURE_2D, w, h);
}

/* A framebuffer object of w x h: a colour texture (nearest texels), returned in `color`, and a
 * depth renderbuffer of its own; 0 when it is not complete. The window is bound again after. */
static GLuint colour_and_depth_target(int w, int h, GLuint *color)
{
    GLuint depth = 0, fbo = 0;
    *color = rgba8_texture(w, h);
    glGenRenderbuffers(1, &depth);
    glBindRenderbuffer(GL_RENDERBUFFER, depth);
    glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT24, w, h);
    glGenFramebuffers(1, &fbo);
    glBindFramebuffer(GL_FRAMEBUFFER, fbo);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, *color, 0);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, depth);
    const int complete = glCheckFramebufferStatus(GL_FRAMEBUFFER) == GL_FRAMEBUFFER_COMPLETE;
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    return complete ? fbo : 0;
}

/* A framebuffer object over the depth attachment of `scene_fbo` (a texture with --depth-texture,
 * else a renderbuffer) with an RGBA8 colour texture of its own, w x h, into *color; 0 when it is
 * not complete. As Blender's overlay engine and its viewport's resolve draw over its engines' depth. */
static GLuint over_scene_depth(GLuint scene_fbo, int depth_texture, int w, int h, GLenum target, GLuint *color)
{
    GLint scene_depth = 0;
    GLuint fbo = 0;
    glBindFramebuffer(GL_FRAMEBUFFER, scene_fbo);
    glGetFramebufferAttachmentParameteriv(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_FRAMEBUFFER_ATTACHMENT_OBJECT_NAME,
                                          &scene_depth);
    *color = rgba8_texture_of(target, w, h);
    glGenFramebuffers(1, &fbo);
    glBindFramebuffer(GL_FRAMEBUFFER, fbo);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, target, *color, 0);
    if (depth_texture) glFramebufferTexture2D(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_TEXTURE_2D, (GLuint)scene_depth, 0);
    else glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, (GLuint)scene_depth);
    const int complete = glCheckFramebufferStatus(GL_FRAMEBUFFER) == GL_FRAMEBUFFER_COMPLETE;
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    return complete ? fbo : 0;
}

/* The bound texture over the whole target (fixed function, identity matrices), its texture
 * coordinates 0..s across and 0..t up (a rectangle texture's are its texels'). */
static void target_quad(float s, float t)
{
    glBegin(GL_QUADS);
    glTexCoord2f(0, 0); glVertex2f(-1, -1);
    glTexCoord2f(s, 0); glVertex2f(1, -1);
    glTexCoord2f(s, t); glVertex2f(1, 1);
    glTexCoord2f(0, t); glVertex2f(-1, 1);
    glEnd();
}

static void full_target_quad(void)
{
    target_quad(1, 1);
}

/* --wire: a box's twelve edges and its top face, centred at WIRE_CENTRE with half size WIRE_HALF,
 * into `wire_fbo` (cleared transparent first) with the current camera; then `scene_fbo` is bound
 * again. (Blender's camera has a filled triangle on its wire frame so.) */
static const double WIRE_CENTRE[3] = {-1.0, -1.2, -3.5}, WIRE_HALF = 0.35;
static const GLubyte WIRE[3] = {250, 250, 120};

static void draw_wire_box(GLuint wire_fbo, GLuint scene_fbo)
{
    glBindFramebuffer(GL_FRAMEBUFFER, wire_fbo);
    glClearColor(0, 0, 0, 0);
    glClear(GL_COLOR_BUFFER_BIT);
    glEnable(GL_DEPTH_TEST);
    glLineWidth(3);
    glColor3ub(WIRE[0], WIRE[1], WIRE[2]);
    glBegin(GL_LINES);
    for (int axis = 0; axis < 3; axis++)  /* the four edges along each axis */
        for (int k = 0; k < 4; k++)
            for (int end = -1; end <= 1; end += 2) {
                double v[3];
                v[axis] = end * WIRE_HALF;
                v[(axis + 1) % 3] = (k & 1 ? 1 : -1) * WIRE_HALF;
                v[(axis + 2) % 3] = (k & 2 ? 1 : -1) * WIRE_HALF;
                glVertex3d(WIRE_CENTRE[0] + v[0], WIRE_CENTRE[1] + v[1], WIRE_CENTRE[2] + v[2]);
            }
    glEnd();
    glBegin(GL_QUADS);  /* the lid */
    glNormal3f(0, 1, 0);
    glVertex3d(WIRE_CENTRE[0] - WIRE_HALF, WIRE_CENTRE[1] + WIRE_HALF, WIRE_CENTRE[2] + WIRE_HALF);
    glVertex3d(WIRE_CENTRE[0] + WIRE_HALF, WIRE_CENTRE[1] + WIRE_HALF, WIRE_CENTRE[2] + WIRE_HALF);
    glVertex3d(WIRE_CENTRE[0] + WIRE_HALF, WIRE_CENTRE[1] + WIRE_HALF, WIRE_CENTRE[2] - WIRE_HALF);
    glVertex3d(WIRE_CENTRE[0] - WIRE_HALF, WIRE_CENTRE[1] + WIRE_HALF, WIRE_CENTRE[2] - WIRE_HALF);
    glEnd();
    glLineWidth(1);
    glClearColor(0, 0, 0, 1);
    glBindFramebuffer(GL_FRAMEBUFFER, scene_fbo);
}

/* --bbox: the box's edges, with the current camera (inside glBegin(GL_LINES) by the caller's program) */
static const double BBOX_LOW[3] = {-2.0, -1.9, -9.0}, BBOX_HIGH[3] = {2.0, 0.5, -5.5};
static const GLubyte BBOX[3] = {0, 255, 0};

static void draw_bbox(void)
{
    glLineWidth(2);
    glColor3ub(BBOX[0], BBOX[1], BBOX[2]);
    glBegin(GL_LINES);
    for (int axis = 0; axis < 3; axis++)  /* the four edges along each axis */
        for (int k = 0; k < 4; k++)
            for (int end = 0; end < 2; end++) {
                const int at[3] = {axis == 0 ? end : k & 1, axis == 1 ? end : axis == 0 ? k & 1 : k >> 1,
                                   axis == 2 ? end : k >> 1};
                glVertex3d(at[0] ? BBOX_HIGH[0] : BBOX_LOW[0], at[1] ? BBOX_HIGH[1] : BBOX_LOW[1],
                           at[2] ? BBOX_HIGH[2] : BBOX_LOW[2]);
            }
    glEnd();
    glLineWidth(1);
}

/* --hud: a panel at window pixels 20..120 x y0..y0 + 60 of 400x300 (scaled to width x height), the
 * depth test off, under an orthographic projection: fixed function, or the shader program with the
 * matrix in its uniform (and, --modelview, the identity in `modelview_location`) or (builtins) in
 * GL_PROJECTION */
/* --hud-vao: the HUD's vertex-array object (its vertex pointer set once) and buffer */
static GLuint hud_vao = 0, hud_vbo = 0;

static void draw_hud(GLuint program, GLint proj_location, GLint modelview_location, int builtins, int width, int height,
                     double y0, int depth)
{
    static const double identity[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
    const double ortho[16] = {2.0 / width, 0, 0, 0, 0, 2.0 / height, 0, 0, 0, 0, -1, 0, -1, -1, 0, 1};
    const double sx = width / 400.0, sy = height / 300.0;
    if (!depth) glDisable(GL_DEPTH_TEST);
    if (program) glUseProgram(program);
    if (program && !builtins) upload(proj_location, ortho);
    if (program && modelview_location >= 0) upload(modelview_location, identity);
    glMatrixMode(GL_PROJECTION);
    glLoadMatrixd(ortho);
    glMatrixMode(GL_MODELVIEW);
    glLoadIdentity();
    glColor3ub(230, 50, 40);
    if (hud_vao) {
        const GLfloat quad[8] = {(GLfloat)(20 * sx), (GLfloat)(y0 * sy), (GLfloat)(120 * sx), (GLfloat)(y0 * sy),
                                 (GLfloat)(120 * sx), (GLfloat)((y0 + 60) * sy), (GLfloat)(20 * sx), (GLfloat)((y0 + 60) * sy)};
        glBindVertexArray(hud_vao);
        glBindBuffer(GL_ARRAY_BUFFER, hud_vbo);
        glBufferData(GL_ARRAY_BUFFER, sizeof quad, quad, GL_STREAM_DRAW);
        glBindBuffer(GL_ARRAY_BUFFER, 0);
        glDrawArrays(GL_QUADS, 0, 4);
        glBindVertexArray(0);
    } else {
        glBegin(GL_QUADS);
        glVertex2d(20 * sx, y0 * sy); glVertex2d(120 * sx, y0 * sy);
        glVertex2d(120 * sx, (y0 + 60) * sy); glVertex2d(20 * sx, (y0 + 60) * sy);
        glEnd();
    }
    if (program) glUseProgram(0);
}

static int parse_vector(const char *text, double v[3])
{
    return text && sscanf(text, "%lf,%lf,%lf", &v[0], &v[1], &v[2]) == 3 && v[0] * v[0] + v[1] * v[1] + v[2] * v[2] > 0;
}

/* --mvp: the floor and each pillar under projection * view * model, one uniform per draw. The
 * view turns the world by 0 degrees (the pictures match the other modes) and is a rigid matrix
 * the stream never shows alone. */
/* S m S with S = diag(1, 1, -1, 1): a right-handed transform written in left-handed coordinates */
static void mirror_z(double *m)
{
    for (int col = 0; col < 4; col++)
        for (int row = 0; row < 4; row++)
            if ((col == 2) != (row == 2)) m[col * 4 + row] = -m[col * 4 + row];
}

static void draw_mvp(GLint location, const double *proj, double turn_deg, GLint modelview_location, int bbox, int left)
{
    /* glRotated(turn, 0, 1, 0) */
    const double t = turn_deg * M_PI / 180.0, ct = cos(t), st = sin(t);
    double view[16] = {ct, 0, -st, 0, 0, 1, 0, 0, st, 0, ct, 0, 0, 0, 0, 1};
    if (left) mirror_z(view);
    double pv[16], m[16], model[16];
    /* --modelview: the projection alone in `location`, view * model in `modelview_location` */
    const int split = modelview_location >= 0;
    if (split) upload(location, proj);
    mul(pv, split ? view : proj, split ? (const double[16]){1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1} : view);
    upload(split ? modelview_location : location, pv);
    glBegin(GL_QUADS);  /* the floor, modelled in place */
    glColor3ub(90, 90, 90);
    glNormal3f(0, 1, 0);
    glVertex3f(-50, -2, -50); glVertex3f(50, -2, -50); glVertex3f(50, -2, 50); glVertex3f(-50, -2, 50);
    glEnd();
    for (int k = 0; k < 12; k++) {
        const double yaw = k * 30.0 * M_PI / 180.0, c = cos(yaw), s = sin(yaw);
        /* rotate by -yaw about y (the pillar's face towards the viewer), then move it out to 6 units */
        const double place[16] = {c, 0, s, 0, 0, 1, 0, 0, -s, 0, c, 0, 6 * s, 0, -6 * c, 1};
        memcpy(model, place, sizeof place);
        if (left) mirror_z(model);  /* (the pillar's own vertices have z = 0) */
        mul(m, pv, model);
        upload(split ? modelview_location : location, m);
        glColor3ub((GLubyte)(40 + 16 * k), (GLubyte)(200 - 12 * k), (GLubyte)(255 - 20 * k));
        glNormal3d(-s, 0, c);  /* (the world's: --sun lights in the world's space) */
        glBegin(GL_QUADS);  /* the pillar at the origin, facing +z */
        glVertex3d(-0.6, -2, 0); glVertex3d(0.6, -2, 0); glVertex3d(0.6, 6, 0); glVertex3d(-0.6, 6, 0);
        glEnd();
    }
    if (bbox) {  /* modelled in place, as the floor */
        upload(split ? modelview_location : location, pv);
        draw_bbox();
    }
}

/* --markers: where each marker is (eye space) and its colour; tests/e2e/immersive_test.py knows them */
static const struct marker {
    double x, y, z;
    GLubyte r, g, b;
} MARKERS[] = {
    {0.0, 0.0, -2.5, 0, 0, 255},      /* straight ahead, 1 m behind a 3 m CAVE's front wall */
    {0.4, 0.3, -1.2, 255, 0, 0},      /* front, up and to the right */
    {-1.2, 0.2, -0.4, 255, 255, 0},   /* left */
    {1.2, -0.3, 0.5, 0, 255, 0},      /* right, behind the program's camera plane */
    {0.3, -1.2, -0.3, 255, 0, 255},   /* below, on a CAVE's floor */
};

/* The floor's quad, 100 x 100 at y = -2 (inside glBegin(GL_QUADS)). */
static void floor_vertices(double zs)
{
    glVertex3d(-50, -2, -50 * zs); glVertex3d(50, -2, -50 * zs); glVertex3d(50, -2, 50 * zs);
    glVertex3d(-50, -2, 50 * zs);
}

static void draw_markers(double zs)
{
    glPointSize(4);
    glBegin(GL_POINTS);
    for (size_t i = 0; i < sizeof MARKERS / sizeof MARKERS[0]; i++) {
        glColor3ub(MARKERS[i].r, MARKERS[i].g, MARKERS[i].b);
        glVertex3d(MARKERS[i].x, MARKERS[i].y, MARKERS[i].z * zs);
    }
    glEnd();
}

/* A GLSL program of a vertex and a fragment shader; 0 when it does not link */
static GLuint link_program(const char *vs, const char *fs)
{
    GLuint v = glCreateShader(GL_VERTEX_SHADER), fr = glCreateShader(GL_FRAGMENT_SHADER);
    glShaderSource(v, 1, &vs, NULL);
    glShaderSource(fr, 1, &fs, NULL);
    glCompileShader(v);
    glCompileShader(fr);
    GLuint program = glCreateProgram();
    glAttachShader(program, v);
    glAttachShader(program, fr);
    glLinkProgram(program);
    GLint linked = 0;
    glGetProgramiv(program, GL_LINK_STATUS, &linked);
    return linked ? program : 0;
}

/* A flat rectangle in window pixels x0..x1, y0..y1 under the orthographic projection of the window */
static void flat_rect(double x0, double y0, double x1, double y1, GLubyte r, GLubyte g, GLubyte b)
{
    glColor3ub(r, g, b);
    glBegin(GL_QUADS);
    glVertex2d(x0, y0); glVertex2d(x1, y0); glVertex2d(x1, y1); glVertex2d(x0, y1);
    glEnd();
}

/* --region: the scene (fw x fh, in fbo's texture `color`, resolved from msaa_fbo first if that is
 * not 0, copied into post_fbo's `post_color` first if that is not 0) shown at x rx..width, y 0..rh
 * of the window between a toolbar and a header, as a content suite composites its regions */
static void show_region(GLuint msaa_fbo, GLuint fbo, GLuint color, GLuint post_fbo, GLuint post_color, GLuint blit,
                        GLuint overlay_color, int by_blit, int fw, int fh, int width, int height, int rx, int rh,
                        int gizmo)
{
    if (msaa_fbo && !by_blit) {
        glBindFramebuffer(GL_READ_FRAMEBUFFER, msaa_fbo);
        glBindFramebuffer(GL_DRAW_FRAMEBUFFER, fbo);
        glBlitFramebuffer(0, 0, fw, fh, 0, 0, fw, fh, GL_COLOR_BUFFER_BIT, GL_NEAREST);
    }
    glUseProgram(0);
    glDisable(GL_DEPTH_TEST);
    glMatrixMode(GL_MODELVIEW);
    glLoadIdentity();
    glMatrixMode(GL_PROJECTION);
    glLoadIdentity();
    if (post_fbo) {  /* a full-target copy, depth untouched */
        glBindFramebuffer(GL_FRAMEBUFFER, post_fbo);
        glViewport(0, 0, fw, fh);
        glEnable(GL_TEXTURE_2D);
        glBindTexture(GL_TEXTURE_2D, color);
        glColor3ub(255, 255, 255);
        full_target_quad();
        glDisable(GL_TEXTURE_2D);
    }
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    glViewport(0, 0, width, height);
    glOrtho(0, width, 0, height, -1, 1);
    flat_rect(0, 0, rx, height, 60, 62, 70);  /* the toolbar */
    if (by_blit) {
        glBindFramebuffer(GL_READ_FRAMEBUFFER, msaa_fbo ? msaa_fbo : post_fbo ? post_fbo : fbo);
        glBlitFramebuffer(0, 0, fw, fh, rx, 0, width, rh, GL_COLOR_BUFFER_BIT, GL_NEAREST);
        glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
    } else {
    if (blit) glUseProgram(blit);
    else glEnable(GL_TEXTURE_2D);
    if (overlay_color) {  /* (--wire: the blit program mixes it over the scene) */
        glActiveTexture(GL_TEXTURE1);
        glBindTexture(GL_TEXTURE_2D, overlay_color);
        glActiveTexture(GL_TEXTURE0);
    }
    glBindTexture(GL_TEXTURE_2D, post_fbo ? post_color : color);
    glColor3ub(255, 255, 255);
    glBegin(GL_QUADS);
    glTexCoord2f(0, 0); glVertex2d(rx, 0);
    glTexCoord2f(1, 0); glVertex2d(width, 0);
    glTexCoord2f(1, 1); glVertex2d(width, rh);
    glTexCoord2f(0, 1); glVertex2d(rx, rh);
    glEnd();
    glUseProgram(0);
    glDisable(GL_TEXTURE_2D);
    }
    flat_rect(rx, rh, width, height, 45, 48, 55);  /* the header */
    const double sx = width / 400.0, sy = height / 300.0;
    if (gizmo) flat_rect(330 * sx, 190 * sy, 380 * sx, 240 * sy, 230, 50, 40);
}

int main(int argc, char **argv)
{
    struct app_args a;
    const int builtins = app_take_flag(&argc, &argv, "--builtins");
    const int mvp = app_take_flag(&argc, &argv, "--mvp");
    const int modelview = mvp && app_take_flag(&argc, &argv, "--modelview");
    const int grow = app_take_flag(&argc, &argv, "--grow");
    const int shader = app_take_flag(&argc, &argv, "--shader") || builtins || mvp;
    const int fbo_mode = app_take_flag(&argc, &argv, "--fbo");
    const int half = fbo_mode && app_take_flag(&argc, &argv, "--half");
    const int region = fbo_mode && !half && app_take_flag(&argc, &argv, "--region");
    const int by_blit = region && app_take_flag(&argc, &argv, "--blit");
    const int mrt = fbo_mode && app_take_flag(&argc, &argv, "--mrt");
    const int msaa = fbo_mode && app_take_flag(&argc, &argv, "--msaa");
    const int depth_texture = fbo_mode && app_take_flag(&argc, &argv, "--depth-texture");
    const int fragcoord = fbo_mode && !region && app_take_flag(&argc, &argv, "--fragcoord");
    const int gbuffer = fbo_mode && mvp && !region && !half && !msaa && app_take_flag(&argc, &argv, "--gbuffer");
    const int reversed = app_take_flag(&argc, &argv, "--reversed");
    const int hud = app_take_flag(&argc, &argv, "--hud");
    const int with_hud_vao = hud && !mvp && app_take_flag(&argc, &argv, "--hud-vao");
    const int hud_in_scene = hud && fbo_mode && app_take_flag(&argc, &argv, "--in-scene");
    const int hud_depth = hud_in_scene && app_take_flag(&argc, &argv, "--depth-on");
    const int hand = app_take_flag(&argc, &argv, "--hand");
    const int left_handed = app_take_flag(&argc, &argv, "--left-handed");
    const int mixed = builtins && app_take_flag(&argc, &argv, "--mixed");
    const int foliage = builtins && app_take_flag(&argc, &argv, "--foliage");
    const int post = fbo_mode && app_take_flag(&argc, &argv, "--post");
    const int grade = fbo_mode && app_take_flag(&argc, &argv, "--grade");
    const int markers = app_take_flag(&argc, &argv, "--markers");
    const int cull = app_take_flag(&argc, &argv, "--cull");
    const int overlay = app_take_flag(&argc, &argv, "--overlay");
    const int wire = fbo_mode && !shader && !(msaa && region) && !by_blit && !post && app_take_flag(&argc, &argv, "--wire");
    const int wire_rect = wire && !msaa && !region && app_take_flag(&argc, &argv, "--rect");
    const GLenum wire_target = wire_rect ? GL_TEXTURE_RECTANGLE : GL_TEXTURE_2D;
    const int mirror = fbo_mode && !shader && !msaa && !region && !post && !wire && !fragcoord && app_take_flag(&argc, &argv, "--mirror");
    const int mirror_columns = fbo_mode && !shader && !msaa && !region && !post && !wire && !fragcoord && !mirror &&
                               app_take_flag(&argc, &argv, "--mirror-columns");
    const int reflection = app_take_flag(&argc, &argv, "--reflection");
    const int bbox = (!shader || builtins || mvp) && app_take_flag(&argc, &argv, "--bbox");
    const int canopy = !shader && app_take_flag(&argc, &argv, "--canopy");
    const int blended = app_take_flag(&argc, &argv, "--blended");
    const int objects = shader && !builtins && !mvp && app_take_flag(&argc, &argv, "--objects");
    const int fisheye = shader && !builtins && !mvp && app_take_flag(&argc, &argv, "--fisheye");
    double fov = 60;
    if (argc > 2 && strcmp(argv[1], "--fov") == 0) {  /* (before --turn, as the usage lists them) */
        fov = atof(argv[2]);
        if (!(fov > 1 && fov < 179)) {
            fprintf(stderr, "pillars: --fov takes 1..179 degrees\n");
            return 2;
        }
        argv[2] = argv[0];
        argv += 2;
        argc -= 2;
    }
    const char *scale_text = take_value(&argc, &argv, "--scale");
    const double scale = scale_text ? atof(scale_text) : 1;
    if (!(scale > 0) || (scale_text && shader && !builtins)) {
        fprintf(stderr, "pillars: --scale takes a positive factor, for fixed function or --builtins\n");
        return 2;
    }
    const char *turn_text = take_value(&argc, &argv, "--turn");
    const double turn = turn_text ? atof(turn_text) : 0;
    const char *sun_text = take_value(&argc, &argv, "--sun");
    const char *gl_light_text = sun_text ? NULL : take_value(&argc, &argv, "--gl-light");
    double sun[3] = {0, 1, 0};
    if ((sun_text && !parse_vector(sun_text, sun)) || (gl_light_text && !parse_vector(gl_light_text, sun))) {
        fprintf(stderr, "pillars: --sun and --gl-light take X,Y,Z, not all 0\n");
        return 2;
    }
    if ((sun_text && !builtins && !mvp) || (gl_light_text && !builtins) || (turn_text && shader && !builtins && !mvp)) {
        fprintf(stderr, "pillars: --sun is for --builtins or --mvp, --gl-light for --builtins, --turn not for --shader\n");
        return 2;
    }
    const double zs = left_handed ? -1 : 1;  /* the world's z as the program keeps it */
    if (left_handed && (reversed || (mvp && (bbox || sun_text)))) {
        fprintf(stderr, "pillars: --left-handed is not for --reversed, nor for --mvp with --bbox or --sun\n");
        return 2;
    }
    if (region && (hud_in_scene || hand)) {
        fprintf(stderr, "pillars: --region has no --in-scene HUD or --hand\n");
        return 2;
    }
    if (hand && fbo_mode) {
        fprintf(stderr, "pillars: --hand draws into the window: not with --fbo\n");
        return 2;
    }
    app_parse_args("pillars", argc, argv, &a);
    Display *dpy = XOpenDisplay(NULL);
    if (!dpy) {
        fprintf(stderr, "pillars: cannot open display\n");
        return 1;
    }
    int attribs[] = {GLX_RGBA, GLX_DOUBLEBUFFER, GLX_RED_SIZE, 8, GLX_GREEN_SIZE, 8, GLX_BLUE_SIZE, 8, GLX_DEPTH_SIZE, 24, None};
    XVisualInfo *vi = glXChooseVisual(dpy, DefaultScreen(dpy), attribs);
    XSetWindowAttributes swa;
    swa.colormap = XCreateColormap(dpy, RootWindow(dpy, vi->screen), vi->visual, AllocNone);
    Window win = XCreateWindow(dpy, RootWindow(dpy, vi->screen), 0, 0, grow ? 32 : a.width, grow ? 32 : a.height, 0,
                               vi->depth, InputOutput, vi->visual, CWColormap, &swa);
    XMapWindow(dpy, win);
    GLXContext ctx = glXCreateContext(dpy, vi, NULL, True);
    glXMakeCurrent(dpy, win, ctx);
    if (grow) {
        glViewport(0, 0, a.width, a.height);
        XResizeWindow(dpy, win, a.width, a.height);
        XSync(dpy, False);
        usleep(150000);  /* past the shim's 100 ms between two looks at the window's size */
    }
    GLuint program = 0;
    GLint proj_location = -1, modelview_location = -1;
    GLuint ubo[2] = {0, 0};  /* --objects: the objects' block and the view's */
    if (shader) {
        const char *vs = sun_text && modelview
                             ? "#version 120\nuniform mat4 projection, modelView;\nuniform vec3 u_lightDirection;\n"
                               "void main() { float lit = 0.55 + 0.45 * abs(dot(mat3(modelView) * gl_Normal,"
                               " normalize(u_lightDirection)));"
                               " gl_FrontColor = vec4(gl_Color.rgb * lit, 1.0); gl_Position = projection * modelView * gl_Vertex; }\n"
                         : sun_text && mvp
                             ? "#version 120\nuniform mat4 mvp;\nuniform vec3 sun_direction;\n"
                               "void main() { float lit = 0.55 + 0.45 * abs(dot(gl_Normal, normalize(sun_direction)));"
                               " gl_FrontColor = vec4(gl_Color.rgb * lit, 1.0); gl_Position = mvp * gl_Vertex; }\n"
                         : sun_text ? "#version 120\nuniform vec3 sun_direction;\n"
                               "void main() { float lit = 0.55 + 0.45 * abs(dot(gl_Normal, normalize(sun_direction)));"
                               " gl_FrontColor = vec4(gl_Color.rgb * lit, 1.0);"
                               " gl_Position = gl_ModelViewProjectionMatrix * gl_Vertex; }\n"
                         : gl_light_text ? "#version 120\n"
                               "void main() { float lit = 0.55 + 0.45 * abs(dot(gl_NormalMatrix * gl_Normal,"
                               " normalize(gl_LightSource[0].position.xyz)));"
                               " gl_FrontColor = vec4(gl_Color.rgb * lit, 1.0);"
                               " gl_Position = gl_ModelViewProjectionMatrix * gl_Vertex; }\n"
                         : fisheye ? "#version 120\nuniform float aspect;\n"
                               "void main() { gl_FrontColor = gl_Color; vec3 e = gl_Vertex.xyz; float r = length(e);"
                               " float theta = acos(clamp(-e.z / r, -1.0, 1.0)), phi = atan(e.y, e.x);"
                               " float rho = theta / radians(60.0);"
                               " gl_Position = vec4(rho * cos(phi), rho * sin(phi) * aspect,"
                               " (r - 0.5) / 99.5 * 2.0 - 1.0, 1.0); }\n"
                         : foliage ? "#version 120\nvoid main() { gl_FrontColor = gl_Color; gl_TexCoord[0] = gl_MultiTexCoord0;"
                                   " gl_Position = gl_ModelViewProjectionMatrix * gl_Vertex; }\n"
                         : builtins ? "#version 120\n"
                                    "void main() { gl_FrontColor = gl_Color; gl_Position = gl_ModelViewProjectionMatrix * gl_Vertex; }\n"
                         : objects ? "#version 140\n#extension GL_ARB_compatibility : enable\n"
                                     "struct Object { mat4 model; mat4 model_inverse; };\n"
                                     "layout(std140) uniform view_block { mat4 winmat; };\n"
                                     "layout(std140) uniform objects_block { Object object[512]; };\n"
                                     "layout(std140) uniform LightingData { vec3 sun_direction; };\n"
                                     "void main() { gl_FrontColor = gl_Color;"
                                     " gl_Position = winmat * (object[0].model * gl_Vertex); }\n"
                         : mvp ? "#version 120\nuniform mat4 mvp;\n"
                                 "void main() { gl_FrontColor = gl_Color; gl_Position = mvp * gl_Vertex; }\n"
                               : "#version 120\nuniform mat4 proj;\n"
                                 "void main() { gl_FrontColor = gl_Color; gl_Position = proj * gl_Vertex; }\n";
        const char *fs = foliage ? "#version 120\nuniform sampler2D leaves;\n"
                                   "void main() { gl_FragColor = gl_Color * texture2D(leaves, gl_TexCoord[0].st); }\n"
                                 : "#version 120\nvoid main() { gl_FragColor = gl_Color; }\n";
        program = link_program(vs, fs);
        if (!program) {
            fprintf(stderr, "pillars: shader program does not link\n");
            return 1;
        }
        proj_location = glGetUniformLocation(program, modelview ? "projection" : mvp ? "mvp" : "proj");
        if (modelview) modelview_location = glGetUniformLocation(program, "modelView");
        if (objects) {  /* block bindings 1 (the objects) and 2 (the view) */
            glGenBuffers(2, ubo);
            GLfloat *block = calloc(512 * 32, sizeof(GLfloat));
            for (int i = 0; i < 4; i++) block[i * 5] = block[16 + i * 5] = 1;  /* object 0: the identity */
            glBindBuffer(GL_UNIFORM_BUFFER, ubo[0]);
            glBufferData(GL_UNIFORM_BUFFER, 512 * 32 * sizeof(GLfloat), block, GL_STATIC_DRAW);
            free(block);
            glBindBuffer(GL_UNIFORM_BUFFER, ubo[1]);
            glBufferData(GL_UNIFORM_BUFFER, 16 * sizeof(GLfloat), NULL, GL_DYNAMIC_DRAW);
            glBindBufferBase(GL_UNIFORM_BUFFER, 0, ubo[0]);  /* (what LightingData, left at 0, finds) */
            glBindBufferBase(GL_UNIFORM_BUFFER, 1, ubo[0]);
            glBindBufferBase(GL_UNIFORM_BUFFER, 2, ubo[1]);
            glUniformBlockBinding(program, glGetUniformBlockIndex(program, "objects_block"), 1);
            glUniformBlockBinding(program, glGetUniformBlockIndex(program, "view_block"), 2);
        }
        if (fisheye) {
            glUseProgram(program);
            glUniform1f(glGetUniformLocation(program, "aspect"), (GLfloat)a.width / (GLfloat)a.height);
            glUseProgram(0);
        }
        if (sun_text) {
            glUseProgram(program);
            glUniform3f(glGetUniformLocation(program, modelview ? "u_lightDirection" : "sun_direction"), (GLfloat)sun[0],
                        (GLfloat)sun[1], (GLfloat)sun[2]);
            glUseProgram(0);
        }
    }
    GLuint blit = 0;  /* --region with a shader program: the viewport shown by a GLSL texture blit */
    if (region && wire) {  /* ... or with --wire: the box's texture (unit 1) mixed over the scene's */
        const char *cvs = "#version 120\nvoid main() { gl_TexCoord[0] = gl_MultiTexCoord0;"
                          " gl_Position = gl_ModelViewProjectionMatrix * gl_Vertex; }\n";
        const char *cfs = "#version 120\nuniform sampler2D picture, overlay;\n"
                          "void main() { vec4 o = texture2D(overlay, gl_TexCoord[0].st);\n"
                          "  gl_FragColor = vec4(mix(texture2D(picture, gl_TexCoord[0].st).rgb, o.rgb, o.a), 1.0); }\n";
        blit = link_program(cvs, cfs);
        if (!blit) {
            fprintf(stderr, "pillars: the composite program does not link\n");
            return 1;
        }
        glUseProgram(blit);
        glUniform1i(glGetUniformLocation(blit, "overlay"), 1);
        glUseProgram(0);
    } else if (region && shader) {
        const char *bvs = "#version 120\nvoid main() { gl_TexCoord[0] = gl_MultiTexCoord0;"
                          " gl_Position = gl_ModelViewProjectionMatrix * gl_Vertex; }\n";
        const char *bfs = "#version 120\nuniform sampler2D picture;\n"
                          "void main() { gl_FragColor = texture2D(picture, gl_TexCoord[0].st); }\n";
        blit = link_program(bvs, bfs);
        if (!blit) {
            fprintf(stderr, "pillars: the blit program does not link\n");
            return 1;
        }
    }
    GLuint grade_program = 0;  /* --grade: a full-target pass whose vertex shader has no matrix */
    if (grade) {
        const char *gvs = "#version 130\nvoid main() { gl_Position = vec4(float((gl_VertexID & 1) * 4 - 1),"
                          " float((gl_VertexID & 2) * 2 - 1), 0.0, 1.0); }\n";
        const char *gfs = "#version 130\nvoid main() { gl_FragColor = vec4(0.5, 0.5, 0.5, 1.0); }\n";
        grade_program = link_program(gvs, gfs);
        if (!grade_program) {
            fprintf(stderr, "pillars: the grade program does not link\n");
            return 1;
        }
    }
    GLuint fragcoord_program = 0;  /* --fragcoord: the scene's texel where the fragment lands */
    GLint fragcoord_size = -1;
    if (fragcoord) {
        /* (with --objects its vertex shader declares the view's block, and reads none of it: as
         * SuperTuxKart's every shader declares its block of camera matrices) */
        const char *fvs = objects ? "#version 140\n#extension GL_ARB_compatibility : enable\n"
                                    "layout(std140) uniform view_block { mat4 winmat; };\n"
                                    "void main() { gl_Position = ftransform(); }\n"
                                  : "#version 120\nvoid main() { gl_Position = ftransform(); }\n";
        const char *ffs = "#version 120\nuniform sampler2D scene;\nuniform vec2 size;\n"
                          "void main() { gl_FragColor = texture2D(scene, gl_FragCoord.xy / size); }\n";
        fragcoord_program = link_program(fvs, ffs);
        if (!fragcoord_program) {
            fprintf(stderr, "pillars: the fragcoord program does not link\n");
            return 1;
        }
        fragcoord_size = glGetUniformLocation(fragcoord_program, "size");
        if (objects) glUniformBlockBinding(fragcoord_program, glGetUniformBlockIndex(fragcoord_program, "view_block"), 2);
    }
    GLuint gbuffer_program = 0, gbuffer_fbo = 0, gbuffer_color = 0;  /* --gbuffer: the first pass's target */
    GLint gbuffer_mvp = -1, gbuffer_size = -1;
    if (gbuffer) {
        const char *gvs = "#version 120\nuniform mat4 mvp;\nvoid main() { gl_Position = mvp * gl_Vertex; }\n";
        const char *gfs = "#version 120\nuniform sampler2D lit;\nuniform vec2 size;\n"
                          "void main() { gl_FragColor = texture2D(lit, gl_FragCoord.xy / size); }\n";
        gbuffer_program = link_program(gvs, gfs);
        if (!gbuffer_program) {
            fprintf(stderr, "pillars: the gbuffer program does not link\n");
            return 1;
        }
        gbuffer_mvp = glGetUniformLocation(gbuffer_program, "mvp");
        gbuffer_size = glGetUniformLocation(gbuffer_program, "size");
        if (!(gbuffer_fbo = colour_and_depth_target(a.width, a.height, &gbuffer_color))) {
            fprintf(stderr, "pillars: the gbuffer target is not complete\n");
            return 1;
        }
    }
    GLuint floor_vbo = 0;
    if (with_hud_vao) {
        const GLfloat floor[12] = {-50, -2, (GLfloat)(-50 * zs), 50, -2, (GLfloat)(-50 * zs),
                                   50, -2, (GLfloat)(50 * zs), -50, -2, (GLfloat)(50 * zs)};
        glGenBuffers(1, &floor_vbo);
        glBindBuffer(GL_ARRAY_BUFFER, floor_vbo);
        glBufferData(GL_ARRAY_BUFFER, sizeof floor, floor, GL_STATIC_DRAW);
        glGenBuffers(1, &hud_vbo);
        glGenVertexArrays(1, &hud_vao);
        glBindVertexArray(hud_vao);
        glBindBuffer(GL_ARRAY_BUFFER, hud_vbo);
        glBufferData(GL_ARRAY_BUFFER, 8 * sizeof(GLfloat), NULL, GL_STREAM_DRAW);
        glVertexPointer(2, GL_FLOAT, 0, NULL);
        glEnableClientState(GL_VERTEX_ARRAY);
        glBindVertexArray(0);
        glBindBuffer(GL_ARRAY_BUFFER, 0);
    }
    GLuint leaves = 0;
    if (foliage) {  /* opaque white, then transparent */
        const GLubyte texels[8] = {255, 255, 255, 255, 255, 255, 255, 0};
        glGenTextures(1, &leaves);
        glBindTexture(GL_TEXTURE_2D, leaves);
        glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, 2, 1, 0, GL_RGBA, GL_UNSIGNED_BYTE, texels);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    }
    GLuint fbo = 0, color = 0, msaa_fbo = 0, msaa_depth = 0;
    /* --region: the viewport's rectangle in the window */
    const int rx = a.width / 5, rw = a.width - rx, rh = a.height * 13 / 15;
    const int fw = half ? a.width / 2 : region ? rw : a.width, fh = half ? a.height / 2 : region ? rh : a.height;
    if (fbo_mode) {
        GLuint depth = 0;
        color = rgba8_texture(fw, fh);
        if (depth_texture) {
            glGenTextures(1, &depth);
            glBindTexture(GL_TEXTURE_2D, depth);
            glTexImage2D(GL_TEXTURE_2D, 0, GL_DEPTH_COMPONENT32F, fw, fh, 0, GL_DEPTH_COMPONENT, GL_FLOAT, NULL);
            glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
            glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
        } else {
            glGenRenderbuffers(1, &depth);
            glBindRenderbuffer(GL_RENDERBUFFER, depth);
            glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT24, fw, fh);
        }
        glGenFramebuffers(1, &fbo);
        glBindFramebuffer(GL_FRAMEBUFFER, fbo);
        glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, color, 0);
        if (depth_texture) glFramebufferTexture2D(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_TEXTURE_2D, depth, 0);
        else glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, depth);
        if (mrt) {  /* a second target the scene writes too */
            const GLuint second = rgba8_texture(fw, fh);
            glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT1, GL_TEXTURE_2D, second, 0);
            const GLenum both[2] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1};
            glDrawBuffers(2, both);
        }
        if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) {
            fprintf(stderr, "pillars: the scene's framebuffer object is not complete\n");
            return 1;
        }
        if (msaa) {  /* the scene drawn here, resolved into fbo's texture */
            GLuint rb[2];
            glGenRenderbuffers(2, rb);
            glBindRenderbuffer(GL_RENDERBUFFER, rb[0]);
            glRenderbufferStorageMultisample(GL_RENDERBUFFER, 4, GL_RGBA8, fw, fh);
            glBindRenderbuffer(GL_RENDERBUFFER, rb[1]);
            glRenderbufferStorageMultisample(GL_RENDERBUFFER, 4, GL_DEPTH_COMPONENT24, fw, fh);
            glGenFramebuffers(1, &msaa_fbo);
            glBindFramebuffer(GL_FRAMEBUFFER, msaa_fbo);
            glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, rb[0]);
            glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, rb[1]);
            msaa_depth = rb[1];
            if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) {
                fprintf(stderr, "pillars: the multisampled framebuffer object is not complete\n");
                return 1;
            }
        }
        glBindFramebuffer(GL_FRAMEBUFFER, 0);
    }
    GLuint overlay_fbo = 0;  /* --overlay --fbo: the scene's colour, no depth */
    if (overlay && fbo_mode && !msaa) {
        glGenFramebuffers(1, &overlay_fbo);
        glBindFramebuffer(GL_FRAMEBUFFER, overlay_fbo);
        glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, color, 0);
        if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) {
            fprintf(stderr, "pillars: the overlay's framebuffer object is not complete\n");
            return 1;
        }
        glBindFramebuffer(GL_FRAMEBUFFER, 0);
    }
    GLuint wire_fbo = 0, wire_color = 0;  /* --wire: a colour of its own, the scene's depth */
    GLuint wire_resolve_fbo = 0;          /* --wire --msaa: wire_color, resolved from wire_fbo's */
    if (wire && msaa) {
        GLuint wire_samples = 0;
        glGenTextures(1, &wire_samples);
        glBindTexture(GL_TEXTURE_2D_MULTISAMPLE, wire_samples);
        glTexImage2DMultisample(GL_TEXTURE_2D_MULTISAMPLE, 4, GL_RGBA8, fw, fh, GL_TRUE);
        glBindTexture(GL_TEXTURE_2D_MULTISAMPLE, 0);
        glGenFramebuffers(1, &wire_fbo);
        glBindFramebuffer(GL_FRAMEBUFFER, wire_fbo);
        glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D_MULTISAMPLE, wire_samples, 0);
        glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, msaa_depth);
        const int complete = glCheckFramebufferStatus(GL_FRAMEBUFFER) == GL_FRAMEBUFFER_COMPLETE;
        wire_resolve_fbo = colour_and_depth_target(fw, fh, &wire_color);
        glBindFramebuffer(GL_FRAMEBUFFER, 0);
        if (!complete || !wire_resolve_fbo) wire_fbo = 0;
    } else if (wire) {
        wire_fbo = over_scene_depth(fbo, depth_texture, fw, fh, wire_target, &wire_color);
    }
    if (wire && !wire_fbo) {
        fprintf(stderr, "pillars: the wire frame's framebuffer object is not complete\n");
        return 1;
    }
    GLuint post_fbo = 0, post_color = 0;
    if (post && region) {  /* the region's size, the scene's depth */
        post_fbo = over_scene_depth(fbo, depth_texture, fw, fh, GL_TEXTURE_2D, &post_color);
    } else if (post) {
        post_fbo = colour_and_depth_target(a.width, a.height, &post_color);
    }
    for (int f = 0; f < a.frames; f++) {
        if (wire) (void)glGetError();  /* (a program that checks its errors each frame) */
        if (fbo_mode) {
            glBindFramebuffer(GL_FRAMEBUFFER, msaa ? msaa_fbo : fbo);
            glViewport(0, 0, fw, fh);
        } else if (!grow) {
            glViewport(0, 0, a.width, a.height);
        }
        glClearColor(0, 0, 0, 1);
        if (reversed) {
            glClipControl(GL_LOWER_LEFT, GL_ZERO_TO_ONE);
            glClearDepth(0.0);
            glDepthFunc(GL_GREATER);
        }
        glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
        if (blended) {
            glEnable(GL_BLEND);
            glBlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
        }
        glEnable(GL_DEPTH_TEST);
        glMatrixMode(GL_PROJECTION);
        glLoadIdentity();
        const double n = 0.5, half = n * tan(fov / 2 * M_PI / 180.0);
        const double top = region ? half * fh / fw : half * a.height / a.width;
        /* the matrix, column-major, for GL_PROJECTION and the uniforms */
        const double fa = 100.0;
        const double standard[16] = {n / half, 0, 0, 0, 0, n / top, 0, 0, 0, 0, -(fa + n) / (fa - n), -1,
                                     0, 0, -2 * fa * n / (fa - n), 0};
        const double reverse_infinite[16] = {n / half, 0, 0, 0, 0, n / top, 0, 0, 0, 0, 0, -1, 0, 0, n, 0};
        double left[16];
        for (int i = 0; i < 16; i++) left[i] = i >= 8 && i < 12 ? -standard[i] : standard[i];
        const double *proj = reversed ? reverse_infinite : left_handed ? left : standard;
        if (reversed || left_handed) glLoadMatrixd(proj);
        else if (mirror) glFrustum(-half * scale, half * scale, top * scale, -top * scale, n * scale, fa * scale);
        else if (mirror_columns) glFrustum(half * scale, -half * scale, -top * scale, top * scale, n * scale, fa * scale);
        else glFrustum(-half * scale, half * scale, -top * scale, top * scale, n * scale, fa * scale);
        if (shader && !mixed) glUseProgram(program);
        if (shader && !builtins && !mvp) {
            GLfloat m[16];
            for (int i = 0; i < 16; i++) m[i] = (GLfloat)proj[i];
            if (objects) {  /* each frame, as engines do (SuperTuxKart) */
                glBindBuffer(GL_UNIFORM_BUFFER, ubo[1]);
                glBufferSubData(GL_UNIFORM_BUFFER, 0, sizeof m, m);
                glBindBufferBase(GL_UNIFORM_BUFFER, 1, ubo[0]);  /* (which binds GL_UNIFORM_BUFFER to it too) */
            }
            else glUniformMatrix4fv(proj_location, 1, GL_FALSE, m);
        }
        glMatrixMode(GL_MODELVIEW);
        glLoadIdentity();
        if (scale_text) glScaled(scale, scale, scale);
        if (turn_text && !mvp) glRotated(turn, 0, 1, 0);
        if (gl_light_text) {  /* in the world's space: GL keeps it in the eye's, through the view */
            const GLfloat position[4] = {(GLfloat)sun[0], (GLfloat)sun[1], (GLfloat)sun[2], 0};
            glLightfv(GL_LIGHT0, GL_POSITION, position);
        }
        if (mvp && gbuffer) {
            glBindFramebuffer(GL_FRAMEBUFFER, gbuffer_fbo);
            glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
            draw_mvp(proj_location, proj, turn, modelview_location, bbox, left_handed);
            glBindFramebuffer(GL_FRAMEBUFFER, fbo);
            glUseProgram(gbuffer_program);
            glBindTexture(GL_TEXTURE_2D, gbuffer_color);
            glUniform2f(gbuffer_size, (GLfloat)a.width, (GLfloat)a.height);
            draw_mvp(gbuffer_mvp, proj, turn, -1, 0, left_handed);
            glBindTexture(GL_TEXTURE_2D, 0);
            glUseProgram(program);
        } else if (mvp) {
            draw_mvp(proj_location, proj, turn, modelview_location, bbox, left_handed);
        } else {
            if (foliage) {
                glBindTexture(GL_TEXTURE_2D, leaves);
                glEnable(GL_ALPHA_TEST);
                glAlphaFunc(GL_GREATER, 0.5f);
            }
            if (floor_vbo) {  /* --hud-vao: from a buffer, with the vertex-array object 0 bound */
                glColor3ub(90, 90, 90);
                glNormal3f(0, 1, 0);
                glBindBuffer(GL_ARRAY_BUFFER, floor_vbo);
                glVertexPointer(3, GL_FLOAT, 0, NULL);
                glEnableClientState(GL_VERTEX_ARRAY);
                glDrawArrays(GL_QUADS, 0, 4);
                glDisableClientState(GL_VERTEX_ARRAY);
                glBindBuffer(GL_ARRAY_BUFFER, 0);
            } else {
                glBegin(GL_QUADS);  /* the floor */
                glColor3ub(90, 90, 90);
                glNormal3f(0, 1, 0);
                glTexCoord2f(0.25f, 0.5f);  /* (--foliage: the opaque texel) */
                floor_vertices(zs);
                glEnd();
            }
            if (reflection) {
                glDisable(GL_DEPTH_TEST);
                glBegin(GL_QUADS);
                glColor3ub(60, 90, 200);
                floor_vertices(zs);
                glEnd();
                glEnable(GL_DEPTH_TEST);
                glDepthFunc(GL_LEQUAL);
                glBegin(GL_QUADS);
                glColor3ub(90, 90, 90);
                floor_vertices(zs);
                glEnd();
                glDepthFunc(GL_LESS);
            }
            if (mixed) glUseProgram(program);
            if (overlay) glDisable(GL_DEPTH_TEST);
            if (overlay_fbo) glBindFramebuffer(GL_FRAMEBUFFER, overlay_fbo);
            for (int k = 0; k < 12; k++) {
                const double yaw = k * 30.0 * M_PI / 180.0, x = 6 * sin(yaw), z = -6 * cos(yaw), w = 0.6;
                /* --cull: outside the field of view by more than the pillar's half width (0.6 at 6) */
                const double off = fabs(remainder(k * 30.0, 360.0)) - fov / 2;
                if (cull && off > atan(0.6 / 6) * 180 / M_PI) continue;
                const double tx = cos(yaw) * w, tz = sin(yaw) * w;  /* across the line of sight */
                glColor3ub((GLubyte)(40 + 16 * k), (GLubyte)(200 - 12 * k), (GLubyte)(255 - 20 * k));
                glNormal3d(-sin(yaw), 0, cos(yaw) * zs);  /* towards the viewer */
                glBegin(GL_QUADS);
                glTexCoord2f(0, 0.5f); glVertex3d(x - tx, -2, (z - tz) * zs);
                glTexCoord2f(1, 0.5f); glVertex3d(x + tx, -2, (z + tz) * zs);
                glTexCoord2f(1, 0.5f); glVertex3d(x + tx, 6, (z + tz) * zs);
                glTexCoord2f(0, 0.5f); glVertex3d(x - tx, 6, (z - tz) * zs);
                glEnd();
            }
            if (foliage) glDisable(GL_ALPHA_TEST);
            if (overlay_fbo) glBindFramebuffer(GL_FRAMEBUFFER, fbo);
            if (overlay) glEnable(GL_DEPTH_TEST);
        }
        if (wire) draw_wire_box(wire_fbo, msaa ? msaa_fbo : fbo);
        if (bbox && !mvp) draw_bbox();
        if (canopy) {  /* a translucent sheet over everything, drawn last, writing depth */
            glEnable(GL_BLEND);
            glBlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
            glColor4ub(255, 255, 255, 60);
            glBegin(GL_QUADS);
            glVertex3d(-50, 8, 50); glVertex3d(50, 8, 50); glVertex3d(50, 8, -50); glVertex3d(-50, 8, -50);
            glEnd();
            glDisable(GL_BLEND);
        }
        if (markers) {
            if (mvp) upload(proj_location, proj);  /* the view is the identity: the points as modelled */
            else if (shader && mixed) glUseProgram(program);
            draw_markers(zs);
        }
        if (grade) {  /* the scene's colour halved, in its target, as an engine's colour grade is */
            glUseProgram(grade_program);
            glDisable(GL_DEPTH_TEST);
            glDepthMask(GL_FALSE);
            glEnable(GL_BLEND);
            glBlendFunc(GL_DST_COLOR, GL_ZERO);
            glDrawArrays(GL_TRIANGLES, 0, 3);
            glDisable(GL_BLEND);
            glDepthMask(GL_TRUE);
            glEnable(GL_DEPTH_TEST);
            glUseProgram(0);
        }
        if (hud_in_scene) draw_hud(shader ? program : 0, proj_location, modelview_location, builtins, fw, fh, 40, hud_depth);
        if (region) {
            show_region(msaa ? msaa_fbo : 0, fbo, color, post_fbo, post_color, blit, wire_color, by_blit, fw, fh,
                        a.width, a.height, rx, rh, hud);
        } else if (fbo_mode) {  /* the scene shown in the window, as a last post-processing pass does */
            if (msaa) {
                glBindFramebuffer(GL_READ_FRAMEBUFFER, msaa_fbo);
                glBindFramebuffer(GL_DRAW_FRAMEBUFFER, fbo);
                glBlitFramebuffer(0, 0, fw, fh, 0, 0, fw, fh, GL_COLOR_BUFFER_BIT, GL_NEAREST);
            }
            glViewport(0, 0, a.width, a.height);
            if (shader) glUseProgram(0);
            glDisable(GL_DEPTH_TEST);
            glMatrixMode(GL_PROJECTION);
            glLoadIdentity();
            glMatrixMode(GL_MODELVIEW);
            glLoadIdentity();
            glEnable(GL_TEXTURE_2D);
            glColor3ub(255, 255, 255);
            /* (--post: first into the post-processing target, then that into the window) */
            for (int step = post ? 0 : 1; step < 2; step++) {
                glBindFramebuffer(GL_FRAMEBUFFER, step == 0 ? post_fbo : 0);
                if (post && step == 1) {
                    glEnable(GL_DEPTH_TEST);
                    glDepthFunc(GL_ALWAYS);
                    glDepthMask(GL_TRUE);
                }
                glBindTexture(GL_TEXTURE_2D, post && step == 1 ? post_color : color);
                if (fragcoord) {
                    glUseProgram(fragcoord_program);
                    glUniform2f(fragcoord_size, (GLfloat)a.width, (GLfloat)a.height);
                    full_target_quad();
                    glUseProgram(0);
                } else if (mirror) {  /* (the scene upside down in its target: shown mirrored) */
                    glBindFramebuffer(GL_READ_FRAMEBUFFER, fbo);
                    glBlitFramebuffer(0, 0, fw, fh, 0, a.height, a.width, 0, GL_COLOR_BUFFER_BIT, GL_NEAREST);
                    glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
                } else if (mirror_columns) {
                    glBindFramebuffer(GL_READ_FRAMEBUFFER, fbo);
                    glBlitFramebuffer(0, 0, fw, fh, a.width, 0, 0, a.height, GL_COLOR_BUFFER_BIT, GL_NEAREST);
                    glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
                } else {
                    full_target_quad();
                }
            }
            if (wire) {
                if (wire_resolve_fbo) {
                    glBindFramebuffer(GL_READ_FRAMEBUFFER, wire_fbo);
                    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, wire_resolve_fbo);
                    glBlitFramebuffer(0, 0, fw, fh, 0, 0, fw, fh, GL_COLOR_BUFFER_BIT, GL_NEAREST);
                    glBindFramebuffer(GL_FRAMEBUFFER, 0);
                }
                glDisable(GL_TEXTURE_2D);
                glEnable(wire_target);
                glBindTexture(wire_target, wire_color);
                glEnable(GL_BLEND);
                glBlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
                if (wire_rect) target_quad((float)fw, (float)fh);
                else full_target_quad();
                glDisable(GL_BLEND);
                glDisable(wire_target);
                glEnable(GL_TEXTURE_2D);
            }
            glDisable(GL_TEXTURE_2D);
            if (post) {
                glDepthFunc(GL_LESS);
                glDisable(GL_DEPTH_TEST);
            }
        }
        if (hand) {
            glClear(GL_DEPTH_BUFFER_BIT);
            glMatrixMode(GL_PROJECTION);
            glLoadIdentity();
            const double hx = 0.4, hy = hx * a.height / a.width;  /* 77 degrees across, not the scene's 60 */
            glFrustum(-hx, hx, -hy, hy, 0.5, 10);
            glMatrixMode(GL_MODELVIEW);
            glLoadIdentity();
            /* window fraction u maps to x = (2u - 1) hx / 0.5 at z = -1 */
            const double x0 = (2 * 0.69 - 1) * hx * 2, x1 = (2 * 0.94 - 1) * hx * 2;
            const double y0 = (2 * 0.67 - 1) * hy * 2, y1 = (2 * 0.92 - 1) * hy * 2;
            glColor3ub(200, 180, 150);
            glBegin(GL_QUADS);
            glVertex3d(x0, y0, -1); glVertex3d(x1, y0, -1); glVertex3d(x1, y1, -1); glVertex3d(x0, y1, -1);
            glEnd();
        }
        if (fisheye) glUseProgram(0);  /* (its HUD by fixed function) */
        if (hud && !hud_in_scene && !region) draw_hud(shader && !fisheye ? program : 0, proj_location, modelview_location, builtins, a.width, a.height, 220, 0);
        glXSwapBuffers(dpy, win);
        if (glGetError() != GL_NO_ERROR) {
            fprintf(stderr, "pillars: GL error\n");
            return 1;
        }
    }
    glXMakeCurrent(dpy, None, NULL);
    glXDestroyContext(dpy, ctx);
    XCloseDisplay(dpy);
    return 0;
}
