/* The renderer (render/tb_render.h): an OSMesa context on Mesa's softpipe
 * rasterizer (GALLIUM_DRIVER=softpipe is set before the context is made:
 * llvmpipe's code generation and threads are not needed and softpipe's
 * single-threaded rasterization is reproducible), fixed-function OpenGL
 * 1.1 with vertex arrays, one directional light at the camera with
 * two-sided lighting, supersampling by an integer factor averaged down to
 * the image, and libpng for the file. */
#include <GL/gl.h>
#include <GL/osmesa.h>
#include <math.h>
#include <png.h>
#include <setjmp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "render_priv.h"

tb_renderer *tb_renderer_new(int w, int h, int ss, tb_error *err) {
  if (w < 8 || h < 8 || w > 8192 || h > 8192)
    return tb_error_set(err, "render", 0, "image size %dx%d: each side must be 8..8192", w, h),
           NULL;
  if (ss < 1 || ss > 4)
    return tb_error_set(err, "render", 0, "supersampling %d: must be 1..4", ss), NULL;
  tb_renderer *r = calloc(1, sizeof *r);
  if (!r) return tb_error_set(err, "render", 0, "out of memory"), NULL;
  r->w = w, r->h = h, r->ss = ss;
  r->buf = calloc((size_t)w * ss * h * ss, 4);
  r->image = malloc((size_t)w * h * 3);
  setenv("GALLIUM_DRIVER", "softpipe", 1);
  r->ctx = r->buf && r->image ? OSMesaCreateContextExt(OSMESA_RGBA, 24, 0, 0, NULL) : NULL;
  if (!r->ctx || !OSMesaMakeCurrent(r->ctx, r->buf, GL_UNSIGNED_BYTE, w * ss, h * ss)) {
    tb_renderer_free(r);
    return tb_error_set(err, "render", 0, "cannot make an OSMesa context (libosmesa6)"), NULL;
  }
  if (tb_text_open(&r->text, err)) {
    tb_renderer_free(r);
    return NULL;
  }
  return r;
}

void tb_renderer_free(tb_renderer *r) {
  if (!r) return;
  if (r->ctx) OSMesaDestroyContext(r->ctx);
  tb_text_close(&r->text);
  free(r->buf), free(r->image), free(r->vx), free(r->vn), free(r->vc);
  free(r);
}

/* ---- camera ---- */

static void look_at(const tb_camera *c) {
  tb_vec3 f = tb_normalize(tb_sub(c->target, c->eye));
  tb_vec3 s = tb_normalize(tb_cross(f, c->up)), u = tb_cross(s, f);
  GLdouble m[16] = {s.x, u.x, -f.x, 0, s.y, u.y, -f.y, 0, s.z, u.z, -f.z, 0, 0, 0, 0, 1};
  glMultMatrixd(m);
  glTranslated(-c->eye.x, -c->eye.y, -c->eye.z);
}

void tb_renderer_begin(tb_renderer *r, const tb_camera *cam, const float bg[3]) {
  r->nlabels = 0;
  OSMesaMakeCurrent(r->ctx, r->buf, GL_UNSIGNED_BYTE, r->w * r->ss, r->h * r->ss);
  glViewport(0, 0, r->w * r->ss, r->h * r->ss);
  glClearColor(bg[0], bg[1], bg[2], 1);
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  glEnable(GL_DEPTH_TEST);
  double aspect = (double)r->w / r->h, dist = tb_dist(cam->eye, cam->target);
  double nearz = 1e-3 * dist, farz = 1e3 * dist;
  glMatrixMode(GL_PROJECTION);
  glLoadIdentity();
  if (cam->half_height > 0) {
    double hh = cam->half_height;
    glOrtho(-hh * aspect, hh * aspect, -hh, hh, -farz, farz);
  } else {
    double t = nearz * tan(0.5 * cam->fov_deg * M_PI / 180);
    glFrustum(-t * aspect, t * aspect, -t, t, nearz, farz);
  }
  glMatrixMode(GL_MODELVIEW);
  glLoadIdentity();
  /* the light at the camera, fixed in eye space */
  GLfloat pos[4] = {0.3f, 0.5f, 1, 0}, white[4] = {0.85f, 0.85f, 0.85f, 1};
  GLfloat amb[4] = {0.25f, 0.25f, 0.25f, 1};
  glLightfv(GL_LIGHT0, GL_POSITION, pos);
  glLightfv(GL_LIGHT0, GL_DIFFUSE, white);
  glLightModelfv(GL_LIGHT_MODEL_AMBIENT, amb);
  glLightModeli(GL_LIGHT_MODEL_TWO_SIDE, GL_TRUE);
  look_at(cam);
}

/* ---- meshes ---- */

static int reserve(tb_renderer *r, int n) {
  if (n <= r->cap) return 0;
  GLfloat *a = realloc(r->vx, sizeof(GLfloat) * 3 * (size_t)n);
  if (a) r->vx = a;
  GLfloat *b = realloc(r->vn, sizeof(GLfloat) * 3 * (size_t)n);
  if (b) r->vn = b;
  GLfloat *c = realloc(r->vc, sizeof(GLfloat) * 4 * (size_t)n);
  if (c) r->vc = c;
  if (!a || !b || !c) return -1;
  r->cap = n;
  return 0;
}

void tb_renderer_mesh(tb_renderer *r, const tb_render_mesh *m) {
  if (m->nv < 1 || m->ntri < 1 || reserve(r, m->nv)) return;
  /* area-weighted vertex normals */
  memset(r->vn, 0, sizeof(GLfloat) * 3 * (size_t)m->nv);
  for (int k = 0; k < m->ntri; k++) {
    const int *v = m->tri + 3 * k;
    tb_vec3 n = tb_cross(tb_sub(m->x[v[1]], m->x[v[0]]), tb_sub(m->x[v[2]], m->x[v[0]]));
    for (int c = 0; c < 3; c++) {
      r->vn[3 * v[c]] += (GLfloat)n.x, r->vn[3 * v[c] + 1] += (GLfloat)n.y;
      r->vn[3 * v[c] + 2] += (GLfloat)n.z;
    }
  }
  double span = m->hi > m->lo ? m->hi - m->lo : 1;
  for (int i = 0; i < m->nv; i++) {
    r->vx[3 * i] = (GLfloat)m->x[i].x, r->vx[3 * i + 1] = (GLfloat)m->x[i].y;
    r->vx[3 * i + 2] = (GLfloat)m->x[i].z;
    float rgb[3] = {m->rgb[0], m->rgb[1], m->rgb[2]};
    if (m->value) tb_colormap((m->value[i] - m->lo) / span, rgb);
    r->vc[4 * i] = rgb[0], r->vc[4 * i + 1] = rgb[1], r->vc[4 * i + 2] = rgb[2],
              r->vc[4 * i + 3] = 1;
  }
  GLfloat back[4] = {0.45f, 0.5f, 0.65f, 1}, spec[4] = {0.15f, 0.15f, 0.15f, 1};
  glEnable(GL_LIGHTING);
  glEnable(GL_LIGHT0);
  glEnable(GL_NORMALIZE);
  glDisable(GL_COLOR_MATERIAL); /* the face it tracks is set while it is off */
  glColorMaterial(m->any_side ? GL_FRONT_AND_BACK : GL_FRONT, GL_AMBIENT_AND_DIFFUSE);
  glEnable(GL_COLOR_MATERIAL);
  if (!m->any_side) glMaterialfv(GL_BACK, GL_AMBIENT_AND_DIFFUSE, back);
  glMaterialfv(GL_FRONT_AND_BACK, GL_SPECULAR, spec);
  glMaterialf(GL_FRONT_AND_BACK, GL_SHININESS, 24);
  glEnableClientState(GL_VERTEX_ARRAY);
  glEnableClientState(GL_NORMAL_ARRAY);
  glEnableClientState(GL_COLOR_ARRAY);
  glVertexPointer(3, GL_FLOAT, 0, r->vx);
  glNormalPointer(GL_FLOAT, 0, r->vn);
  glColorPointer(4, GL_FLOAT, 0, r->vc);
  if (m->wireframe || m->on_top) {
    glEnable(GL_POLYGON_OFFSET_FILL);
    glPolygonOffset(m->on_top ? -2 : 1, m->on_top ? -2 : 1);
  }
  if (m->flat) {
    glDisableClientState(GL_NORMAL_ARRAY);
    glBegin(GL_TRIANGLES);
    for (int k = 0; k < m->ntri; k++) {
      const int *v = m->tri + 3 * k;
      tb_vec3 n = tb_cross(tb_sub(m->x[v[1]], m->x[v[0]]), tb_sub(m->x[v[2]], m->x[v[0]]));
      glNormal3d(n.x, n.y, n.z);
      for (int c = 0; c < 3; c++) glArrayElement(v[c]);
    }
    glEnd();
  } else
    glDrawElements(GL_TRIANGLES, 3 * m->ntri, GL_UNSIGNED_INT, m->tri);
  glDisable(GL_POLYGON_OFFSET_FILL);
  glDisableClientState(GL_NORMAL_ARRAY);
  glDisableClientState(GL_COLOR_ARRAY);
  glDisable(GL_LIGHTING);
  if (m->wireframe) {
    glColor3f(0.1f, 0.1f, 0.12f);
    glLineWidth((GLfloat)r->ss);
    glPolygonMode(GL_FRONT_AND_BACK, GL_LINE);
    glDrawElements(GL_TRIANGLES, 3 * m->ntri, GL_UNSIGNED_INT, m->tri);
    glPolygonMode(GL_FRONT_AND_BACK, GL_FILL);
  }
  glDisableClientState(GL_VERTEX_ARRAY);
}

void tb_renderer_lines(tb_renderer *r, int n, const tb_vec3 *ends, const float rgb[3],
                       float width) {
  glDisable(GL_LIGHTING);
  glColor3f(rgb[0], rgb[1], rgb[2]);
  glLineWidth(width * (GLfloat)r->ss);
  glBegin(GL_LINES);
  for (int k = 0; k < 2 * n; k++) glVertex3d(ends[k].x, ends[k].y, ends[k].z);
  glEnd();
}

void tb_renderer_points(tb_renderer *r, int n, const tb_vec3 *x, const float *rgb, float size) {
  glDisable(GL_LIGHTING);
  glPointSize(size * (GLfloat)r->ss);
  glBegin(GL_POINTS);
  for (int k = 0; k < n; k++) {
    glColor3f(rgb[3 * k], rgb[3 * k + 1], rgb[3 * k + 2]);
    glVertex3d(x[k].x, x[k].y, x[k].z);
  }
  glEnd();
}

void tb_renderer_ground(tb_renderer *r, tb_vec3 p, tb_vec3 n, tb_vec3 c, double half) {
  (void)r;
  n = tb_normalize(n);
  tb_vec3 a = fabs(n.x) < 0.9 ? tb_v3(1, 0, 0) : tb_v3(0, 1, 0);
  tb_vec3 u = tb_normalize(tb_cross(n, a)), w = tb_cross(n, u);
  c = tb_madd(c, -tb_dot(tb_sub(c, p), n), n);
  /* a checkerboard of 8 x 8 squares, lit, slightly below the plane so contact shows */
  c = tb_madd(c, -1e-4 * half, n);
  glEnable(GL_LIGHTING);
  glEnable(GL_LIGHT0);
  glEnable(GL_COLOR_MATERIAL);
  glColorMaterial(GL_FRONT_AND_BACK, GL_AMBIENT_AND_DIFFUSE);
  glBegin(GL_QUADS);
  glNormal3d(n.x, n.y, n.z);
  for (int i = 0; i < 8; i++)
    for (int j = 0; j < 8; j++) {
      float g = (i + j) % 2 ? 0.78f : 0.68f;
      glColor3f(g, g, g * 0.95f);
      double s0 = -half + i * half / 4, s1 = s0 + half / 4, t0 = -half + j * half / 4,
             t1 = t0 + half / 4;
      tb_vec3 q[4] = {tb_add(c, tb_add(tb_scale(u, s0), tb_scale(w, t0))),
                      tb_add(c, tb_add(tb_scale(u, s1), tb_scale(w, t0))),
                      tb_add(c, tb_add(tb_scale(u, s1), tb_scale(w, t1))),
                      tb_add(c, tb_add(tb_scale(u, s0), tb_scale(w, t1)))};
      for (int k = 0; k < 4; k++) glVertex3d(q[k].x, q[k].y, q[k].z);
    }
  glEnd();
  glDisable(GL_LIGHTING);
}

/* ---- the colour map and its bar ---- */

void tb_palette(int k, float rgb[3]) {
  /* Kelly's colours of maximum contrast (1965) without white and black */
  static const unsigned hex[20] = {0xF3C300, 0x875692, 0xF38400, 0xA1CAF1, 0xBE0032,
                                   0xC2B280, 0x848482, 0x008856, 0xE68FAC, 0x0067A5,
                                   0xF99379, 0x604E97, 0xF6A600, 0xB3446C, 0xDCD300,
                                   0x882D17, 0x8DB600, 0x654522, 0xE25822, 0x2B3D26};
  unsigned c = hex[(k % 20 + 20) % 20];
  for (int j = 0; j < 3; j++) rgb[j] = (float)((c >> (16 - 8 * j)) & 0xFF) / 255.0f;
}

void tb_colormap(double u, float rgb[3]) {
  /* nine stops from dark violet through blue and green to yellow (our
   * approximation of a perceptually ordered map) */
  static const float stop[9][3] = {
      {0.27f, 0.00f, 0.33f}, {0.28f, 0.17f, 0.48f}, {0.23f, 0.32f, 0.55f},
      {0.17f, 0.45f, 0.56f}, {0.13f, 0.57f, 0.55f}, {0.15f, 0.68f, 0.50f},
      {0.37f, 0.79f, 0.38f}, {0.68f, 0.86f, 0.19f}, {0.99f, 0.91f, 0.14f}};
  if (!(u > 0)) u = 0;
  if (u > 1) u = 1;
  double p = u * 8;
  int k = (int)p < 8 ? (int)p : 7;
  float f = (float)(p - k);
  for (int c = 0; c < 3; c++) rgb[c] = stop[k][c] + f * (stop[k + 1][c] - stop[k][c]);
}

static const float ink[3] = {0.1f, 0.1f, 0.1f}; /* labels' colour */

/* Flat drawing over the picture in pixels of the supersampled buffer (W x H), origin lower left:
 * no depth test, no lighting; overlay_end restores the camera's state. */
static void overlay_begin(int W, int H) {
  glMatrixMode(GL_PROJECTION);
  glPushMatrix();
  glLoadIdentity();
  glOrtho(0, W, 0, H, -1, 1);
  glMatrixMode(GL_MODELVIEW);
  glPushMatrix();
  glLoadIdentity();
  glDisable(GL_DEPTH_TEST);
  glDisable(GL_LIGHTING);
}

static void overlay_end(void) {
  glEnable(GL_DEPTH_TEST);
  glMatrixMode(GL_PROJECTION);
  glPopMatrix();
  glMatrixMode(GL_MODELVIEW);
  glPopMatrix();
}

void tb_renderer_colorbar(tb_renderer *r, double lo, double hi, const char *label) {
  int W = r->w * r->ss, H = r->h * r->ss;
  overlay_begin(W, H);
  double x0 = 0.91, x1 = 0.94, y0 = 0.2, y1 = 0.8;
  glBegin(GL_QUAD_STRIP);
  for (int k = 0; k <= 32; k++) {
    float rgb[3];
    tb_colormap(k / 32.0, rgb);
    glColor3f(rgb[0], rgb[1], rgb[2]);
    double y = (y0 + (y1 - y0) * k / 32) * H;
    glVertex2d(x0 * W, y), glVertex2d(x1 * W, y);
  }
  glEnd();
  overlay_end();
  /* numbers right-aligned against the bar, the label above it ending at its right edge */
  double size = 0.03;
  char text[32];
  snprintf(text, sizeof text, "%.3g", hi);
  tb_renderer_text(r, x0 - 0.01, y1 - 0.35 * size, size, 1, ink, text);
  snprintf(text, sizeof text, "%.3g", lo);
  tb_renderer_text(r, x0 - 0.01, y0 - 0.35 * size, size, 1, ink, text);
  if (label) tb_renderer_text(r, x1, y1 + 0.8 * size, size, 1, ink, label);
}

void tb_renderer_legend(tb_renderer *r, double y, int n, const char *const *labels,
                        const float (*rgb)[3]) {
  int W = r->w * r->ss, H = r->h * r->ss;
  double size = 0.03, step = 1.5 * size;
  overlay_begin(W, H);
  glBegin(GL_QUADS);
  for (int k = 0; k < n; k++) {
    double y0 = (y - k * step) * H, x0 = 0.02 * W, e = 0.8 * size * H;
    glColor3f(rgb[k][0], rgb[k][1], rgb[k][2]);
    glVertex2d(x0, y0), glVertex2d(x0 + e, y0), glVertex2d(x0 + e, y0 + e), glVertex2d(x0, y0 + e);
  }
  glEnd();
  overlay_end();
  for (int k = 0; k < n; k++)
    tb_renderer_text(r, 0.02 + 1.2 * size * H / W, y - k * step, size, -1, ink, labels[k]);
}

/* ---- the image ---- */

const unsigned char *tb_renderer_pixels(tb_renderer *r, int *w, int *h) {
  tb_text_draw(r);
  int ss = r->ss, W = r->w * ss;
  for (int y = 0; y < r->h; y++)
    for (int x = 0; x < r->w; x++)
      for (int c = 0; c < 3; c++) {
        unsigned sum = 0;
        for (int j = 0; j < ss; j++)
          for (int i = 0; i < ss; i++)
            sum += r->buf[4 * ((size_t)(y * ss + j) * W + x * ss + i) + c];
        /* GL's first row is the bottom */
        r->image[3 * ((size_t)(r->h - 1 - y) * r->w + x) + c] =
            (unsigned char)((sum + ss * ss / 2) / (ss * ss));
      }
  *w = r->w, *h = r->h;
  return r->image;
}

int tb_renderer_write_png(tb_renderer *r, const char *path, tb_error *err) {
  int w, h;
  const unsigned char *px = tb_renderer_pixels(r, &w, &h);
  FILE *f = fopen(path, "wb");
  if (!f) return tb_error_set(err, path, 0, "cannot write the file");
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, NULL, NULL, NULL);
  png_infop info = png ? png_create_info_struct(png) : NULL;
  if (!png || !info || setjmp(png_jmpbuf(png))) {
    png_destroy_write_struct(&png, &info);
    fclose(f);
    return tb_error_set(err, path, 0, "PNG encoding failed");
  }
  png_init_io(png, f);
  png_set_IHDR(png, info, (png_uint_32)w, (png_uint_32)h, 8, PNG_COLOR_TYPE_RGB, PNG_INTERLACE_NONE,
               PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  png_write_info(png, info);
  for (int y = 0; y < h; y++) png_write_row(png, (png_const_bytep)(px + 3 * (size_t)y * w));
  png_write_end(png, NULL);
  png_destroy_write_struct(&png, &info);
  if (fclose(f)) return tb_error_set(err, path, 0, "cannot write the file");
  return 0;
}
