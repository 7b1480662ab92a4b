/* VTK output and input: .vtu pieces with point and cell arrays written and
 * parsed back bit for bit (mesh and arrays), the exact base64 layout, .pvd
 * collections, legacy .vtk round trips, and malformed .vtu and .vtk files
 * rejected with "FILE:LINE: reason". */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "tb_test.h"
#include "core/tb_mesh_io.h"
#include "core/tb_vtu.h"
#include "meshgen/tb_meshgen.h"

/* 1-based line of the first occurrence of needle in s (0 if absent). */
static long line_of(const char *s, const char *needle) {
  const char *p = strstr(s, needle);
  if (!p) return 0;
  long n = 1;
  for (const char *q = s; q < p; q++) n += *q == '\n';
  return n;
}

/* s with the first `from` replaced by `to` (static buffer). */
static const char *replaced(const char *s, const char *from, const char *to) {
  static char out[1 << 20];
  const char *p = strstr(s, from);
  TB_CHECK_MSG(p != NULL, "'%s' not in the file", from);
  if (!p) return s;
  snprintf(out, sizeof out, "%.*s%s%s", (int)(p - s), s, to, p + strlen(from));
  return out;
}

/* ---- a two-piece scene: a beam (tets + boundary triangles) with arrays,
 * and a loose surface without any ---- */
typedef struct scene {
  tb_mesh beam;
  tb_vec3 *disp, sx[4];
  double *strain;
  unsigned char *inverted;
  int stri[6];
  tb_vtu_array arrays[3];
  tb_vtu_piece pieces[2];
} scene;

static int scene_make(scene *s) {
  tb_error err;
  memset(s, 0, sizeof *s);
  if (tb_beam(2, 1, 1, 2, 1, 1, &s->beam, &err)) return -1;
  const tb_mesh *b = &s->beam;
  int ncell = b->ntet + b->ntri;
  s->disp = malloc(sizeof *s->disp * (size_t)b->nv);
  s->strain = malloc(sizeof *s->strain * (size_t)ncell);
  s->inverted = malloc((size_t)ncell);
  for (int i = 0; i < b->nv; i++) s->disp[i] = tb_v3(i / 3.0, -1e-300 * i, i ? 1.0 / i : -0.0);
  for (int i = 0; i < ncell; i++) s->strain[i] = sqrt(i + 0.5), s->inverted[i] = i % 3 == 1;
  s->arrays[0] = (tb_vtu_array){"displacement", 3, &s->disp[0].x, NULL, 0};
  s->arrays[1] = (tb_vtu_array){"strain", 1, s->strain, NULL, 1};
  s->arrays[2] = (tb_vtu_array){"inverted", 1, NULL, s->inverted, 1};
  for (int i = 0; i < 4; i++) s->sx[i] = tb_v3(5 + (i & 1), 0.25 * (i >> 1), M_PI);
  static const int tri[6] = {0, 1, 3, 0, 3, 2};
  memcpy(s->stri, tri, sizeof tri);
  s->pieces[0] = (tb_vtu_piece){b->nv, b->x, b->ntri, b->tri, b->ntet, b->tet, 3, s->arrays};
  s->pieces[1] = (tb_vtu_piece){4, s->sx, 2, s->stri, 0, NULL, 0, NULL};
  return 0;
}

static void scene_free(scene *s) {
  tb_mesh_free(&s->beam);
  free(s->disp), free(s->strain), free(s->inverted);
}

static int write_scene(const char *path, scene *s) {
  tb_error err = {{0}};
  int rc = tb_vtu_write(path, s->pieces, 2, &err);
  TB_CHECK_MSG(rc == 0, "writing %s: %s", path, err.msg);
  return rc;
}

static void test_vtu_roundtrip(void) {
  scene s;
  if (scene_make(&s) || write_scene(tb_test_tmp_path("scene.vtu"), &s)) return;
  const tb_mesh *b = &s.beam;
  tb_mesh m;
  tb_error err = {{0}};
  TB_CHECK_MSG(tb_mesh_read(tb_test_tmp_path("scene.vtu"), &m, &err) == 0, "%s", err.msg);
  TB_CHECK_MSG(m.nv == b->nv + 4 && m.ntet == b->ntet && m.ntri == b->ntri + 2 && !m.nskipped,
               "%d v, %d tets, %d tris", m.nv, m.ntet, m.ntri);
  if (m.nv == b->nv + 4 && m.ntet == b->ntet && m.ntri == b->ntri + 2) {
    TB_CHECK(memcmp(m.x, b->x, sizeof *b->x * (size_t)b->nv) == 0);
    TB_CHECK(memcmp(m.x + b->nv, s.sx, sizeof s.sx) == 0);
    TB_CHECK(memcmp(m.tet, b->tet, sizeof(int) * 4 * (size_t)b->ntet) == 0);
    TB_CHECK(memcmp(m.tri, b->tri, sizeof(int) * 3 * (size_t)b->ntri) == 0);
    for (int i = 0; i < 6; i++) TB_CHECK(m.tri[3 * b->ntri + i] == s.stri[i] + b->nv);
  }
  tb_mesh_free(&m);
  scene_free(&s);
}

/* "VTU files parse back to the same arrays": point and cell arrays, bit for
 * bit, with zeros where the second piece has none. */
static void test_vtu_arrays_parse_back(void) {
  scene s;
  if (scene_make(&s) || write_scene(tb_test_tmp_path("arrays.vtu"), &s)) return;
  const tb_mesh *b = &s.beam;
  int ncell = b->ntet + b->ntri;
  tb_mesh m;
  tb_error err = {{0}};
  tb_vtu_field f = {"displacement", 0, 0, 0, NULL};
  TB_CHECK_MSG(tb_vtu_read(tb_test_tmp_path("arrays.vtu"), &m, &f, &err) == 0, "%s", err.msg);
  TB_CHECK_MSG(f.ncomp == 3 && f.ntuples == b->nv + 4, "%d x %d", f.ncomp, f.ntuples);
  if (f.ntuples == b->nv + 4) {
    TB_CHECK(memcmp(f.data, s.disp, sizeof *s.disp * (size_t)b->nv) == 0);
    for (int i = 3 * b->nv; i < 3 * f.ntuples; i++) TB_CHECK(f.data[i] == 0);
  }
  free(f.data);
  tb_mesh_free(&m);
  f = (tb_vtu_field){"strain", 1, 0, 0, NULL};
  TB_CHECK_MSG(tb_vtu_read(tb_test_tmp_path("arrays.vtu"), &m, &f, &err) == 0, "%s", err.msg);
  TB_CHECK_MSG(f.ncomp == 1 && f.ntuples == ncell + 2, "%d x %d", f.ncomp, f.ntuples);
  if (f.ntuples == ncell + 2)
    TB_CHECK(memcmp(f.data, s.strain, sizeof *s.strain * (size_t)ncell) == 0 && f.data[ncell] == 0);
  free(f.data);
  tb_mesh_free(&m);
  f = (tb_vtu_field){"inverted", 1, 0, 0, NULL};
  TB_CHECK_MSG(tb_vtu_read(tb_test_tmp_path("arrays.vtu"), &m, &f, &err) == 0, "%s", err.msg);
  for (int i = 0; i < ncell && f.ntuples == ncell + 2; i++)
    TB_CHECK(f.data[i] == (s.inverted[i] ? 1.0 : 0.0));
  free(f.data);
  tb_mesh_free(&m);
  /* a point-data request does not find cell data, nor an unknown name */
  f = (tb_vtu_field){"strain", 0, 0, 0, NULL};
  TB_CHECK(tb_vtu_read(tb_test_tmp_path("arrays.vtu"), &m, &f, &err) != 0 &&
           strstr(err.msg, "no point-data"));
  TB_CHECK(f.data == NULL && m.nv == 0);
  f = (tb_vtu_field){"velocity", 0, 0, 0, NULL};
  TB_CHECK(tb_vtu_read(tb_test_tmp_path("arrays.vtu"), &m, &f, &err) != 0 &&
           strstr(err.msg, "velocity"));
  scene_free(&s);
}

/* The layout ParaView reads: header attributes, UInt64 byte-count headers
 * encoded with the data, tets then triangles. */
static void test_vtu_layout(void) {
  tb_vec3 x[4] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  int tet[4] = {0, 1, 2, 3}, tri[3] = {0, 2, 1};
  double one[2] = {1, 2};
  tb_vtu_array a = {"a<&\"b", 1, one, NULL, 1};
  tb_vtu_piece p = {4, x, 1, tri, 1, tet, 1, &a};
  tb_error err = {{0}};
  TB_CHECK_MSG(tb_vtu_write(tb_test_tmp_path("one.vtu"), &p, 1, &err) == 0, "%s", err.msg);
  char *s = tb_test_slurp(tb_test_tmp_path("one.vtu"));
  if (!s) return;
  static const char head[] = "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\"";
  TB_CHECK(strncmp(s, head, strlen(head)) == 0);
  TB_CHECK(strstr(s, "byte_order=\"LittleEndian\" header_type=\"UInt64\""));
  TB_CHECK(strstr(s, "<Piece NumberOfPoints=\"4\" NumberOfCells=\"2\">"));
  TB_CHECK(strstr(s, "Name=\"a&lt;&amp;&quot;b\""));
  /* types: UInt64 2, then bytes 10 and 5 */
  TB_CHECK(strstr(s, "Name=\"types\" format=\"binary\">\n          AgAAAAAAAAAKBQ==\n"));
  TB_CHECK(!strstr(s, "compressor") && !strstr(s, "appended"));
  free(s);
}

static void test_vtu_write_errors(void) {
  tb_vec3 x[3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  int tri[3] = {0, 1, 3};
  double d[3] = {1, 2, 3};
  tb_vtu_array a[2] = {{"d", 1, d, NULL, 0}, {"d", 3, d, NULL, 0}};
  tb_vtu_piece p[2] = {{3, x, 1, tri, 0, NULL, 0, NULL}, {1, x, 0, NULL, 0, NULL, 1, a + 1}};
  tb_error err = {{0}};
  TB_CHECK(tb_vtu_write(tb_test_tmp_path("e.vtu"), p, 1, &err) != 0 &&
           strstr(err.msg, "uses point 3 of 3"));
  tri[2] = 2;
  p[0].narrays = 2, p[0].arrays = a;
  TB_CHECK(tb_vtu_write(tb_test_tmp_path("e.vtu"), p, 1, &err) != 0 &&
           strstr(err.msg, "'d' twice"));
  p[0].narrays = 1;
  TB_CHECK(tb_vtu_write(tb_test_tmp_path("e.vtu"), p, 2, &err) != 0 &&
           strstr(err.msg, "changes components"));
  TB_CHECK(tb_vtu_write("/nonexistent-dir/e.vtu", p, 1, &err) != 0 &&
           strstr(err.msg, "/nonexistent-dir/e.vtu: cannot open for writing"));
  TB_CHECK(tb_vtu_write(tb_test_tmp_path("e.vtu"), p, 0, &err) != 0);
}

static void test_pvd(void) {
  double t[3] = {0, 0.5, 1.0 / 3};
  const char *files[3] = {"f/frame_0000.vtu", "f/frame_0001.vtu", "f/a&b.vtu"};
  tb_error err = {{0}};
  TB_CHECK_MSG(tb_pvd_write(tb_test_tmp_path("run.pvd"), 3, t, files, &err) == 0, "%s", err.msg);
  char *s = tb_test_slurp(tb_test_tmp_path("run.pvd"));
  if (!s) return;
  TB_CHECK(strstr(s, "<VTKFile type=\"Collection\""));
  TB_CHECK(
      strstr(s,
             "<DataSet timestep=\"0\" group=\"\" part=\"0\" file=\"f/frame_0000.vtu\"/>\n"
             "    <DataSet timestep=\"0.5\" group=\"\" part=\"0\" file=\"f/frame_0001.vtu\"/>"));
  TB_CHECK(strstr(s, "timestep=\"0.33333333333333331\"") && strstr(s, "file=\"f/a&amp;b.vtu\""));
  free(s);
  t[1] = NAN;
  TB_CHECK(tb_pvd_write(tb_test_tmp_path("bad.pvd"), 3, t, files, &err) != 0 &&
           strstr(err.msg, "non-finite"));
}

/* s less the last base64 group of the Points array (static buffer). */
static const char *cut_points(const char *s) {
  static char out[1 << 20];
  const char *p = strstr(s, "<Points>"), *q = p ? strstr(p, "format=\"binary\">\n") : NULL;
  const char *e = q ? strchr(q + 18, '\n') : NULL;
  TB_CHECK(e != NULL);
  if (!e) return s;
  snprintf(out, sizeof out, "%.*s%s", (int)(e - 4 - s), s, e);
  return out;
}

/* Malformed .vtu files, made from a good one-tet file. */
static void test_vtu_errors(void) {
  tb_vec3 x[4] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  int tet[4] = {0, 1, 2, 3};
  tb_vtu_piece p = {4, x, 0, NULL, 1, tet, 0, NULL};
  tb_error err = {{0}};
  TB_CHECK_MSG(tb_vtu_write(tb_test_tmp_path("good.vtu"), &p, 1, &err) == 0, "%s", err.msg);
  char *good = tb_test_slurp(tb_test_tmp_path("good.vtu"));
  if (!good) return;
  static const char *types_tag = "Name=\"types\"";
  long points = line_of(good, "<Points>") + 1, types = line_of(good, types_tag);
  long conn = line_of(good, "Name=\"connectivity\""), offs = line_of(good, "Name=\"offsets\"");
  const char *t;
  /* unknown cell type 99 */
  t = replaced(good, "AQAAAAAAAAAK", "AQAAAAAAAABj");
  tb_test_expect_read_error(tb_test_file("e_type.vtu", t, -1), types, "unknown cell type 99");
  /* truncated base64: one character, then a whole group, of the types */
  t = replaced(good, "AQAAAAAAAAAK", "AQAAAAAAAAA");
  tb_test_expect_read_error(tb_test_file("e_b64.vtu", t, -1), types, "truncated base64 data");
  t = cut_points(good);
  tb_test_expect_read_error(tb_test_file("e_b64b.vtu", t, -1), points,
                            "Points: header says 96 bytes, the data holds 94 (truncated)");
  t = replaced(good, "AQAAAAAAAAAK", "AgAAAAAAAAAK");
  tb_test_expect_read_error(tb_test_file("e_b64d.vtu", t, -1), types,
                            "types: header says 2 bytes, the data holds 1 (truncated)");
  t = replaced(good, "AQAAAAAAAAAK", "AQAA*AAAAAAK");
  tb_test_expect_read_error(tb_test_file("e_b64c.vtu", t, -1), types + 1,
                            "invalid base64 data ('*')");
  /* wrong counts */
  t = replaced(good, "NumberOfPoints=\"4\"", "NumberOfPoints=\"5\"");
  tb_test_expect_read_error(tb_test_file("e_np.vtu", t, -1), points,
                            "4 tuples, the piece declares 5");
  t = replaced(good, "NumberOfCells=\"1\"", "NumberOfCells=\"2\"");
  tb_test_expect_read_error(tb_test_file("e_nc.vtu", t, -1), offs,
                            "offsets: 1 tuples, the piece declares 2");
  t = replaced(good, "NumberOfPoints=\"4\"", "NumberOfPoints=\"-4\"");
  tb_test_expect_read_error(tb_test_file("e_neg.vtu", t, -1), line_of(good, "<Piece"),
                            "NumberOfPoints=\"-4\" is not a count");
  /* unsupported variants, and not XML */
  t = replaced(good, "format=\"binary\"", "format=\"ascii\"");
  tb_test_expect_read_error(tb_test_file("e_ascii.vtu", t, -1), points,
                            "format 'ascii' not supported");
  t = replaced(good, "type=\"UnstructuredGrid\"", "type=\"PolyData\"");
  tb_test_expect_read_error(tb_test_file("e_poly.vtu", t, -1), 2,
                            "VTKFile type 'PolyData' not supported");
  t = replaced(good, "header_type=\"UInt64\"", "header_type=\"UInt64\" compressor=\"vtkZLib\"");
  tb_test_expect_read_error(tb_test_file("e_zlib.vtu", t, -1), 2, "compressed data");
  t = replaced(good, "Name=\"connectivity\"", "Name=\"connectivity\" type=\"Int64\"");
  tb_test_expect_read_error(tb_test_file("e_dupattr.vtu", t, -1), conn,
                            "XML error: duplicate attribute");
  t = replaced(good, "</Cells>", "");
  tb_test_expect_read_error(tb_test_file("e_xml.vtu", t, -1), line_of(good, "</Cells>") + 1,
                            "XML error: mismatched tag");
  tb_test_expect_read_error(tb_test_file("e_empty.vtu", "", -1), 0, "XML error: no element found");
  tb_test_expect_read_error(tb_test_file("e_root.vtu", "<mesh/>\n", -1), 1, "not a VTK XML file");
  free(good);
}

/* What VTK's own writer adds: a UInt32 header_type (also the default),
 * Int32 cells, InformationKey elements inside a DataArray, FieldData, and
 * a header encoded apart from its data ('=' padding mid-stream). */
static void test_vtu_vtk_style(void) {
  const char *p = tb_test_file(
      "vtkstyle.vtu",
      "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"0.1\" "
      "byte_order=\"LittleEndian\" header_type=\"UInt32\">\n<UnstructuredGrid>\n"
      "<FieldData><DataArray type=\"Float64\" Name=\"TIME\" NumberOfTuples=\"1\" "
      "format=\"ascii\">0.5</DataArray></FieldData>\n"
      "<Piece NumberOfPoints=\"3\" NumberOfCells=\"1\">\n<PointData>\n"
      "<DataArray type=\"Int32\" Name=\"s\" format=\"ascii\">1 2 3</DataArray>\n"
      "<DataArray type=\"Float32\" Name=\"v\" NumberOfComponents=\"3\" format=\"binary\">\n"
      "JAAAAA==AADAPwAAIEAAAIC/AAAAAAAAAAAAAAAAAADgQAAAAEEAABBB\n</DataArray>\n</"
      "PointData>\n<Points>\n"
      "<DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"binary\" RangeMin=\"0\">\n"
      "SAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAPA/AAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAA8D8A"
      "AAAAAADgPw==\n<InformationKey name=\"L2_NORM_RANGE\" location=\"vtkDataArray\" "
      "length=\"2\"><Value index=\"0\">0</Value></InformationKey>\n</DataArray>\n</Points>\n"
      "<Cells>\n<DataArray type=\"Int32\" Name=\"connectivity\" format=\"binary\">\n"
      "DAAAAAAAAAABAAAAAgAAAA==\n</DataArray>\n"
      "<DataArray type=\"Int32\" Name=\"offsets\" format=\"binary\">BAAAAAMAAAA=</DataArray>\n"
      "<DataArray type=\"UInt8\" Name=\"types\" format=\"binary\">AQAAAAU=</DataArray>\n"
      "</Cells>\n</Piece>\n</UnstructuredGrid>\n</VTKFile>\n",
      -1);
  tb_mesh m;
  tb_error err = {{0}};
  tb_vtu_field f = {"v", 0, 0, 0, NULL};
  if (tb_vtu_read(p, &m, &f, &err)) {
    TB_CHECK_MSG(0, "%s", err.msg);
    return;
  }
  TB_CHECK(m.nv == 3 && m.ntri == 1 && m.ntet == 0 && m.tri[2] == 2 && m.x[2].z == 0.5);
  TB_CHECK(f.ncomp == 3 && f.ntuples == 3 && f.data[0] == 1.5 && f.data[2] == -1 && f.data[8] == 9);
  free(f.data);
  tb_mesh_free(&m);
  /* an ASCII array is ignored unless asked for */
  f = (tb_vtu_field){"s", 0, 0, 0, NULL};
  TB_CHECK(tb_vtu_read(p, &m, &f, &err) != 0 && strstr(err.msg,
                                                       "vtkstyle.vtu:7: DataArray format "
                                                       "'ascii' not supported"));
}

/* ---- legacy VTK ---- */
static void same(const tb_mesh *a, const tb_mesh *b) {
  TB_CHECK_MSG(a->nv == b->nv && a->ntri == b->ntri && a->ntet == b->ntet,
               "counts %d/%d/%d vs %d/%d/%d", a->nv, a->ntri, a->ntet, b->nv, b->ntri, b->ntet);
  if (a->nv != b->nv || a->ntri != b->ntri || a->ntet != b->ntet) return;
  TB_CHECK(memcmp(a->x, b->x, sizeof *a->x * (size_t)a->nv) == 0);
  TB_CHECK(!a->ntri || memcmp(a->tri, b->tri, sizeof(int) * 3 * (size_t)a->ntri) == 0);
  TB_CHECK(!a->ntet || memcmp(a->tet, b->tet, sizeof(int) * 4 * (size_t)a->ntet) == 0);
}

static void test_vtk_roundtrip(void) {
  tb_mesh beam, m;
  tb_error err = {{0}};
  if (tb_beam(3, 1, 0.7, 3, 1, 1, &beam, &err)) return;
  beam.x[5].y += 1.0 / 3; /* a coordinate %.17g must carry exactly */
  tb_mesh tets = beam, surf = beam;
  tets.ntri = 0, surf.ntet = 0;
  const tb_mesh *src[2] = {&tets, &surf};
  const char *name[2] = {"rt_tets.vtk", "rt_surf.vtk"};
  for (int k = 0; k < 2; k++) {
    TB_CHECK_MSG(tb_mesh_write(tb_test_tmp_path(name[k]), src[k], &err) == 0, "%s", err.msg);
    if (tb_mesh_read(tb_test_tmp_path(name[k]), &m, &err)) {
      TB_CHECK_MSG(0, "%s", err.msg);
      continue;
    }
    same(&m, src[k]); /* the beam's surface uses every vertex */
    tb_mesh_free(&m);
  }
  tb_mesh_free(&beam);
}

static void test_vtk_reader(void) {
  tb_mesh m;
  tb_error err = {{0}};
  const char *p = tb_test_file("hand.vtk",
                               "# vtk DataFile Version 2.0\n\nascii\nDATASET POLYDATA\n"
                               "POINTS 5 float\n0 0 0 1 0 0\n1 1 0\n0 1 0 0.5 0.5 1\n"
                               "LINES 1 3\n2 0 1\nPOLYGONS 2 9\n4 0 1 2 3\n3 0 1 4\n"
                               "POINT_DATA 5\nSCALARS s float\nLOOKUP_TABLE default\n1 2 3 4 5\n",
                               -1);
  if (tb_mesh_read(p, &m, &err) == 0) {
    int want[9] = {0, 1, 2, 0, 2, 3, 0, 1, 4};
    TB_CHECK(m.nv == 5 && m.ntri == 3 && m.ntet == 0 && m.nskipped == 1);
    TB_CHECK(m.ntri == 3 && memcmp(m.tri, want, sizeof want) == 0 && m.x[4].z == 1);
    tb_mesh_free(&m);
  } else {
    TB_CHECK_MSG(0, "%s", err.msg);
  }
  p = tb_test_file("hand2.vtk",
                   "# vtk DataFile Version 3.0\ngrid\nASCII\nDATASET UNSTRUCTURED_GRID\n"
                   "POINTS 4 double\n0 0 0\n1 0 0\n0 1 0\n0 0 1\nCELLS 3 14\n4 0 1 2 3\n3 0 2 1\n"
                   "4 0 1 2 3\nCELL_TYPES 3\n10\n5\n9\n",
                   -1);
  if (tb_mesh_read(p, &m, &err) == 0) {
    TB_CHECK(m.nv == 4 && m.ntet == 1 && m.ntri == 1 && m.nskipped == 1 && m.tri[1] == 2);
    tb_mesh_free(&m);
  } else {
    TB_CHECK_MSG(0, "%s", err.msg);
  }
}

#define VHDR "# vtk DataFile Version 3.0\nt\nASCII\nDATASET UNSTRUCTURED_GRID\n"
#define VPTS "POINTS 4 double\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n"
static void test_vtk_errors(void) {
  static const struct {
    const char *name, *text;
    long line;
    const char *reason;
  } c[] = {
      {"v_type.vtk", VHDR VPTS "CELLS 1 5\n4 0 1 2 3\nCELL_TYPES 1\n99\n", 13,
       "unknown cell type 99"},
      {"v_size.vtk", VHDR VPTS "CELLS 1 6\n4 0 1 2 3\nCELL_TYPES 1\n10\n", 11,
       "list size 6, but its 1 cells hold 5 numbers"},
      {"v_ntypes.vtk", VHDR VPTS "CELLS 1 5\n4 0 1 2 3\nCELL_TYPES 2\n10\n10\n", 12,
       "cell type count 2 out of range (1..1)"},
      {"v_npts.vtk", VHDR "POINTS 3 double\n0 0 0\n1 0 0\n", 7,
       "unexpected end of file (expected point 3 of 3)"},
      {"v_idx.vtk", VHDR VPTS "CELLS 1 5\n4 0 1 2 4\n", 11, "point index 4 out of range (0..3)"},
      {"v_tetsize.vtk", VHDR VPTS "CELLS 1 4\n3 0 1 2\nCELL_TYPES 1\n10\n", 13,
       "cell 0 of type 10 has 3 points, not 4"},
      {"v_notypes.vtk", VHDR VPTS "CELLS 1 5\n4 0 1 2 3\n", 11, "CELLS without CELL_TYPES"},
      {"v_nan.vtk", VHDR "POINTS 1 double\n0 nan 0\n", 6, "'nan' is not finite"},
      {"v_bin.vtk", "# vtk DataFile Version 3.0\nt\nBINARY\n", 3, "binary legacy VTK"},
      {"v_magic.vtk", "hello\n", 1, "not a legacy VTK file"},
      {"v_set.vtk", "# vtk DataFile Version 3.0\nt\nASCII\nDATASET STRUCTURED_POINTS\n", 4,
       "DATASET STRUCTURED_POINTS not supported"},
      {"v_kw.vtk", VHDR VPTS "POLYGONS 1 4\n3 0 1 2\n", 10, "unexpected 'POLYGONS'"},
      {"v_none.vtk", VHDR, 4, "no vertices"},
      {NULL, NULL, 0, NULL}};
  for (int i = 0; c[i].name; i++)
    tb_test_expect_read_error(tb_test_file(c[i].name, c[i].text, -1), c[i].line, c[i].reason);
}

/* mesh info reads both, and reports a bad .vtu with FILE:LINE, exit 2. */
static void test_vtu_cli(void) {
  scene s;
  if (scene_make(&s) || write_scene(tb_test_tmp_path("cli.vtu"), &s)) return;
  char args[1024], want[800];
  snprintf(args, sizeof args, "mesh info %s", tb_test_tmp_path("cli.vtu"));
  TB_CHECK_MSG(tb_test_cli_run(args) == 0, "%s", tb_test_out);
  snprintf(want, sizeof want, "vertices    %d\ntriangles   %d\ntets        %d\n", s.beam.nv + 4,
           s.beam.ntri + 2, s.beam.ntet);
  TB_CHECK_MSG(strstr(tb_test_out, want), "%s", tb_test_out);
  const char *bad = tb_test_file("cli_bad.vtu", "<VTKFile type=\"UnstructuredGrid\">\n<x>\n", -1);
  snprintf(args, sizeof args, "mesh info %s", bad);
  TB_CHECK(tb_test_cli_run(args) == 2);
  snprintf(want, sizeof want, "%s:2: XML error", bad);
  TB_CHECK_MSG(strstr(tb_test_out, want), "%s", tb_test_out);
  snprintf(args, sizeof args, "mesh beam --out %s && '%s' mesh info %s",
           tb_test_tmp_path("cli.vtk"), tb_test_cli(), tb_test_tmp_path("cli.vtk"));
  TB_CHECK_MSG(tb_test_cli_run(args) == 0 && strstr(tb_test_out, "tets        480"), "%s",
               tb_test_out);
  scene_free(&s);
}

const tb_test_case tb_tests_vtu[] = {
    {"vtu_roundtrip", test_vtu_roundtrip},
    {"vtu_arrays_parse_back", test_vtu_arrays_parse_back},
    {"vtu_layout", test_vtu_layout},
    {"vtu_write_errors", test_vtu_write_errors},
    {"pvd", test_pvd},
    {"vtu_errors", test_vtu_errors},
    {"vtu_vtk_style", test_vtu_vtk_style},
    {"vtk_roundtrip", test_vtk_roundtrip},
    {"vtk_reader", test_vtk_reader},
    {"vtk_errors", test_vtk_errors},
    {"vtu_cli", test_vtu_cli},
    {0, 0},
};
