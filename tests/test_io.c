/* Mesh file I/O: each reader on small hand-written files, exact write-read
 * round trips, every malformed-input case with its "FILE:LINE:" prefix, and
 * the real SOFA and FCL meshes when ../shared/data is present. */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "tb_test.h"
#include "core/tb_mesh_io.h"
#include "meshgen/tb_meshgen.h"

/* ---- helpers ---- */

static int read_ok(const char *path, tb_mesh *m) {
  tb_error err = {{0}};
  int rc = tb_mesh_read(path, m, &err);
  TB_CHECK_MSG(rc == 0, "reading %s: %s", path, err.msg);
  return rc == 0;
}

static int write_ok(const char *path, const tb_mesh *m) {
  tb_error err = {{0}};
  int rc = tb_mesh_write(path, m, &err);
  TB_CHECK_MSG(rc == 0, "writing %s: %s", path, err.msg);
  return rc == 0;
}

static void check_ints(const int *got, const int *want, int n, const char *what) {
  for (int i = 0; i < n; i++)
    TB_CHECK_MSG(got[i] == want[i], "%s[%d] = %d, expected %d", what, i, got[i], want[i]);
}

/* Counts, then positions and indices bit for bit. */
static void check_same(const tb_mesh *a, const tb_mesh *b) {
  TB_CHECK_MSG(a->nv == b->nv && a->ntri == b->ntri && a->ntet == b->ntet,
               "counts %d/%d/%d vs %d/%d/%d", a->nv, a->ntri, a->ntet, b->nv, b->ntri, b->ntet);
  if (a->nv != b->nv || a->ntri != b->ntri || a->ntet != b->ntet) return;
  TB_CHECK(a->nv == 0 || memcmp(a->x, b->x, (size_t)a->nv * sizeof *a->x) == 0);
  check_ints(a->tri, b->tri, 3 * a->ntri, "tri");
  check_ints(a->tet, b->tet, 4 * a->ntet, "tet");
}

/* A unit-ish cube in five tets with awkward coordinates, and a surface. */
static tb_vec3 cube_x[8];
static int cube_tet[20] = {0, 1, 3, 5, 0, 3, 2, 6, 0, 5, 6, 4, 3, 6, 5, 7, 0, 3, 6, 5};
static int quad_tri[12] = {0, 1, 3, 0, 3, 2, 4, 5, 7, 4, 7, 6};
static tb_mesh cube(int tets, int tris) {
  for (int i = 0; i < 8; i++)
    cube_x[i] = tb_v3((i & 1) * (1 + 1.0 / 3.0) + 0.1 * i, ((i >> 1) & 1) ? 0.7 : 1e-310 * i,
                      ((i >> 2) & 1) ? 1e17 / 3 : -1.0 / 7);
  cube_x[0].x = -0.0;
  return (tb_mesh){
      8, cube_x, tris ? 4 : 0, tris ? quad_tri : NULL, tets ? 5 : 0, tets ? cube_tet : NULL, 0};
}

/* ---- OBJ ---- */

static void test_obj_polygons(void) {
  tb_mesh m;
  const char *p =
      tb_test_file("poly.obj",
                   "# quad and pentagon\r\nv 0 0 0\r\nv 1 0 0\r\nv 1 1 0 1.0\r\nv 0 1 0\r\n"
                   "v 2 0 0 0.5 0.5 0.5\r\nf 1 2 3 4\r\nf 1 2 5 3 4\r\n",
                   -1);
  if (!read_ok(p, &m)) return;
  TB_CHECK(m.nv == 5 && m.ntri == 5 && m.ntet == 0);
  int want[15] = {0, 1, 2, 0, 2, 3, 0, 1, 4, 0, 4, 2, 0, 2, 3};
  if (m.ntri == 5) check_ints(m.tri, want, 15, "tri");
  TB_CHECK(m.x[2].y == 1.0 && m.x[4].x == 2.0);
  tb_mesh_free(&m);
}

static void test_obj_indices(void) {
  tb_mesh m;
  const char *p = tb_test_file("idx.obj",
                               "mtllib a.mtl\no thing\ng grp\ns off\nusemtl red\n"
                               "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvn 0 0 1\nf -3 -2 -1\n"
                               "v 0 0 1\nf 1/1/1 2/1/1 4/1/1\nf 2//1 3//1 4//1\nf 3/1 -4/1 -1/1\n"
                               "l 1 2\np 3\n",
                               -1);
  if (!read_ok(p, &m)) return;
  TB_CHECK(m.nv == 4 && m.ntri == 4 && m.nskipped == 2);
  int want[12] = {0, 1, 2, 0, 1, 3, 1, 2, 3, 2, 0, 3};
  if (m.ntri == 4) check_ints(m.tri, want, 12, "tri");
  tb_mesh_free(&m);
}

static void test_obj_fcl_header(void) {
  tb_mesh m;
  const char *p = tb_test_file("fclhdr.obj", "3 1\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", -1);
  if (!read_ok(p, &m)) return;
  TB_CHECK(m.nv == 3 && m.ntri == 1);
  tb_mesh_free(&m);
}

/* ---- OFF ---- */

static void test_off_reader(void) {
  tb_mesh m;
  const char *p =
      tb_test_file("quad.off",
                   "OFF # header\n# a comment line\n\n5 2 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n"
                   "0.5 0.5 -1e-3 # apex\n4 0 1 2 3 255 0 0\n3 0 1 4\n",
                   -1);
  if (read_ok(p, &m)) {
    TB_CHECK(m.nv == 5 && m.ntri == 3 && m.x[4].z == -1e-3);
    int want[9] = {0, 1, 2, 0, 2, 3, 0, 1, 4};
    if (m.ntri == 3) check_ints(m.tri, want, 9, "tri");
    tb_mesh_free(&m);
  }
  p = tb_test_file("coff.off", "COFF 3 1 3\n0 0 0 1 0 0 1\n1 0 0 0 1 0 1\n0 1 0 0 0 1 1\n3 0 1 2\n",
                   -1);
  if (read_ok(p, &m)) {
    TB_CHECK(m.nv == 3 && m.ntri == 1 && m.x[1].x == 1.0);
    tb_mesh_free(&m);
  }
  p = tb_test_file("nohdr.off", "3 1\n0 0 0\n1 0 0\n0 1 0\n3 2 1 0\n", -1);
  if (read_ok(p, &m)) {
    TB_CHECK(m.nv == 3 && m.ntri == 1 && m.tri[0] == 2 && m.tri[2] == 0);
    tb_mesh_free(&m);
  }
}

/* ---- STL ---- */

static void test_stl_ascii(void) {
  tb_mesh m;
  const char *p =
      tb_test_file("two.stl",
                   "solid a\n facet normal 0 0 1\n  outer loop\n   vertex 0 0 0\n"
                   "   vertex 1 0 0\n   vertex 0 1 0\n  endloop\n endfacet\nendsolid a\n"
                   "solid b\n facet normal 0 0 1\n  outer loop\n   vertex 1 0 0\n"
                   "   vertex 1 1 0\n   vertex -0 1 0\n  endloop\n endfacet\nendsolid b\n",
                   -1);
  if (!read_ok(p, &m)) return;
  TB_CHECK(m.nv == 4 && m.ntri == 2);
  int want[6] = {0, 1, 2, 1, 3, 2};
  if (m.ntri == 2) check_ints(m.tri, want, 6, "tri");
  tb_mesh_free(&m);
}

static void put_le32(unsigned char *p, unsigned long u) {
  for (int k = 0; k < 4; k++) p[k] = (unsigned char)(u >> (8 * k));
}

/* A binary STL of n triangles (9 floats each) into buf; returns its size. */
static long stl_binary(unsigned char *buf, const float *v, int n, const char *header) {
  memset(buf, 0, 84 + 50 * (size_t)n);
  memcpy(buf, header, strlen(header));
  put_le32(buf + 80, (unsigned long)n);
  for (int t = 0; t < n; t++)
    for (int k = 0; k < 9; k++) {
      uint32_t u;
      memcpy(&u, &v[9 * t + k], 4);
      put_le32(buf + 84 + 50 * t + 12 + 4 * k, u);
    }
  return 84 + 50L * n;
}

static void test_stl_binary(void) {
  static const float v[27] = {0, 0,     0,    1.25f, 0, 0, 0, 0.5f, 0,    1.25f, 0, 0, 1.25f, 0.5f,
                              0, -0.0f, 0.5f, 0,     0, 0, 0, 0,    0.5f, 0,     0, 0, -3};
  unsigned char buf[84 + 150];
  long n = stl_binary(buf, v, 3, "solid looks like ascii but is binary");
  tb_mesh m;
  if (!read_ok(tb_test_file("bin.stl", (const char *)buf, n), &m)) return;
  TB_CHECK(m.nv == 5 && m.ntri == 3);
  int want[9] = {0, 1, 2, 1, 3, 2, 0, 2, 4};
  tb_vec3 wx[5] = {{0, 0, 0}, {1.25, 0, 0}, {0, 0.5, 0}, {1.25, 0.5, 0}, {0, 0, -3}};
  if (m.ntri == 3 && m.nv == 5) {
    check_ints(m.tri, want, 9, "tri");
    for (int i = 0; i < 5; i++)
      TB_CHECK(m.x[i].x == wx[i].x && m.x[i].y == wx[i].y && m.x[i].z == wx[i].z);
  }
  tb_mesh_free(&m);
}

/* ---- TetGen ---- */

static void test_tetgen_one_based(void) {
  tb_mesh m;
  tb_test_file("a.node",
               "# five nodes\n5 3 1 1\n1 0 0 0 7.5 1\n2 1 0 0 7.5 1\n3 0 1 0 7.5 1\n"
               "4 0 0 1 7.5 1\n5 1 1 1 7.5 0\n",
               -1);
  tb_test_file("a.ele", "2 4 1\n1 1 2 3 4 1\n2 2 3 4 5 1  # region\n", -1);
  tb_test_file("a.face", "2 1\n1 1 3 2 -1\n2 1 2 4 -1\n", -1);
  int tet[8] = {0, 1, 2, 3, 1, 2, 3, 4}, tri[6] = {0, 2, 1, 0, 1, 3};
  const char *which[2] = {"a.node", "a.ele"};
  for (int k = 0; k < 2; k++) {
    if (!read_ok(tb_test_tmp_path(which[k]), &m)) continue;
    TB_CHECK(m.nv == 5 && m.ntet == 2 && m.ntri == 2 && m.x[4].z == 1.0);
    if (m.ntet == 2 && m.ntri == 2)
      check_ints(m.tet, tet, 8, "tet"), check_ints(m.tri, tri, 6, "tri");
    tb_mesh_free(&m);
  }
}

static void test_tetgen_zero_based(void) {
  tb_mesh m;
  tb_test_file("z.node", "4 3 0 0\n0 0 0 0\n1 1 0 0\n2 0 1 0\n3 0 0 1\n", -1);
  tb_test_file("z.ele", "1 10 0\n0 3 2 1 0 0 1 1 2 2 3\n", -1);
  tb_test_file("z.face", "1 1\n0 0 1 2 5 0 -1\n", -1); /* marker and two neighbours (-nn) */
  if (read_ok(tb_test_tmp_path("z.node"), &m)) {
    TB_CHECK(m.nv == 4 && m.ntet == 1 && m.ntri == 1 && m.tet[0] == 3 && m.tet[3] == 0);
    tb_mesh_free(&m);
  }
  tb_test_file("pts.node", "2 3\n1 0 0 0\n2 1 2 3\n", -1); /* no .ele: points only */
  if (read_ok(tb_test_tmp_path("pts.node"), &m)) {
    TB_CHECK(m.nv == 2 && m.ntet == 0 && m.x[1].z == 3.0);
    tb_mesh_free(&m);
  }
}

/* ---- Gmsh ---- */

static void check_msh(const char *name, const char *text, int nv, int ntri, int ntet, int nskip,
                      const int *tri, const int *tet) {
  tb_mesh m;
  if (!read_ok(tb_test_file(name, text, -1), &m)) return;
  TB_CHECK_MSG(m.nv == nv && m.ntri == ntri && m.ntet == ntet && m.nskipped == nskip,
               "%s: %d v %d tri %d tet %d skipped", name, m.nv, m.ntri, m.ntet, m.nskipped);
  if (m.ntri == ntri) check_ints(m.tri, tri, 3 * ntri, "tri");
  if (m.ntet == ntet) check_ints(m.tet, tet, 4 * ntet, "tet");
  tb_mesh_free(&m);
}

static void test_msh_v1(void) {
  int tri[3] = {0, 1, 2}, tet[4] = {0, 1, 2, 3};
  check_msh("v1.msh",
            "$NOD\n4\n10 0 0 0\n20 1 0 0\n30 0 1 0\n40 0 0 1\n$ENDNOD\n$ELM\n4\n1 15 0 1 1 10\n"
            "2 1 0 1 2 10 20\n3 2 0 1 3 10 20 30\n4 4 0 1 4 10 20 30 40\n$ENDELM",
            4, 1, 1, 2, tri, tet);
}

static void test_msh_v2(void) {
  int tri[3] = {0, 1, 2}, tet[8] = {0, 1, 2, 3, 1, 2, 3, 4};
  check_msh(
      "v2.msh",
      "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$PhysicalNames\n1\n3 1 \"body\"\n$EndPhysicalNames\n"
      "$Nodes\n5\n7 0 0 0\n3 1 0 0\n9 0 1 0\n1 0 0 1\n100 1 1 1\n$EndNodes\n$Elements\n5\n"
      "1 1 2 0 1 7 3\n2 2 2 0 1 7 3 9\n3 4 2 1 1 7 3 9 1\n4 4 0 3 9 1 100\n5 3 1 0 7 3 9 1\n"
      "$EndElements\n$NodeData\n1\n\"t\"\n$EndNodeData\n",
      5, 1, 2, 2, tri, tet);
}

static void test_msh_v4(void) {
  int tri[3] = {0, 1, 2}, tet[8] = {0, 1, 2, 3, 1, 2, 3, 4};
  check_msh(
      "v4.msh",
      "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Entities\n1 0 0 1\n1 0 0 0 0\n"
      "1 0 0 0 1 1 1 0\n$EndEntities\n$Nodes\n3 6 3 60\n0 1 0 1\n50\n0 0 0\n3 1 0 4\n3\n12\n5\n4\n"
      "1 0 0\n0 1 0\n0 0 1\n1 1 1\n2 1 1 1\n60\n0.5 0.5 0 0.25 0.75\n$EndNodes\n"
      "$Elements\n3 4 1 10\n0 1 15 1\n1 50\n2 1 2 1\n2 50 3 12\n3 1 4 2\n3 50 3 12 5\n"
      "4 3 12 5 4\n$EndElements\n",
      6, 1, 2, 1, tri, tet);
}

/* ---- writers: exact round trips ---- */

static void roundtrip(const char *name, tb_mesh src) {
  tb_mesh m;
  if (!write_ok(tb_test_tmp_path(name), &src) || !read_ok(tb_test_tmp_path(name), &m)) return;
  check_same(&m, &src);
  tb_mesh_free(&m);
}

static void test_roundtrip_surface(void) {
  roundtrip("rt.obj", cube(0, 1));
  roundtrip("rt.off", cube(0, 1));
}

static void test_roundtrip_tetgen(void) {
  roundtrip("rt.node", cube(1, 1));
  roundtrip("rt2.ele", cube(1, 0));
  roundtrip("rt3.node", cube(0, 1));
}

/* A tet mesh without triangles is written as its boundary. */
static void test_write_tet_boundary(void) {
  tb_mesh src = cube(1, 0), m;
  int *faces = NULL, n = tb_mesh_tet_boundary(&src, &faces);
  TB_CHECK(n == 12);
  const char *name[2] = {"bnd.off", "bnd.obj"};
  for (int k = 0; k < 2 && n > 0; k++) {
    if (!write_ok(tb_test_tmp_path(name[k]), &src) || !read_ok(tb_test_tmp_path(name[k]), &m))
      continue;
    TB_CHECK(m.nv == 8 && m.ntri == n && m.ntet == 0);
    if (m.ntri == n) check_ints(m.tri, faces, 3 * n, "boundary");
    TB_CHECK(m.nv == 8 && memcmp(m.x, src.x, sizeof cube_x) == 0);
    tb_mesh_free(&m);
  }
  free(faces);
}

/* Surface files carry only the vertices their triangles use, in order. */
static void test_write_surface_compact(void) {
  tb_vec3 x[5] = {{9, 9, 9}, {0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1.0 / 3}};
  int tri[6] = {4, 1, 3, 1, 4, 2}, want[6] = {3, 0, 2, 0, 3, 1};
  tb_mesh src = {5, x, 2, tri, 0, NULL, 0}, m;
  const char *name[3] = {"cmp.off", "cmp.obj", "cmp.vtk"};
  for (int k = 0; k < 3; k++) {
    if (!write_ok(tb_test_tmp_path(name[k]), &src) || !read_ok(tb_test_tmp_path(name[k]), &m))
      continue;
    TB_CHECK_MSG(m.nv == 4 && m.ntri == 2, "%s: %d vertices, %d triangles", name[k], m.nv, m.ntri);
    if (m.nv == 4 && m.ntri == 2) {
      check_ints(m.tri, want, 6, "tri");
      TB_CHECK(memcmp(m.x, x + 1, 4 * sizeof *x) == 0);
    }
    tb_mesh_free(&m);
  }
  /* a tet mesh with interior vertices: its boundary's vertices only */
  tb_mesh beam;
  tb_error err;
  TB_CHECK(tb_beam(3, 3, 3, 3, 3, 3, &beam, &err) == 0);
  if (write_ok(tb_test_tmp_path("cmp_beam.off"), &beam) &&
      read_ok(tb_test_tmp_path("cmp_beam.off"), &m)) {
    TB_CHECK_MSG(m.nv == 64 - 8 && m.ntri == beam.ntri, "%d vertices", m.nv);
    for (int i = 0, j = 0; i < beam.nv && j < m.nv; i++) {
      tb_vec3 p = beam.x[i];
      if (p.x > 0 && p.x < 3 && p.y > 0 && p.y < 3 && p.z > 0 && p.z < 3) continue;
      TB_CHECK_MSG(memcmp(&m.x[j], &p, sizeof p) == 0, "vertex %d out of order", j);
      j++;
    }
    tb_mesh_topo t = tb_mesh_topology(&m);
    TB_CHECK(t.closed && t.manifold && t.unused_verts == 0);
    tb_mesh_free(&m);
  }
  tb_mesh_free(&beam);
}

static void test_write_vtk(void) {
  tb_mesh tets = cube(1, 1), tris = cube(0, 1);
  if (!write_ok(tb_test_tmp_path("t.vtk"), &tets) || !write_ok(tb_test_tmp_path("s.vtk"), &tris))
    return;
  char *a = tb_test_slurp(tb_test_tmp_path("t.vtk")), *b = tb_test_slurp(tb_test_tmp_path("s.vtk")),
       line[200];
  TB_CHECK(a && b);
  if (a && b) {
    TB_CHECK(strncmp(a, "# vtk DataFile Version 3.0\n", 27) == 0);
    TB_CHECK(strstr(a, "DATASET UNSTRUCTURED_GRID\nPOINTS 8 double\n"));
    TB_CHECK(strstr(a, "CELLS 5 25\n4 0 1 3 5\n") &&
             strstr(a, "CELL_TYPES 5\n10\n10\n10\n10\n10\n"));
    TB_CHECK(strstr(b, "DATASET POLYDATA\nPOINTS 8 double\n") &&
             strstr(b, "POLYGONS 4 16\n3 0 1 3\n"));
    snprintf(line, sizeof line, "%.17g %.17g %.17g\n", cube_x[7].x, cube_x[7].y, cube_x[7].z);
    TB_CHECK(strstr(a, line) && strstr(b, line));
  }
  free(a);
  free(b);
}

static void expect_write_error(const char *path, const tb_mesh *m, const char *reason) {
  tb_error err = {{0}};
  char prefix[700];
  snprintf(prefix, sizeof prefix, "%s: ", path);
  TB_CHECK_MSG(tb_mesh_write(path, m, &err) != 0, "writing %s should fail", path);
  TB_CHECK_MSG(strncmp(err.msg, prefix, strlen(prefix)) == 0 && strstr(err.msg, reason),
               "message '%s'", err.msg);
}

static void test_write_errors(void) {
  tb_mesh m = cube(1, 1);
  expect_write_error("/nonexistent-dir/x.obj", &m, "cannot open for writing");
  expect_write_error(tb_test_tmp_path("x.ply"), &m, "unknown mesh format");
  if (symlink("/dev/full", tb_test_tmp_path("full.obj")) == 0 &&
      symlink("/dev/full", tb_test_tmp_path("full.vtk")) == 0) {
    expect_write_error(tb_test_tmp_path("full.obj"), &m, "write failed");
    expect_write_error(tb_test_tmp_path("full.vtk"), &m, "write failed");
  } else {
    TB_CHECK_MSG(0, "cannot link /dev/full");
  }
  int bad[3] = {0, 8, 2};
  tb_mesh b = {8, cube_x, 1, bad, 0, NULL, 0};
  expect_write_error(tb_test_tmp_path("bad.off"), &b, "cannot write: triangle 0 uses vertex 8");
  tb_vec3 nan_x[3] = {{0, 0, 0}, {NAN, 0, 0}, {0, 1, 0}};
  tb_mesh c = {3, nan_x, 1, bad, 0, NULL, 0};
  expect_write_error(tb_test_tmp_path("nan.obj"), &c, "vertex 1 is not finite");
}

/* ---- malformed input, per format ---- */

#define TRI3 "v 0 0 0\nv 1 0 0\nv 0 1 0\n"
static void test_errors_obj(void) {
  static const tb_test_bad_file c[] = {
      {"e_range.obj", TRI3 "f 1 2 4\n", 4, "vertex index 4 out of range"},
      {"e_zero.obj", TRI3 "f 0 1 2\n", 4, "out of range"},
      {"e_neg.obj", TRI3 "\n# c\nf -1 -2 -4\n", 6, "vertex index -4 out of range"},
      {"e_nan.obj", "v 0 0 0\nv nan 0 0\n", 2, "x coordinate 'nan' is not finite"},
      {"e_inf.obj", "v 0 0 0\n\nv 1 -inf 0\n", 3, "'-inf' is not finite"},
      {"e_huge.obj", "v 0 0 1e999\n", 1, "not finite"},
      {"e_text.obj", "v 1 abc 3\n", 1, "y coordinate 'abc' is not a number"},
      {"e_junk.obj", "v 1 2 3x\n", 1, "'3x' is not a number"},
      {"e_trunc.obj", TRI3 "v 0 1", 4, "missing z coordinate"},
      {"e_short.obj", TRI3 "f 1 2\n", 4, "face with 2 vertices"},
      {"e_float.obj", TRI3 "f 1.5 2 3\n", 4, "not an integer"},
      {"e_vt.obj", TRI3 "f 1/x 2 3\n", 4, "bad texture/normal index"},
      {"e_slash.obj", TRI3 "f 1/1/1/1 2 3\n", 4, "too many '/'"},
      {"e_stmt.obj", TRI3 "vx 1 2 3\n", 4, "unknown OBJ statement 'vx'"},
      {"e_many.obj", "v 1 2 3 4 5 6 7 8\n", 1, "vertex with 8 values"},
      {"e_empty.obj", "", 0, "empty file"},
      {"e_blank.obj", "# only\n\n# comments\n", 3, "empty file"},
      {"e_novert.obj", "o thing\ng group\n", 2, "no vertices"},
      {"e_hdr.obj", "4 1\n" TRI3 "f 1 2 3\n", 1, "header counts 4 vertices, 1 faces"},
      {NULL, NULL, 0, NULL}};
  tb_test_expect_read_errors(c);
  tb_test_expect_read_error(tb_test_file("e_nul.obj", "v 0 0 0\nv 1\0 0 0\n", 16), 2, "NUL byte");
}

#define OFF3 "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n"
static void test_errors_off(void) {
  static const tb_test_bad_file c[] = {
      {"e_empty.off", "", 0, "empty file"},
      {"e_magic.off", "PLY\n3 1 0\n", 1, "not an OFF file"},
      {"e_variant.off", "4OFF\n3 1 0\n", 1, "unsupported OFF variant '4OFF'"},
      {"e_count.off", "OFF\nthree 1 0\n", 2, "vertex count 'three' is not an integer"},
      {"e_negcount.off", "OFF\n3 -1 0\n", 2, "face count -1 out of range"},
      {"e_truncv.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n", 4,
       "unexpected end of file (expected vertex 3 of 3)"},
      {"e_truncf.off", OFF3, 5, "unexpected end of file (expected face 1 of 1)"},
      {"e_extra.off", OFF3 "3 0 1 2\n3 0 1 2\n", 7, "unexpected data after the last face"},
      {"e_range.off", OFF3 "3 0 1 3\n", 6, "vertex index 3 out of range (0..2)"},
      {"e_negidx.off", OFF3 "3 0 -1 2\n", 6, "vertex index -1 out of range"},
      {"e_nan.off", "OFF\n3 1 0\n0 0 0\n1 NaN 0\n0 1 0\n3 0 1 2\n", 4, "'NaN' is not finite"},
      {"e_inf.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 infinity\n3 0 1 2\n", 5, "is not finite"},
      {"e_text.off", "OFF\n3 1 0\n0 0 0\n1 0 zero\n", 4, "'zero' is not a number"},
      {"e_vextra.off", "OFF\n3 1 0\n0 0 0 5\n", 3, "unexpected '5'"},
      {"e_fsize.off", OFF3 "2 0 1\n", 6, "face with 2 vertices"},
      {"e_fshort.off", OFF3 "4 0 1 2\n", 6, "missing vertex index"},
      {"e_huge.off", "OFF\n2000000000 2000000000 0\n0 0 0\n", 3, "expected vertex 2 of 2000000000"},
      {"e_big.off", "OFF\n99999999999 1 0\n", 2, "vertex count 99999999999 out of range"},
      {NULL, NULL, 0, NULL}};
  tb_test_expect_read_errors(c);
}

#define FACET(v)                                                                      \
  " facet normal 0 0 1\n  outer loop\n   vertex 0 0 0\n   vertex 1 0 0\n   vertex " v \
  "\n  endloop\n endfacet\n"
static void test_errors_stl(void) {
  static const tb_test_bad_file c[] = {
      {"e_empty.stl", "", 0, "empty file"},
      {"e_magic.stl", "hello world\n", 1, "not an STL file"},
      {"e_trunc.stl",
       "solid t\n facet normal 0 0 1\n  outer loop\n   vertex 0 0 0\n   vertex 1 0 0\n", 5,
       "unexpected end of file (expected 'vertex')"},
      {"e_noend.stl", "solid t\n" FACET("0 1 0"), 8, "expected 'facet' or 'endsolid'"},
      {"e_nan.stl", "solid t\n" FACET("0 nan 0") "endsolid\n", 6, "'nan' is not finite"},
      {"e_text.stl", "solid t\n" FACET("0 1 z") "endsolid\n", 6, "'z' is not a number"},
      {"e_few.stl", "solid t\n" FACET("0 1") "endsolid\n", 6, "missing z coordinate"},
      {"e_loop.stl", "solid t\n facet normal 0 0 1\n   vertex 0 0 0\n", 3, "expected 'outer loop'"},
      {"e_four.stl",
       "solid t\n"
       " facet normal 0 0 1\n  outer loop\n   vertex 0 0 0\n   vertex 1 0 0\n"
       "   vertex 0 1 0\n   vertex 1 1 0\n  endloop\n endfacet\nendsolid\n",
       7, "expected 'endloop'"},
      {"e_kw.stl", "solid t\n" FACET("0 1 0") "facets\n", 9,
       "expected 'facet' or 'endsolid', found 'facets'"},
      {"e_after.stl", "solid t\n" FACET("0 1 0") "endsolid\nmore\n", 10,
       "expected 'solid' or end of file"},
      {"e_none.stl", "solid t\nendsolid t\n", 2, "no vertices"},
      {NULL, NULL, 0, NULL}};
  tb_test_expect_read_errors(c);
}

static void test_errors_stl_binary(void) {
  float v[18] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0};
  unsigned char buf[84 + 100];
  v[10] = NAN; /* triangle 2, vertex 1, y */
  long n = stl_binary(buf, v, 2, "binary");
  tb_test_expect_read_error(tb_test_file("e_nan_bin.stl", (const char *)buf, n), 0,
                            "triangle 2 (byte offset 146): coordinate not finite");
  v[10] = INFINITY;
  stl_binary(buf, v, 2, "binary");
  tb_test_expect_read_error(tb_test_file("e_inf_bin.stl", (const char *)buf, n), 0,
                            "triangle 2 (byte offset 146)");
  v[10] = 0;
  stl_binary(buf, v, 2, "binary");
  tb_test_expect_read_error(tb_test_file("e_trunc_bin.stl", (const char *)buf, n - 50), 1,
                            "134 bytes is not the 184 of a binary STL of 2 triangles");
  tb_test_expect_read_error(tb_test_file("e_zero_bin.stl", (const char *)buf, 84), 1,
                            "not an STL file");
  put_le32(buf + 80, 0);
  tb_test_expect_read_error(tb_test_file("e_none_bin.stl", (const char *)buf, 84), 0,
                            "binary STL with 0 triangles");
}

/* One TetGen case: the files base.node/.ele/.face (NULL: absent), the one read. */
typedef struct tg_case {
  const char *base, *node, *ele, *face, *read, *bad;
  long line;
  const char *reason;
} tg_case;

#define NODE4 "4 3 0 0\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n"
static void test_errors_tetgen(void) {
  static const tg_case c[] = {
      {"t1", "3 3 0 0\n1 0 0 0\n2 1 0 0\n", NULL, NULL, ".node", ".node", 3,
       "expected node 3 of 3"},
      {"t2", "2 3 0 0\n1 0 0 0\n3 1 0 0\n", NULL, NULL, ".node", ".node", 3,
       "node number 3 out of sequence"},
      {"t3", "1 3 0 0\n2 0 0 0\n", NULL, NULL, ".node", ".node", 2,
       "first node number 2 is not 0 or 1"},
      {"t4", "1 2 0 0\n1 0 0\n", NULL, NULL, ".node", ".node", 1, "dimension 2 out of range"},
      {"t5", "2 3 0 0\n1 0 0 0\n2 1 -nan 0\n", NULL, NULL, ".node", ".node", 3,
       "'-nan' is not finite"},
      {"t6", "1 3 0 0\n1 0 zero 0\n", NULL, NULL, ".node", ".node", 2, "'zero' is not a number"},
      {"t7", "1 3 0 0\n1 0 0 0\n2 1 0 0\n", NULL, NULL, ".node", ".node", 3,
       "unexpected data after the last node"},
      {"t8", "1 3 1 1\n1 0 0 0 5\n", NULL, NULL, ".node", ".node", 2, "missing boundary marker"},
      {"t9", "", NULL, NULL, ".node", ".node", 0, "empty file"},
      {"t10", NODE4, "1 4 0\n1 1 2 3 9\n", NULL, ".node", ".ele", 2,
       "node index 9 out of range (1..4)"},
      {"t11", NODE4, "1 4 0\n# zero-based index in a 1-based set\n1 0 1 2 3\n", NULL, ".ele",
       ".ele", 3, "node index 0 out of range"},
      {"t12", NULL, "1 4 0\n1 1 2 3 4\n", NULL, ".ele", ".ele", 0, "missing companion"},
      {"t13", NODE4, "1 5 0\n1 1 2 3 4 4\n", NULL, ".ele", ".ele", 1, "5 nodes per tetrahedron"},
      {"t14", NODE4, "2 4 0\n1 1 2 3 4\n", NULL, ".ele", ".ele", 2, "expected tetrahedron 2 of 2"},
      {"t15", NODE4, "1 4 1\n1 1 2 3 4\n", NULL, ".ele", ".ele", 2,
       "missing tetrahedron attribute"},
      {"t16", NODE4, "1 4 0\n1 1 2 3 4\n", "1 1\n1 1 2 3\n", ".node", ".face", 2,
       "0 values after the face's nodes"},
      {"t17", NODE4, "1 4 0\n1 1 2 3 4\n", "1 0\n1 1 2 5\n", ".node", ".face", 2,
       "node index 5 out of range"},
      {"t18", "2147483647 3 0 0\n1 0 0 0\n", NULL, NULL, ".node", ".node", 2,
       "expected node 2 of 2147483647"},
      {NULL, NULL, NULL, NULL, NULL, NULL, 0, NULL}};
  static const char *const ext[3] = {".node", ".ele", ".face"};
  char name[64];
  for (const tg_case *t = c; t->base; t++) {
    const char *text[3] = {t->node, t->ele, t->face};
    for (int k = 0; k < 3; k++) {
      snprintf(name, sizeof name, "%s%s", t->base, ext[k]);
      if (text[k]) tb_test_file(name, text[k], -1);
    }
    snprintf(name, sizeof name, "%s%s", t->base, t->read);
    const char *path = tb_test_tmp_path(name);
    snprintf(name, sizeof name, "%s%s", t->base, t->bad);
    tb_mesh m;
    tb_error err = {{0}};
    char prefix[700];
    if (t->line)
      snprintf(prefix, sizeof prefix, "%s:%ld: ", tb_test_tmp_path(name), t->line);
    else
      snprintf(prefix, sizeof prefix, "%s: ", tb_test_tmp_path(name));
    TB_CHECK_MSG(tb_mesh_read(path, &m, &err) != 0, "%s should fail", path);
    TB_CHECK_MSG(strncmp(err.msg, prefix, strlen(prefix)) == 0 && strstr(err.msg, t->reason),
                 "message '%s', expected '%s...%s'", err.msg, prefix, t->reason);
    TB_CHECK(m.nv == 0 && !m.x && !m.tet && !m.tri);
  }
}

#define MSH2 "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n"
#define NOD3 "$NOD\n3\n1 0 0 0\n2 1 0 0\n3 0 1 0\n$ENDNOD\n"
static void test_errors_msh(void) {
  static const tb_test_bad_file c[] = {
      {"e_empty.msh", "", 0, "empty file"},
      {"e_top.msh", "hello\n", 1, "expected a $Section, found 'hello'"},
      {"e_bin.msh", "$MeshFormat\n4.1 1 8\n", 2, "binary .msh not supported"},
      {"e_v40.msh", "$MeshFormat\n4 0 8\n$EndMeshFormat\n", 2, "unsupported .msh version 4"},
      {"e_v3.msh", "$MeshFormat\n3.0 0 8\n$EndMeshFormat\n", 2, "unsupported .msh version 3"},
      {"e_trunc.msh", "$NOD\n2\n1 0 0 0\n", 3, "unexpected end of file (expected node 2 of 2)"},
      {"e_trelm.msh", NOD3 "$ELM\n1\n1 2 0 1 3 1 2 3\n", 9,
       "unexpected end of file (expected $ENDELM)"},
      {"e_tag.msh", NOD3 "$ELM\n1\n1 2 0 1 3 1 2 99\n$ENDELM\n", 9, "unknown node tag 99"},
      {"e_nan.msh", "$NOD\n1\n1 0 nan 0\n$ENDNOD\n", 3, "y coordinate 'nan' is not finite"},
      {"e_text.msh", "$NOD\n1\n1 0 0 O\n$ENDNOD\n", 3, "z coordinate 'O' is not a number"},
      {"e_tagtext.msh", "$NOD\n1\n1.5 0 0 0\n$ENDNOD\n", 3, "node tag '1.5' is not an integer"},
      {"e_few.msh", "$NOD\n1\n1 0 0 0\n2 1 0 0\n$ENDNOD\n", 4, "expected $ENDNOD, found '2'"},
      {"e_many.msh", "$NOD\n3\n1 0 0 0\n2 1 0 0\n$ENDNOD\n", 5, "section ends after 2 of 3 nodes"},
      {"e_nn.msh", NOD3 "$ELM\n1\n1 4 0 1 3 1 2 3\n$ENDELM\n", 9,
       "element type 4 has 4 nodes, not 3"},
      {"e_dup.msh", "$NOD\n2\n1 0 0 0\n1 1 0 0\n$ENDNOD\n", 4, "duplicate node tag 1"},
      {"e_order.msh", MSH2 "$Elements\n0\n$EndElements\n", 4, "elements before nodes"},
      {"e_nofmt.msh", "$Nodes\n0\n$EndNodes\n", 1, "$Nodes without $MeshFormat"},
      {"e_mix.msh", MSH2 "$NOD\n0\n$ENDNOD\n", 4,
       "legacy (version 1) section $NOD in a version 2 file: the legacy and the new format mixed"},
      {"e_skip.msh", MSH2 "$Comments\nhello\n", 5, "expected $EndComments"},
      {"e_v2elm.msh",
       MSH2 "$Nodes\n3\n1 0 0 0\n2 1 0 0\n3 0 1 0\n$EndNodes\n$Elements\n1\n1 2 2 0 1 1 2\n"
            "$EndElements\n",
       12, "missing node tag"},
      {"e_v4sum.msh",
       "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\n1 3 1 2\n0 1 0 2\n1\n2\n0 0 0\n1 0 0\n"
       "$EndNodes\n",
       5, "header says 3 nodes, the blocks hold 2"},
      {"e_v4blk.msh",
       "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\n2 1 1 1\n0 1 0 1\n1\n0 0 0\n$EndNodes\n", 9,
       "section ends after 1 of 2 node blocks"},
      {"e_huge.msh", "$NOD\n2147483647\n1 0 0 0\n", 3, "expected node 2 of 2147483647"},
      {"e_none.msh", MSH2, 3, "no vertices"},
      {NULL, NULL, 0, NULL}};
  tb_test_expect_read_errors(c);
}

static void test_errors_generic(void) {
  tb_test_expect_read_error(tb_test_file("mesh.ply", "ply\n", -1), 0, "unknown mesh format '.ply'");
  tb_test_expect_read_error(tb_test_file("noext", "v 0 0 0\n", -1), 0, "unknown mesh format ''");
  tb_test_expect_read_error(tb_test_tmp_path("missing.obj"), 0, "cannot open: No such file");
  tb_test_expect_read_error(tb_test_tmp_path("missing.node"), 0, "cannot open: No such file");
  long n = (1L << 20) + 100;
  char *big = malloc((size_t)n + 1);
  if (!big) return;
  memcpy(big, "v 0 0 0\nv ", 10);
  memset(big + 10, '1', (size_t)n - 10);
  big[n] = 0;
  tb_test_expect_read_error(tb_test_file("long.obj", big, n), 2, "line longer than");
  free(big);
}

/* ---- real meshes from ../shared/data ---- */

static int real(const char *rel, tb_mesh *m) {
  char path[1024];
  snprintf(path, sizeof path, "%s/../shared/data/%s", tb_test_source_root(), rel);
  if (access(path, R_OK) != 0) {
    tb_test_skip("%s absent (../shared/data not present)", path);
    return 0;
  }
  return read_ok(path, m);
}

static void check_real(const char *rel, int nv, int ntri, int ntet, int nskip) {
  tb_mesh m;
  if (!real(rel, &m)) return;
  TB_CHECK_MSG(m.nv == nv && m.ntri == ntri && m.ntet == ntet && m.nskipped == nskip,
               "%s: %d v, %d tri, %d tet, %d skipped", rel, m.nv, m.ntri, m.ntet, m.nskipped);
  if (m.ntet > 0) TB_CHECK_MSG(tb_mesh_min_tet_volume(&m) > 0, "%s: inverted tet", rel);
  tb_mesh_free(&m);
}

static void test_sofa_msh(void) {
  check_real("sofa/liver.msh", 181, 0, 596, 0);
  check_real("sofa/liver2.msh", 507, 860, 1493, 71);
  check_real("sofa/cylinder.msh", 510, 0, 2430, 0);
}

static void test_sofa_obj(void) {
  check_real("sofa/liver.obj", 181, 274, 0, 0);
  check_real("sofa/dental_instrument.obj", 1100, 2178, 0, 0);
}

static void test_fcl_obj(void) {
  check_real("fcl/env.obj", 6540, 2180, 0, 0);
  check_real("fcl/rob.obj", 648, 216, 0, 0);
}

/* Drops the vertices no triangle uses, renumbering in order (in place). */
static void drop_unused(tb_mesh *m) {
  int *map = calloc((size_t)m->nv + 1, sizeof *map), n = 0;
  if (!map) return;
  for (int i = 0; i < 3 * m->ntri; i++) map[m->tri[i]] = 1;
  for (int i = 0; i < m->nv; i++)
    if (map[i]) m->x[n] = m->x[i], map[i] = n++;
  for (int i = 0; i < 3 * m->ntri; i++) m->tri[i] = map[m->tri[i]];
  m->nv = n;
  free(map);
}

/* liver.obj through OBJ (less its 42 unused vertices) and liver2.msh through
 * .node/.ele/.face, exactly. */
static void test_real_roundtrip(void) {
  tb_mesh m, r;
  if (real("sofa/liver.obj", &m)) {
    TB_CHECK(tb_mesh_topology(&m).closed);
    if (write_ok(tb_test_tmp_path("liver.obj"), &m) && read_ok(tb_test_tmp_path("liver.obj"), &r)) {
      drop_unused(&m);
      TB_CHECK(m.nv == 139);
      check_same(&r, &m), tb_mesh_free(&r);
    }
    tb_mesh_free(&m);
  }
  if (real("sofa/liver2.msh", &m)) {
    m.nskipped = 0;
    if (write_ok(tb_test_tmp_path("liver2.node"), &m) &&
        read_ok(tb_test_tmp_path("liver2.ele"), &r))
      check_same(&r, &m), tb_mesh_free(&r);
    tb_mesh_free(&m);
  }
}

const tb_test_case tb_tests_io[] = {{"obj_polygons_fan", test_obj_polygons},
                                    {"obj_indices", test_obj_indices},
                                    {"obj_fcl_header", test_obj_fcl_header},
                                    {"off_reader", test_off_reader},
                                    {"stl_ascii_merge", test_stl_ascii},
                                    {"stl_binary", test_stl_binary},
                                    {"tetgen_one_based", test_tetgen_one_based},
                                    {"tetgen_zero_based", test_tetgen_zero_based},
                                    {"msh_v1", test_msh_v1},
                                    {"msh_v2", test_msh_v2},
                                    {"msh_v4", test_msh_v4},
                                    {"roundtrip_surface", test_roundtrip_surface},
                                    {"roundtrip_tetgen", test_roundtrip_tetgen},
                                    {"write_tet_boundary", test_write_tet_boundary},
                                    {"write_vtk", test_write_vtk},
                                    {"write_surface_compact", test_write_surface_compact},
                                    {"write_errors", test_write_errors},
                                    {"errors_obj", test_errors_obj},
                                    {"errors_off", test_errors_off},
                                    {"errors_stl", test_errors_stl},
                                    {"errors_stl_binary", test_errors_stl_binary},
                                    {"errors_tetgen", test_errors_tetgen},
                                    {"errors_msh", test_errors_msh},
                                    {"errors_generic", test_errors_generic},
                                    {"sofa_msh", test_sofa_msh},
                                    {"sofa_obj", test_sofa_obj},
                                    {"fcl_obj", test_fcl_obj},
                                    {"real_roundtrip", test_real_roundtrip},
                                    {0, 0}};
