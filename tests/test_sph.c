/* Tests for sphere sets (core/tb_spheres.h: SOFA's .sph files), the packing
 * of a closed surface from inner Voronoi poles and its coverage
 * (meshgen/tb_sphpack.h), and `tissuebench mesh spheres`; SOFA's liver.sph
 * when ../shared/data is present. */
#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "tb_test.h"
#include "core/tb_mesh_io.h"
#include "core/tb_spheres.h"
#include "meshgen/tb_meshgen.h"
#include "meshgen/tb_sphpack.h"

/* ---- .sph files ---- */
static void round_trip(void) {
  tb_spheres s = {0, NULL, NULL, -1}, t;
  tb_error err;
  const double v[] = {0.1, 1.0 / 3, -2.5e-300, 1e88, 4.9e-324, -0.0, 123456789.123456789};
  for (int i = 0; i < 40; i++) {
    tb_vec3 c = tb_v3(v[i % 7], v[(i + 2) % 7] * (i + 1), v[(i + 5) % 7] / 7);
    double r = fabs(v[(i + 3) % 7]) + 1e-3 * i + DBL_MIN;
    TB_CHECK(tb_spheres_push(&s, c, r) == 0);
  }
  char path[600];
  snprintf(path, sizeof path, "%s/round.sph", tb_test_tmpdir());
  TB_CHECK_MSG(tb_spheres_write(path, &s, &err) == 0, "%s", err.msg);
  TB_CHECK_MSG(tb_spheres_read(path, &t, &err) == 0, "%s", err.msg);
  TB_CHECK(t.n == s.n && t.declared == s.n);
  if (t.n == s.n) {
    TB_CHECK(memcmp(t.c, s.c, (size_t)s.n * sizeof *s.c) == 0);
    TB_CHECK(memcmp(t.r, s.r, (size_t)s.n * sizeof *s.r) == 0);
  }
  tb_spheres_free(&t);
  tb_spheres_free(&s);
  s.n = 0;
  TB_CHECK(tb_spheres_write(path, &s, &err) != 0); /* nothing to write */
}

static void sofa_liver(void) {
  char path[600];
  snprintf(path, sizeof path, "%s/../shared/data/sofa/liver.sph", tb_test_source_root());
  FILE *f = fopen(path, "rb");
  if (!f) {
    tb_test_skip("%s absent (../shared/data not present)", path);
    return;
  }
  fclose(f);
  tb_spheres s;
  tb_error err;
  TB_CHECK_MSG(tb_spheres_read(path, &s, &err) == 0, "%s", err.msg);
  TB_CHECK_MSG(s.n == 34 && s.declared == 27, "n %d, #nums %d", s.n, s.declared);
  if (s.n == 34) {
    TB_CHECK(s.c[0].x == -4 && s.c[0].y == 1.25 && s.c[0].z == 0 && s.r[0] == 0.85);
    for (int i = 0; i < s.n; i++) TB_CHECK(s.r[i] > 0 && tb_isfinite3(s.c[i]));
  }
  tb_spheres_free(&s);
}

/* CRLF, comments anywhere, no "#nums": declared stays -1. */
static void comments(void) {
  const char *p = tb_test_file("ok.sph",
                               "# made by hand\r\n\r\nsph 1.0 # version\r\n#nums x\r\n"
                               "sphe 7 1 2 3 0.5   # a comment\r\n\tsphe -1 1e-3 -2 3.5 1e2\r\n",
                               -1);
  tb_spheres s;
  tb_error err;
  TB_CHECK_MSG(tb_spheres_read(p, &s, &err) == 0, "%s", err.msg);
  TB_CHECK(s.n == 2 && s.declared == -1);
  if (s.n == 2) TB_CHECK(s.c[1].x == 1e-3 && s.c[1].z == 3.5 && s.r[1] == 100);
  tb_spheres_free(&s);
}

static void expect_error(const char *name, const char *content, long len, long line,
                         const char *reason) {
  const char *p = tb_test_file(name, content, len);
  char prefix[700];
  if (line > 0)
    snprintf(prefix, sizeof prefix, "%s:%ld: ", p, line);
  else
    snprintf(prefix, sizeof prefix, "%s: ", p);
  tb_spheres s;
  tb_error err = {{0}};
  int rc = tb_spheres_read(p, &s, &err);
  TB_CHECK_MSG(rc != 0, "%s should fail (%s)", name, reason);
  TB_CHECK_MSG(!strncmp(err.msg, prefix, strlen(prefix)) && strstr(err.msg, reason),
               "%s: message '%s', expected '%s...%s'", name, err.msg, prefix, reason);
  TB_CHECK(s.n == 0 && !s.c && !s.r);
  char args[800];
  snprintf(args, sizeof args, "mesh spheres --info %s", p);
  TB_CHECK_MSG(tb_test_cli_run(args) == 2 && strstr(tb_test_out, prefix), "%s: %s", args,
               tb_test_out);
}

static void malformed(void) {
  expect_error("kw.sph", "sph 1.0\nsphere 1 0 0 0 1\n", -1, 2, "unknown .sph statement 'sphere'");
  expect_error("field.sph", "sph 1.0\nsphe 1 0 0 0 1\nsphe 2 0 0 1\n", -1, 3, "missing radius");
  expect_error("nan.sph", "sph 1.0\nsphe 1 0 nan 0 1\n", -1, 2, "y 'nan' is not finite");
  expect_error("inf.sph", "sph 1.0\nsphe 1 0 0 0 inf\n", -1, 2, "radius 'inf' is not finite");
  expect_error("zero.sph", "sph 1.0\nsphe 1 0 0 0 0\n", -1, 2, "radius 0 is not positive");
  expect_error("neg.sph", "sph 1.0\n\nsphe 1 0 0 0 -0.5\n", -1, 3, "radius -0.5 is not positive");
  expect_error("junk.sph", "sph 1.0\nsphe 1 0 0 0 1 2\n", -1, 2, "unexpected '2' at end of line");
  expect_error("junk2.sph", "sph 1.0\nsphe 1 0 0 0 1x\n", -1, 2, "radius '1x' is not a number");
  expect_error("id.sph", "sph 1.0\nsphe 1.5 0 0 0 1\n", -1, 2, "sphere id '1.5' is not an integer");
  expect_error("empty.sph", "", 0, 0, "empty file");
  expect_error("comments.sph", "# nothing\n#nums 3\n", -1, 2, "empty file");
  expect_error("nohdr.sph", "sphe 1 0 0 0 1\n", -1, 1, "expected the header 'sph 1.0'");
  expect_error("ver.sph", "sph 2.0\nsphe 1 0 0 0 1\n", -1, 1, "unsupported version '2.0'");
  expect_error("two.sph", "sph 1.0\nsphe 1 0 0 0 1\nsph 1.0\n", -1, 3, "second 'sph' header");
  expect_error("none.sph", "sph 1.0\n#nums 0\n", -1, 2, "no spheres");
  expect_error("far.sph", "sph 1.0\nsphe 1 0 0 0 1\nsphe 2 1e200 0 0 1\n", -1, 3, "beyond +-1e+90");
  expect_error("bigr.sph", "sph 1.0\nsphe 1 0 0 0 1e91\n", -1, 2, "beyond +-1e+90");
  expect_error("bin.sph",
               "\x7f"
               "ELF\x02\x01\x01\x00\x00\x00\xff\xfe\n",
               13, 1, "NUL byte");
  expect_error("bin2.sph", "\x89PNG\r\n\x1a\n\xff\xd8", 10, 1, "expected the header");
  /* a file that cannot be opened: "FILE: reason" */
  char path[600], args[800];
  snprintf(path, sizeof path, "%s/absent.sph", tb_test_tmpdir());
  tb_spheres s;
  tb_error err;
  TB_CHECK(tb_spheres_read(path, &s, &err) != 0 && strstr(err.msg, "cannot open"));
  snprintf(args, sizeof args, "mesh info %s", path);
  TB_CHECK(tb_test_cli_run(args) == 2 && strstr(tb_test_out, "absent.sph: cannot open"));
}

/* ---- the packing ---- */
/* A box [0,2]x[0,1]x[0,0.8], 12 outward triangles. */
static void box_mesh(tb_mesh *m) {
  static const int q[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                              {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  memset(m, 0, sizeof *m);
  m->nv = 8, m->ntri = 12;
  m->x = malloc(8 * sizeof *m->x);
  m->tri = malloc(36 * sizeof *m->tri);
  for (int v = 0; v < 8; v++) m->x[v] = tb_v3(v & 1 ? 2 : 0, v & 2 ? 1 : 0, v & 4 ? 0.8 : 0);
  for (int f = 0; f < 6; f++) {
    int *t = m->tri + 6 * f;
    t[0] = q[f][0], t[1] = q[f][1], t[2] = q[f][2];
    t[3] = q[f][0], t[4] = q[f][2], t[5] = q[f][3];
  }
}

static double brute_distance(const tb_mesh *m, tb_vec3 p) {
  double best = INFINITY;
  for (int t = 0; t < m->ntri; t++) {
    const int *v = m->tri + 3 * t;
    best = fmin(best, tb_dist(p, tb_closest_on_triangle(p, m->x[v[0]], m->x[v[1]], m->x[v[2]])));
  }
  return best;
}

/* Packs m to count spheres twice (same bits), checks every sphere against a
 * brute-force distance and the inside test, and returns the coverage. */
static tb_sphere_coverage check_pack(const tb_mesh *m, int count, int expect_n) {
  tb_sphpack_def def = tb_sphpack_default_def(count);
  tb_spheres s, s2;
  tb_sphpack_stats st;
  tb_error err;
  tb_sphere_coverage cov;
  memset(&cov, 0, sizeof cov);
  TB_CHECK_MSG(tb_sphere_pack(m, "surface", &def, &s, &st, &err) == 0, "%s", err.msg);
  TB_CHECK_MSG(s.n == expect_n, "%d spheres (%d candidates)", s.n, st.candidates);
  TB_CHECK(tb_sphere_pack(m, "surface", &def, &s2, NULL, &err) == 0);
  TB_CHECK(s2.n == s.n);
  if (s2.n == s.n) {
    TB_CHECK(memcmp(s.c, s2.c, (size_t)s.n * sizeof *s.c) == 0);
    TB_CHECK(memcmp(s.r, s2.r, (size_t)s.n * sizeof *s.r) == 0);
  }
  tb_closed_surface S;
  TB_CHECK(tb_closed_surface_init(&S, m, "surface", &err) == 0);
  for (int i = 0; i < s.n; i++) {
    TB_CHECK_MSG(tb_closed_surface_inside(&S, s.c[i]), "centre %d outside", i);
    TB_CHECK_NEAR(s.r[i], brute_distance(m, s.c[i]), 1e-9);
    if (i > 0) TB_CHECK(s.r[i] <= s.r[i - 1] || st.alpha < 1); /* largest first in pass 1 */
  }
  tb_closed_surface_free(&S);
  TB_CHECK_MSG(tb_sphere_coverage_of(m, "surface", &s, 48, &cov, &err) == 0, "%s", err.msg);
  TB_CHECK(cov.volume > 0 && cov.volume <= 1 && cov.centres_outside == 0);
  TB_CHECK(cov.max_protrusion <= 1e-12);
  /* the grid's inside points measure the enclosed volume */
  tb_vec3 lo, hi;
  tb_mesh_bbox(m, &lo, &hi);
  tb_vec3 e = tb_sub(hi, lo);
  double h = fmax(e.x, fmax(e.y, e.z)) / 48, vol = tb_mesh_volume(m);
  TB_CHECK_NEAR(cov.grid_inside * h * h * h, vol, 0.03 * vol);
  tb_spheres_free(&s);
  tb_spheres_free(&s2);
  return cov;
}

/* One sphere in the 252-vertex geodesic sphere of radius 1: at the centre
 * (within 0.01) with the inradius (its triangles' planes are ~0.988 away);
 * it covers 0.987 of the volume (measured, grid 64). */
static void pack_unit_sphere(void) {
  tb_mesh m;
  tb_error err;
  TB_CHECK(tb_geosphere(252, 1.0, &m, &err) == 0);
  tb_sphpack_def def = tb_sphpack_default_def(1);
  tb_spheres s;
  TB_CHECK_MSG(tb_sphere_pack(&m, "sphere", &def, &s, NULL, &err) == 0, "%s", err.msg);
  TB_CHECK(s.n == 1);
  if (s.n == 1) {
    TB_CHECK_NEAR(tb_len(s.c[0]), 0, 0.01);
    TB_CHECK_NEAR(s.r[0], 1, 0.02);
    TB_CHECK_NEAR(s.r[0], brute_distance(&m, s.c[0]), 1e-9);
  }
  tb_spheres_free(&s);
  tb_sphere_coverage cov = check_pack(&m, 1, 1);
  TB_CHECK_MSG(cov.volume > 0.95 && cov.reach == 1, "volume %g reach %g", cov.volume, cov.reach);
  tb_mesh_free(&m);
}

/* The box to 100 spheres: measured volume coverage 0.844 (grid 48; the
 * corners' wedges stay uncovered: a sphere touching a face cannot fill them). */
static void pack_box(void) {
  tb_mesh m;
  box_mesh(&m);
  tb_sphere_coverage cov = check_pack(&m, 100, 100);
  TB_CHECK_MSG(cov.volume > 0.80 && cov.reach == 1, "volume %g reach %g", cov.volume, cov.reach);
  tb_mesh_free(&m);
}

/* The generated liver (mesh liver --part surface) to 100 spheres: measured
 * volume coverage 0.865 (grid 48), every vertex within skinning reach. */
static void pack_liver(void) {
  tb_liver_def d = tb_liver_default_def();
  tb_mesh m;
  tb_error err;
  TB_CHECK_MSG(tb_liver_surface(&d, &m, &err) == 0, "%s", err.msg);
  tb_sphere_coverage cov = check_pack(&m, 100, 100);
  TB_CHECK_MSG(cov.volume > 0.82 && cov.reach > 0.99, "volume %g reach %g", cov.volume, cov.reach);
  tb_mesh_free(&m);
}

/* An open surface, a tet-free nothing: "NAME: reason". */
static void pack_refuses(void) {
  tb_mesh m;
  box_mesh(&m);
  m.ntri = 10; /* two triangles gone: open */
  tb_sphpack_def def = tb_sphpack_default_def(5);
  tb_spheres s;
  tb_error err;
  TB_CHECK(tb_sphere_pack(&m, "box", &def, &s, NULL, &err) != 0);
  TB_CHECK_MSG(strstr(err.msg, "box: not a closed") != NULL, "%s", err.msg);
  TB_CHECK(s.n == 0 && !s.c);
  m.ntri = 12;
  def.count = 0;
  TB_CHECK(tb_sphere_pack(&m, "box", &def, &s, NULL, &err) != 0);
  tb_mesh_free(&m);
}

/* ---- the CLI ---- */
static void cli(void) {
  char obj[600], out[600], args[1600];
  const char *dir = tb_test_tmpdir();
  snprintf(obj, sizeof obj, "%s/ball.obj", dir);
  snprintf(out, sizeof out, "%s/ball.sph", dir);
  snprintf(args, sizeof args, "mesh sphere --out %s", obj);
  TB_CHECK(tb_test_cli_run(args) == 0);
  snprintf(args, sizeof args, "mesh spheres %s --count 20 --out %s", obj, out);
  TB_CHECK_MSG(tb_test_cli_run(args) == 0 && strstr(tb_test_out, "packed      20 of 20"), "%s",
               tb_test_out);
  tb_spheres s;
  tb_error err;
  TB_CHECK(tb_spheres_read(out, &s, &err) == 0 && s.n == 20);
  tb_spheres_free(&s);
  snprintf(args, sizeof args, "mesh spheres --info %s --surface %s", out, obj);
  TB_CHECK_MSG(tb_test_cli_run(args) == 0 && strstr(tb_test_out, "count       20") &&
                   strstr(tb_test_out, "volume ") && strstr(tb_test_out, "skin reach"),
               "%s", tb_test_out);
  snprintf(args, sizeof args, "mesh info %s", out);
  TB_CHECK(tb_test_cli_run(args) == 0 && strstr(tb_test_out, "radius "));
  /* bad options and inputs: exit 2 */
  snprintf(args, sizeof args, "mesh spheres %s --count 0 --out %s", obj, out);
  TB_CHECK(tb_test_cli_run(args) == 2 && strstr(tb_test_out, "--count"));
  snprintf(args, sizeof args, "mesh spheres %s --out %s", obj, out);
  TB_CHECK(tb_test_cli_run(args) == 2 && strstr(tb_test_out, "usage"));
  const char *bad = tb_test_file("bad.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nq\n", -1);
  snprintf(args, sizeof args, "mesh spheres %s --count 5 --out %s", bad, out);
  TB_CHECK_MSG(tb_test_cli_run(args) == 2 && strstr(tb_test_out, "bad.obj:5: "), "%s", tb_test_out);
  const char *open = tb_test_file("open.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", -1);
  snprintf(args, sizeof args, "mesh spheres %s --count 5 --out %s", open, out);
  TB_CHECK_MSG(tb_test_cli_run(args) == 2 && strstr(tb_test_out, "open.obj: "), "%s", tb_test_out);
  snprintf(args, sizeof args, "mesh spheres --info %s --surface %s", out, open);
  TB_CHECK(tb_test_cli_run(args) == 2 && strstr(tb_test_out, "open.obj: "));
}

const tb_test_case tb_tests_sph[] = {
    {"round_trip", round_trip},
    {"sofa_liver", sofa_liver},
    {"comments", comments},
    {"malformed", malformed},
    {"pack_unit_sphere", pack_unit_sphere},
    {"pack_box", pack_box},
    {"pack_liver", pack_liver},
    {"pack_refuses", pack_refuses},
    {"cli", cli},
    {NULL, NULL},
};
