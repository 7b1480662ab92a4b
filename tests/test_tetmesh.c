/* A user's surface to tets (meshgen/tetmesh.c, meshgen/cap.c, `mesh tetrahedralize`,
 * `mesh close`, and a surface given to a tet model in `simulate`). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "tb_test.h"
#include "collision/tb_bvh.h"
#include "core/tb_mesh_io.h"
#include "meshgen/tb_meshgen.h"

/* A geodesic sphere of nv vertices written as OBJ, with one vertex no triangle uses. */
static const char *sphere_obj(const char *name, int nv, int extra_vertex) {
  tb_mesh m;
  tb_error err;
  TB_CHECK(tb_geosphere(nv, 1.0, &m, &err) == 0);
  size_t cap = 64 * (size_t)(m.nv + m.ntri) + 64, len = 0;
  char *text = malloc(cap);
  for (int i = 0; i < m.nv; i++)
    len += (size_t)snprintf(text + len, cap - len, "v %.17g %.17g %.17g\n", m.x[i].x, m.x[i].y,
                            m.x[i].z);
  if (extra_vertex) len += (size_t)snprintf(text + len, cap - len, "v 5 5 5\n");
  for (int t = 0; t < m.ntri; t++)
    len += (size_t)snprintf(text + len, cap - len, "f %d %d %d\n", m.tri[3 * t] + 1,
                            m.tri[3 * t + 1] + 1, m.tri[3 * t + 2] + 1);
  const char *path = tb_test_file(name, text, (long)len);
  free(text);
  tb_mesh_free(&m);
  return path;
}

static void shape_of_regular_tet(void) {
  tb_vec3 x[4] = {{1, 1, 1}, {1, -1, -1}, {-1, 1, -1}, {-1, -1, 1}};
  int tet[4] = {0, 1, 2, 3};
  tb_mesh m = {4, x, 0, NULL, 1, tet, 0};
  if (tb_tet_volume(x[0], x[1], x[2], x[3]) < 0) tet[2] = 3, tet[3] = 2;
  tb_tet_shape s = tb_tet_mesh_shape(&m);
  TB_CHECK_NEAR(s.min_dihedral, acos(1.0 / 3) * 180 / M_PI, 1e-9);
  TB_CHECK_NEAR(s.max_dihedral, acos(1.0 / 3) * 180 / M_PI, 1e-9);
  TB_CHECK_NEAR(s.max_radius_edge, sqrt(6.0) / 4, 1e-12);
}

/* The command: an OBJ with an unused vertex, to tets in every tet format; the volume is the
 * surface's, every tet positive, the boundary the surface. */
static void tetrahedralize_sphere(void) {
  const char *in = sphere_obj("ball.obj", 162, 1);
  static const char *const out[] = {"ball.vtk", "ball.node", "ball.msh"};
  tb_mesh surf;
  tb_error err;
  TB_CHECK(tb_mesh_read(in, &surf, &err) == 0);
  int dropped = tb_mesh_drop_unused(&surf);
  TB_CHECK(dropped == 1 && surf.nv == 162);
  for (int k = 0; k < 3; k++) {
    char args[1024], path[600];
    snprintf(path, sizeof path, "%s/%s", tb_test_tmpdir(), out[k]);
    snprintf(args, sizeof args, "mesh tetrahedralize %s --out %s", in, path);
    TB_CHECK_MSG(tb_test_cli_run(args) == 0, "%s", tb_test_out);
    TB_CHECK_MSG(strstr(tb_test_out, "1 unused vertex dropped"), "%s", tb_test_out);
    tb_mesh m;
    TB_CHECK_MSG(tb_mesh_read(path, &m, &err) == 0, "%s", err.msg);
    TB_CHECK_MSG(m.ntet > 162 && tb_mesh_min_tet_volume(&m) > 0, "%s: %d tets", out[k], m.ntet);
    TB_CHECK_NEAR(tb_mesh_volume(&m), tb_mesh_volume(&surf), 1e-12);
    int *bnd = NULL, nb = tb_mesh_tet_boundary(&m, &bnd);
    TB_CHECK(nb == 320); /* the surface kept (TetGen's Y) */
    free(bnd);
    for (int i = 0; i < 162; i++) /* its vertices first, in order */
      TB_CHECK(tb_dist(m.x[i], surf.x[i]) == 0);
    tb_mesh_free(&m);
  }
  tb_mesh_free(&surf);
}

static void tetrahedralize_count_and_quality(void) {
  const char *in = sphere_obj("ball2.obj", 642, 0);
  char args[1024];
  snprintf(args, sizeof args, "mesh tetrahedralize %s --tets 8000 --out %s/b8k.vtk", in,
           tb_test_tmpdir());
  TB_CHECK_MSG(tb_test_cli_run(args) == 0, "%s", tb_test_out);
  int nv = 0, nt = 0;
  const char *p = strstr(tb_test_out, "\ntets: ");
  TB_CHECK_MSG(p && sscanf(p, "\ntets: %d vertices, %d tets", &nv, &nt) == 2 &&
                   fabs(nt / 8000.0 - 1) <= 0.05,
               "%s", tb_test_out);
  snprintf(args, sizeof args, "mesh tetrahedralize %s --split-surface --out %s/split.vtk", in,
           tb_test_tmpdir());
  TB_CHECK_MSG(tb_test_cli_run(args) == 0, "%s", tb_test_out);
  snprintf(args, sizeof args, "%s/split.vtk", tb_test_tmpdir());
  tb_mesh m;
  tb_error err;
  TB_CHECK(tb_mesh_read(args, &m, &err) == 0);
  tb_tet_shape s = tb_tet_mesh_shape(&m);
  TB_CHECK_MSG(s.min_dihedral > 5 && s.max_radius_edge < 3, "%g %g", s.min_dihedral,
               s.max_radius_edge);
  tb_mesh_free(&m);
  /* bad options and inputs: exit 2 */
  static const char *const bad[] = {"--quality 0.5",
                                    "--quality abc",
                                    "--tets 0",
                                    "--tets 2.5",
                                    "--max-volume 0",
                                    "--max-volume -1",
                                    "--tets 100 --max-volume 1",
                                    "--colour 3"};
  for (int k = 0; k < 8; k++) {
    snprintf(args, sizeof args, "mesh tetrahedralize %s %s --out %s/x.vtk", in, bad[k],
             tb_test_tmpdir());
    TB_CHECK_MSG(tb_test_cli_run(args) == 2, "%s: %s", bad[k], tb_test_out);
  }
  snprintf(args, sizeof args, "mesh tetrahedralize %s --out %s/x.obj2", in, tb_test_tmpdir());
  TB_CHECK(tb_test_cli_run(args) == 2 && strstr(tb_test_out, "unknown extension"));
  snprintf(args, sizeof args, "mesh tetrahedralize %s/b8k.vtk --out %s/x.vtk", tb_test_tmpdir(),
           tb_test_tmpdir());
  TB_CHECK(tb_test_cli_run(args) == 2 && strstr(tb_test_out, "a tet mesh already"));
}

/* A sphere with one vertex pushed through the far side: refused naming a crossing pair; the
 * repair pulls the vertex back until nothing crosses, then TetGen meshes it. */
static void self_intersecting_refused_and_repaired(void) {
  tb_mesh m;
  tb_error err;
  TB_CHECK(tb_geosphere(162, 1.0, &m, &err) == 0);
  m.x[0] = tb_scale(m.x[0], -1.3);
  const char *path = tb_test_file("tangled.off", "", 0);
  TB_CHECK(tb_mesh_write(path, &m, &err) == 0);
  tb_pairlist self = {0, 0, NULL};
  TB_CHECK(tb_collide_self(m.x, m.tri, m.ntri, &self, &err) == 0 && self.n > 0);
  char want[64];
  snprintf(want, sizeof want, "triangles %d and %d", self.ij[0], self.ij[1]);
  char args[1024];
  snprintf(args, sizeof args, "mesh tetrahedralize %s --out %s/t.vtk", path, tb_test_tmpdir());
  TB_CHECK_MSG(
      tb_test_cli_run(args) == 2 && strstr(tb_test_out, want) && strstr(tb_test_out, "--repair"),
      "%s", tb_test_out);
  double moved;
  int nmoved, left = tb_surface_untangle(&m, 8, &moved, &nmoved, &err);
  TB_CHECK_MSG(left == 0 && nmoved > 0 && moved > 1, "%d left, %d moved by %g", left, nmoved,
               moved);
  tb_pairlist_free(&self);
  TB_CHECK(tb_collide_self(m.x, m.tri, m.ntri, &self, &err) == 0 && self.n == 0);
  tb_pairlist_free(&self);
  snprintf(args, sizeof args, "mesh tetrahedralize %s --repair --out %s/t.vtk", path,
           tb_test_tmpdir());
  TB_CHECK_MSG(tb_test_cli_run(args) == 0 && strstr(tb_test_out, "0 crossing pairs left"), "%s",
               tb_test_out);
  tb_mesh_free(&m);
}

/* Holes cut into a sphere are capped: closed, oriented, no crossing, the volume near the
 * sphere's; a closed surface is left alone. */
static void close_caps_holes(void) {
  tb_mesh m;
  tb_error err;
  TB_CHECK(tb_geosphere(642, 1.0, &m, &err) == 0);
  double v0 = tb_mesh_volume(&m);
  int loops = -1;
  TB_CHECK(tb_mesh_close(&m, &loops, &err) == 0 && loops == 0 && m.ntri == 1280);
  /* drop the fans around two opposite vertices (0 and the farthest from it) */
  int far = 0;
  for (int i = 1; i < m.nv; i++)
    if (tb_dist(m.x[i], m.x[0]) > tb_dist(m.x[far], m.x[0])) far = i;
  int n = 0;
  for (int t = 0; t < m.ntri; t++) {
    const int *f = m.tri + 3 * t;
    int hit = 0;
    for (int j = 0; j < 3; j++) hit |= f[j] == 0 || f[j] == far;
    if (!hit) memmove(m.tri + 3 * n++, f, sizeof(int) * 3);
  }
  m.ntri = n;
  tb_mesh_drop_unused(&m);
  const char *path = tb_test_file("open.obj", "", 0);
  TB_CHECK(tb_mesh_write(path, &m, &err) == 0);
  tb_mesh_topo t = tb_mesh_topology(&m);
  TB_CHECK(!t.closed && t.boundary_edges == 10);
  char args[1024];
  snprintf(args, sizeof args, "mesh close %s --out %s/closed.off", path, tb_test_tmpdir());
  TB_CHECK_MSG(tb_test_cli_run(args) == 0 && strstr(tb_test_out, "2 holes capped"), "%s",
               tb_test_out);
  snprintf(args, sizeof args, "%s/closed.off", tb_test_tmpdir());
  tb_mesh c;
  TB_CHECK(tb_mesh_read(args, &c, &err) == 0);
  t = tb_mesh_topology(&c);
  TB_CHECK(t.closed && t.manifold && !t.misoriented_edges && c.ntri == n + 10);
  TB_CHECK_MSG(fabs(tb_mesh_volume(&c) / v0 - 1) < 0.01, "%g vs %g", tb_mesh_volume(&c), v0);
  tb_pairlist self = {0, 0, NULL};
  TB_CHECK(tb_collide_self(c.x, c.tri, c.ntri, &self, &err) == 0 && self.n == 0);
  tb_pairlist_free(&self);
  /* the capped surface meshes; the open one is refused pointing at mesh close */
  snprintf(args, sizeof args, "mesh tetrahedralize %s/closed.off --out %s/c.vtk", tb_test_tmpdir(),
           tb_test_tmpdir());
  TB_CHECK_MSG(tb_test_cli_run(args) == 0, "%s", tb_test_out);
  snprintf(args, sizeof args, "mesh tetrahedralize %s --out %s/c.vtk", path, tb_test_tmpdir());
  TB_CHECK_MSG(tb_test_cli_run(args) == 2 && strstr(tb_test_out, "mesh close"), "%s", tb_test_out);
  tb_mesh_free(&c), tb_mesh_free(&m);
}

/* A closed surface given to a tet model is meshed by TetGen, and simulate says so. */
static void simulate_meshes_a_surface(void) {
  const char *in = sphere_obj("ball3.obj", 162, 0);
  char args[1024];
  snprintf(args, sizeof args,
           "simulate --model fem --mesh %s --fix-box -2,-2,-2,2,2,-0.8 --steps 3", in);
  TB_CHECK_MSG(tb_test_cli_run(args) == 0, "%s", tb_test_out);
  TB_CHECK_MSG(strstr(tb_test_out, "162 vertices and 320 triangles tetrahedralised by TetGen"),
               "%s", tb_test_out);
  TB_CHECK(strstr(tb_test_out, "inverted tets 0"));
}

/* SOFA's liver-smooth.obj: 7 crossing pairs (TetGen's -d lists the same 7, some twice); the
 * repair moves a few vertices less than a mean edge, then TetGen meshes it. */
static void sofa_liver_smooth_repaired(void) {
  char path[600];
  snprintf(path, sizeof path, "%s/../shared/data/sofa/liver-smooth.obj", tb_test_source_root());
  tb_mesh m, t;
  tb_error err;
  if (tb_mesh_read(path, &m, &err)) {
    tb_test_skip("%s not present (../shared/data)", path);
    return;
  }
  TB_CHECK(tb_tetmesh_check(&m, path, &err) == -1 && strstr(err.msg, "7 crossing pairs"));
  double moved;
  int nmoved, left = tb_surface_untangle(&m, 8, &moved, &nmoved, &err);
  TB_CHECK_MSG(left == 0 && nmoved < 50 && moved < 1, "%d left, %d moved by %g", left, nmoved,
               moved);
  tb_tetmesh_opts o = tb_tetmesh_default_opts();
  TB_CHECK_MSG(tb_tetmesh(&m, path, &o, &t, &err) == 0, "%s", err.msg);
  TB_CHECK(t.ntet > 0 && tb_mesh_min_tet_volume(&t) > 0);
  tb_mesh_free(&t), tb_mesh_free(&m);
}

/* The README's path from a surface to a rendered, ParaView-readable press, with its own scene
 * file (read from the README) on a generated liver surface: every command succeeds. */
static void readme_end_to_end(void) {
  char path[700], cmd[2400], out[8192];
  snprintf(path, sizeof path, "%s/README.md", tb_test_source_root());
  char *md = tb_test_slurp(path);
  const char *a = md ? strstr(md, "```ini\n") : NULL, *b = a ? strstr(a + 7, "```") : NULL;
  TB_CHECK_MSG(a && b && strstr(a, "file = liver.vtk"), "no press.ini in the README");
  if (!a || !b) {
    free(md);
    return;
  }
  char dir[600];
  snprintf(dir, sizeof dir, "%s/readme", tb_test_tmpdir());
  snprintf(cmd, sizeof cmd, "mkdir -p '%s'", dir);
  tb_test_run(cmd, NULL, 0);
  snprintf(path, sizeof path, "%s/press.ini", dir);
  FILE *f = fopen(path, "w");
  if (f) fwrite(a + 7, 1, (size_t)(b - a - 7), f), fclose(f);
  free(md);
  const char *cli = tb_test_cli();
  snprintf(
      cmd, sizeof cmd,
      "cd '%s' && '%s' mesh liver --part surface --set surface_verts=300 --out organ.obj && "
      "'%s' mesh info organ.obj && '%s' mesh tetrahedralize organ.obj --repair --out liver.vtk "
      "&& '%s' simulate --scene press.ini --vtk out/ --json out/run.json; s=$?; "
      "[ $s -eq 0 ] || [ $s -eq 3 ] || exit $s; "
      "'%s' render --scene press.ini --color von_mises --times 0,1 --size 160x120 --out pics/ "
      "&& test -s pics/t1.000.png && test -s out/frames.pvd && test -s out/run.json",
      dir, cli, cli, cli, cli, cli);
  TB_CHECK_MSG(tb_test_run(cmd, out, sizeof out) == 0, "%s", out);
  TB_CHECK_MSG(strstr(out, "self-intersecting 0 triangle pairs") &&
                   strstr(out, "wrote liver.vtk") && strstr(out, "instrument: largest penetration"),
               "%s", out);
}

const tb_test_case tb_tests_tetmesh[] = {
    {"readme_end_to_end", readme_end_to_end},
    {"sofa_liver_smooth_repaired", sofa_liver_smooth_repaired},
    {"shape_of_regular_tet", shape_of_regular_tet},
    {"tetrahedralize_sphere", tetrahedralize_sphere},
    {"tetrahedralize_count_and_quality", tetrahedralize_count_and_quality},
    {"self_intersecting_refused_and_repaired", self_intersecting_refused_and_repaired},
    {"close_caps_holes", close_caps_holes},
    {"simulate_meshes_a_surface", simulate_meshes_a_surface},
    {0, 0},
};
