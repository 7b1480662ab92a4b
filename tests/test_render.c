/* The headless renderer (render/): a sphere's silhouette from an
 * orthographic camera has the area of its disc, the corners stay
 * background, the same input gives the same PNG bytes, no display is
 * needed, and bad cameras, sizes and times are refused with exit 2. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "tb_test.h"
#include "meshgen/tb_meshgen.h"
#include "render/tb_render.h"

/* The silhouette of a unit sphere (10242-vertex geodesic) seen along -z by
 * an orthographic camera of half height 1.25 on a 400 x 400 image: a disc
 * of radius 160 pixels. */
static void sphere_area(void) {
  tb_mesh m;
  tb_error err;
  if (tb_geosphere(10242, 1.0, &m, &err)) {
    TB_CHECK_MSG(0, "%s", err.msg);
    return;
  }
  tb_renderer *r = tb_renderer_new(400, 400, 1, &err);
  TB_CHECK_MSG(r != NULL, "%s", err.msg);
  if (!r) {
    tb_mesh_free(&m);
    return;
  }
  tb_camera cam;
  TB_CHECK(tb_camera_parse("eye=0,0,5 target=0,0,0 up=0,1,0 ortho=1.25", &cam, &err) == 0);
  static const float white[3] = {1, 1, 1};
  tb_renderer_begin(r, &cam, white);
  tb_render_mesh rm = {
      .nv = m.nv, .ntri = m.ntri, .x = m.x, .tri = m.tri, .rgb = {0.8f, 0.3f, 0.3f}};
  tb_renderer_mesh(r, &rm);
  int w, h;
  const unsigned char *px = tb_renderer_pixels(r, &w, &h);
  long inside = 0;
  for (long k = 0; k < (long)w * h; k++)
    inside += !(px[3 * k] == 255 && px[3 * k + 1] == 255 && px[3 * k + 2] == 255);
  double disc = M_PI * 160.0 * 160.0;
  TB_CHECK_MSG(fabs(inside - disc) <= 0.01 * disc, "silhouette %ld pixels, disc %.0f", inside,
               disc);
  int corners[4][2] = {{0, 0}, {w - 1, 0}, {0, h - 1}, {w - 1, h - 1}};
  for (int c = 0; c < 4; c++) {
    const unsigned char *p = px + 3 * ((size_t)corners[c][1] * w + corners[c][0]);
    TB_CHECK(p[0] == 255 && p[1] == 255 && p[2] == 255);
  }
  /* the centre is lit, not black or white */
  const unsigned char *c = px + 3 * ((size_t)200 * w + 200);
  TB_CHECK_MSG(c[0] > 60 && c[0] < 255 && c[0] > c[2], "centre %d %d %d", c[0], c[1], c[2]);
  tb_renderer_free(r);
  tb_mesh_free(&m);
}

static long file_bytes(const char *path, unsigned char **out) {
  FILE *f = fopen(path, "rb");
  if (!f) return -1;
  fseek(f, 0, SEEK_END);
  long n = ftell(f);
  fseek(f, 0, SEEK_SET);
  *out = malloc((size_t)(n > 0 ? n : 0) + 1); /* NUL-terminated for text */
  if (!*out || fread(*out, 1, (size_t)n, f) != (size_t)n) n = -1;
  if (*out && n >= 0) (*out)[n] = 0;
  fclose(f);
  return n;
}

/* The same scene twice, without a display: the same bytes. */
static void deterministic(void) {
  char args[1200], a[700], b[700];
  for (int k = 0; k < 2; k++) {
    snprintf(args, sizeof args,
             "render --scene liver-press --model fem --set nodes=300 --set duration=0.3 --times "
             "0.3 --color displacement --wireframe --size 320x240 --out %s/det%d",
             tb_test_tmpdir(), k);
    char cmd[1400];
    snprintf(cmd, sizeof cmd, "env -u DISPLAY -u WAYLAND_DISPLAY %s %s", tb_test_cli(), args);
    int rc = tb_test_run(cmd, tb_test_out, sizeof tb_test_out);
    TB_CHECK_MSG(rc == 0, "%s", tb_test_out);
  }
  snprintf(a, sizeof a, "%s/det0/t0.300.png", tb_test_tmpdir());
  snprintf(b, sizeof b, "%s/det1/t0.300.png", tb_test_tmpdir());
  unsigned char *x = NULL, *y = NULL;
  long nx = file_bytes(a, &x), ny = file_bytes(b, &y);
  TB_CHECK_MSG(nx > 1000 && nx == ny && !memcmp(x, y, (size_t)nx), "%ld vs %ld bytes", nx, ny);
  TB_CHECK(nx > 8 && !memcmp(x, "\x89PNG", 4));
  free(x), free(y);
  /* the overlays: shape matching's clusters, the triangles crossing the instrument */
  snprintf(args, sizeof args,
           "render --scene liver-press --model sm --set nodes=300 --set duration=0.5 --structure "
           "--contacts --size 160x120 --out %s/ov",
           tb_test_tmpdir());
  TB_CHECK_MSG(tb_test_cli_run(args) == 0 && strstr(tb_test_out, "/ov/t0.500.png"), "%s",
               tb_test_out);
  /* the error against the reference: T4 locking leaves about half the tip deflection out */
  snprintf(args, sizeof args,
           "render --scene beam --model fem --set quasistatic=1 --times 0.5 --color error --size "
           "160x120 --out %s/err",
           tb_test_tmpdir());
  double worst = 0;
  const char *e = NULL;
  TB_CHECK_MSG(tb_test_cli_run(args) == 0 && (e = strstr(tb_test_out, "(error: largest ")) &&
                   sscanf(e + 16, "%lf", &worst) == 1 && worst > 0.3 && worst < 0.7,
               "largest error %g: %s", worst, tb_test_out);
  /* a stress map where the model has one */
  snprintf(args, sizeof args,
           "render --scene beam --model fem --color von_mises --size 160x120 --out %s/vm",
           tb_test_tmpdir());
  TB_CHECK_MSG(tb_test_cli_run(args) == 0 && strstr(tb_test_out, "/vm/t2.000.png"), "%s",
               tb_test_out);
}

static void bad_input(void) {
  static const struct {
    const char *args, *what;
  } cases[] = {
      {"render --scene beam --model fem --camera 'eye=0,0,1' --out %s/b", "target"},
      {"render --scene beam --model fem --camera 'eye=0,0,1 target=0,0,1' --out %s/b", "coincide"},
      {"render --scene beam --model fem --camera 'eye=0,0,5 target=0,0,0 fov=200' --out %s/b",
       "fov"},
      {"render --scene beam --model fem --camera 'eye=0,0,5 target=0,0,0 up=0,0,1' --out %s/b",
       "parallel"},
      {"render --scene beam --model fem --view side --out %s/b", "unknown view"},
      {"render --scene beam --model fem --times 1,0.5 --out %s/b", "--times"},
      {"render --scene beam --model fem --times -1 --out %s/b", "--times"},
      {"render --scene beam --model fem --size 5x5 --out %s/b", "--size"},
      {"render --scene beam --model fem --color heat --out %s/b", "--color"},
      {"render --mesh %s/none.obj --out x.png", "none.obj"},
      {"render --scene beam --model sm --color von_mises --out %s/b", "no stress"},
      {"render --scene liver-press --model fem --color error --out %s/b", "beam and liver-stretch"},
      {"render --scene beam --model fem --up 0,0,0 --out %s/b", "--up"},
      {"render --scene beam --model fem --up 1,x,0 --out %s/b", "--up"},
      {"render --scene beam --model fem --color displacement --range 1,1 --out %s/b", "--range"},
      {"render --scene beam --model fem --color displacement --range 0 --out %s/b", "--range"},
      {"render --scene beam --model fem --color displacement --range 0,inf --out %s/b", "--range"},
  };
  for (size_t k = 0; k < sizeof cases / sizeof cases[0]; k++) {
    char args[800];
    snprintf(args, sizeof args, cases[k].args, tb_test_tmpdir());
    int rc = tb_test_cli_run(args);
    TB_CHECK_MSG(rc == 2 && strstr(tb_test_out, cases[k].what), "%s: exit %d: %s", args, rc,
                 tb_test_out);
  }
}

/* The figures suite: every picture it lists exists and is a PNG; the
 * report shows them. */
static void figures_suite(void) {
  char args[800], path[900];
  snprintf(args, sizeof args, "reproduce --only figures --results %s/figs", tb_test_tmpdir());
  int rc = tb_test_cli_run(args);
  TB_CHECK_MSG(rc == 0, "%s", tb_test_out);
  snprintf(path, sizeof path, "%s/figs/figures/table.md", tb_test_tmpdir());
  unsigned char *md = NULL;
  long n = file_bytes(path, &md);
  TB_CHECK_MSG(n > 0, "no %s", path);
  int pictures = 0;
  for (const char *p = md ? strstr((char *)md, "](fig-") : NULL; p && p < (char *)md + n;
       p = strstr(p + 1, "](fig-")) {
    char name[200];
    if (sscanf(p + 2, "%199[^)]", name) != 1) break;
    snprintf(path, sizeof path, "%s/figs/figures/%s", tb_test_tmpdir(), name);
    unsigned char *png = NULL;
    long k = file_bytes(path, &png);
    TB_CHECK_MSG(k > 1000 && !memcmp(png, "\x89PNG", 4), "%s", path);
    free(png);
    pictures++;
  }
  free(md);
  TB_CHECK_MSG(pictures >= 20, "%d pictures", pictures);
  snprintf(path, sizeof path, "%s/figs/REPORT.md", tb_test_tmpdir());
  n = file_bytes(path, &md);
  TB_CHECK(n > 0 && md && strstr((char *)md, "](figures/fig-4.21-row-2.png)"));
  /* the PBD patent's fig. 9: the liver below the floor it fell through */
  const char *f9 = md ? strstr((char *)md, "PBD patent fig. 9:") : NULL;
  TB_CHECK_MSG(f9 && strstr(f9, "below the ground plane (drawn; ground = 0") &&
                   strstr((char *)md, "](figures/fig-pbd-9.png)"),
               "fig. 9 missing or above the ground");
  free(md);
}

/* The thesis's views fit the body: an elongated ellipsoid's silhouette spans at least 70% of the
 * picture's width or height (90% is aimed at; perspective makes oblique views smaller) and
 * touches no border, for z up and for y up. */
static void views_fit_the_body(void) {
  tb_mesh m;
  tb_error err;
  TB_CHECK(tb_geosphere(642, 1.0, &m, &err) == 0);
  static const char *const views[] = {"front", "left-front", "left-back", "top"};
  static const tb_vec3 ups[2] = {{0, 0, 1}, {0, 1, 0}};
  tb_renderer *r = tb_renderer_new(200, 150, 1, &err);
  for (int i = 0; i < m.nv; i++) m.x[i].x *= 3;
  for (int u = 0; r && u < 2; u++) {
    for (int v = 0; v < 4; v++) {
      tb_camera cam;
      TB_CHECK(tb_camera_preset_points(views[v], m.x, m.nv, ups[u], 200.0 / 150, &cam) == 0);
      static const float white[3] = {1, 1, 1};
      tb_renderer_begin(r, &cam, white);
      tb_render_mesh rm = {
          .nv = m.nv, .ntri = m.ntri, .x = m.x, .tri = m.tri, .rgb = {0.8f, 0.3f, 0.3f}};
      tb_renderer_mesh(r, &rm);
      int w, h, x0 = 1 << 20, x1 = -1, y0 = 1 << 20, y1 = -1;
      const unsigned char *px = tb_renderer_pixels(r, &w, &h);
      for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++) {
          const unsigned char *p = px + 3 * ((size_t)y * w + x);
          if (p[0] == 255 && p[1] == 255 && p[2] == 255) continue;
          x0 = x < x0 ? x : x0, x1 = x > x1 ? x : x1, y0 = y < y0 ? y : y0, y1 = y > y1 ? y : y1;
        }
      double fw = (x1 - x0 + 1.0) / w, fh = (y1 - y0 + 1.0) / h;
      TB_CHECK_MSG((fw >= 0.7 || fh >= 0.7) && x0 > 0 && y0 > 0 && x1 < w - 1 && y1 < h - 1,
                   "%s, up %d: the body spans %.2f x %.2f of the picture", views[v], u, fw, fh);
    }
  }
  tb_renderer_free(r);
  tb_mesh_free(&m);
}

/* A scene's pictures: the colour range shared by its frames (robust: the largest value 3 points
 * reach; at least 1e-9 of the body's size), the up direction from the scene's gravity (--up
 * overrides). */
static void scene_pictures(void) {
  char args[1200];
  snprintf(args, sizeof args,
           "render --scene liver-press --model fem --set nodes=300 --color displacement --times "
           "0,0.3 --size 160x120 --out %s/shared",
           tb_test_tmpdir());
  TB_CHECK_MSG(tb_test_cli_run(args) == 0, "%s", tb_test_out);
  const char *a = strstr(tb_test_out, "t0.000.png"), *b = strstr(tb_test_out, "t0.300.png");
  double top0 = 0, top1 = 1, big0 = 1, big1 = 0;
  TB_CHECK_MSG(
      a && b &&
          sscanf(strstr(a, "largest"), "largest %lf, colour range 0 to %lf", &big0, &top0) == 2 &&
          sscanf(strstr(b, "largest"), "largest %lf, colour range 0 to %lf", &big1, &top1) == 2,
      "%s", tb_test_out);
  TB_CHECK_MSG(top0 == top1 && big0 < 1e-9 && big1 > 0 && top1 <= big1 && top1 > 0.1 * big1,
               "ranges %g and %g, largest %g and %g", top0, top1, big0, big1);
  /* y up from the scene's gravity: the same picture as --up 0,1,0, not as z up */
  const char *sofa =
      "[scene]\nduration = 0.02\ngravity_direction = 0,-1,0\ngravity = 9.81\n"
      "[mesh]\ngenerate = beam\n[fix]\nbox = -1,-1,-1, 0.01,9,9\n";
  const char *path = tb_test_file("yup.ini", sofa, -1);
  static const char *const up[3] = {"", "--up 0,1,0", "--up 0,0,1"};
  unsigned char *png[3] = {NULL, NULL, NULL};
  long n[3];
  for (int k = 0; k < 3; k++) {
    snprintf(args, sizeof args, "render --scene %s --model fem %s --size 160x120 --out %s/up%d",
             path, up[k], tb_test_tmpdir(), k);
    TB_CHECK_MSG(tb_test_cli_run(args) == 0, "%s", tb_test_out);
    char f[900];
    snprintf(f, sizeof f, "%s/up%d/t0.020.png", tb_test_tmpdir(), k);
    n[k] = file_bytes(f, &png[k]);
  }
  TB_CHECK(n[0] > 0 && n[0] == n[1] && !memcmp(png[0], png[1], (size_t)n[0]));
  TB_CHECK(n[2] > 0 && (n[2] != n[0] || memcmp(png[0], png[2], (size_t)n[0])));
  for (int k = 0; k < 3; k++) free(png[k]);
}

const tb_test_case tb_tests_render[] = {
    {"views_fit_the_body", views_fit_the_body},
    {"scene_pictures", scene_pictures},
    {"figures_suite", figures_suite},
    {"sphere_area", sphere_area},
    {"deterministic", deterministic},
    {"bad_input", bad_input},
    {NULL, NULL},
};
