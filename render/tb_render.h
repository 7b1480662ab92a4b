/* A headless renderer for pictures of meshes and simulations: OSMesa
 * (Mesa's off-screen OpenGL, fixed to its softpipe rasterizer so the same
 * input gives the same pixels on every machine) draws into memory, libpng
 * writes the file. Shaded surfaces with per-vertex normals, one light,
 * back faces in their own colour; per-vertex colour maps with a colour
 * bar; wireframes and line sets (springs, tet edges); a ground square;
 * text in DejaVu Sans by FreeType (labels, legends, the colour bar's
 * numbers). No display needed. */
#ifndef TB_RENDER_H
#define TB_RENDER_H

#include "core/tb_error.h"
#include "core/tb_math.h"

/* A camera: perspective (fov_deg > 0) or orthographic (half_height > 0,
 * half the view's height in scene units). */
typedef struct tb_camera {
  tb_vec3 eye, target, up;
  double fov_deg;
  double half_height;
} tb_camera;

/* The thesis's views of a body with bounding box [lo, hi] and the given up
 * direction: front (for z up from -y, for y up from +z), left-front,
 * left-back, top (from above), at the nearest distance where the box
 * fills 90% of the height or the width of a view of that aspect
 * (width / height). Returns -1 for an unknown name or a zero up. */
int tb_camera_preset_up(const char *name, tb_vec3 lo, tb_vec3 hi, tb_vec3 up, double aspect,
                        tb_camera *out);
/* The same view fitted to n points (a body's surface: the tightest fit), aimed at the middle of
 * their extent across the view. */
int tb_camera_preset_points(const char *name, const tb_vec3 *x, int n, tb_vec3 up, double aspect,
                            tb_camera *out);
/* The same with z up and aspect 4:3. */
int tb_camera_preset(const char *name, tb_vec3 lo, tb_vec3 hi, tb_camera *out);
/* "eye=x,y,z target=x,y,z [up=x,y,z] (fov=DEG | ortho=HALF_HEIGHT)",
 * fields separated by spaces or ';'. Errors name the field. */
int tb_camera_parse(const char *spec, tb_camera *out, tb_error *err);

/* A triangle mesh to draw: a flat colour, or a colour map of per-vertex
 * values over [lo, hi]; back faces grey-blue. */
typedef struct tb_render_mesh {
  int nv, ntri;
  const tb_vec3 *x;
  const int *tri;
  float rgb[3];
  const double *value; /* nv values, or NULL */
  double lo, hi;
  int wireframe; /* 1: the triangles' edges drawn over the surface */
  int on_top;    /* 1: drawn over coincident surfaces (highlighted triangles) */
  int any_side;  /* 1: back faces in the front colour (triangles of mixed orientation) */
  int flat;      /* 1: one normal per triangle (no smoothing across unrelated faces) */
} tb_render_mesh;

typedef struct tb_renderer tb_renderer;

/* An image of w x h pixels, drawn at ss x ss samples a pixel (1..4). */
tb_renderer *tb_renderer_new(int w, int h, int ss, tb_error *err);
void tb_renderer_free(tb_renderer *r);
/* Clears to the background colour and sets the camera. */
void tb_renderer_begin(tb_renderer *r, const tb_camera *cam, const float bg[3]);
void tb_renderer_mesh(tb_renderer *r, const tb_render_mesh *m);
/* n segments (2n points), one colour, width in pixels. */
void tb_renderer_lines(tb_renderer *r, int n, const tb_vec3 *ends, const float rgb[3], float width);
/* n points of size pixels, each its own colour (rgb: 3 per point). */
void tb_renderer_points(tb_renderer *r, int n, const tb_vec3 *x, const float *rgb, float size);
/* A square of side 2 * half on the plane (point p, normal n), centred at
 * the projection of c. */
void tb_renderer_ground(tb_renderer *r, tb_vec3 p, tb_vec3 n, tb_vec3 c, double half);
/* The colour bar of the colour map on the right, with lo, hi and a label
 * (the quantity and its unit) above it. */
void tb_renderer_colorbar(tb_renderer *r, double lo, double hi, const char *label);
/* Text s with its baseline at (x, y), fractions of the image's width and
 * height from the lower left; size: the font's height as a fraction of the
 * image's height; align -1 left, 0 centred, 1 right of x. Drawn over
 * the whole picture (when its pixels are read); at most 64 a picture. */
void tb_renderer_text(tb_renderer *r, double x, double y, double size, int align, const float rgb[3],
                      const char *s);
/* A legend at the upper left: n coloured squares, each with its label,
 * the first with its baseline at height y (a fraction of the image's). */
void tb_renderer_legend(tb_renderer *r, double y, int n, const char *const *labels,
                        const float (*rgb)[3]);
/* A qualitative palette for categories (clusters, pieces): colour k of 20
 * well-separated ones (Kelly 1965), repeating. */
void tb_palette(int k, float rgb[3]);
/* The colour map (viridis-like) at u in [0, 1]. */
void tb_colormap(double u, float rgb[3]);
/* Writes the image as an 8-bit RGB PNG (no time stamp: same pixels, same
 * bytes). */
int tb_renderer_write_png(tb_renderer *r, const char *path, tb_error *err);
/* The image's RGB bytes, w * h * 3, top row first (valid until the next
 * call). */
const unsigned char *tb_renderer_pixels(tb_renderer *r, int *w, int *h);

#endif
