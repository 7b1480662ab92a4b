/* Mesh readers against hostile input: the
 * coordinate bound in every format, a second $Elements, upper-case TetGen
 * extensions, byte-order marks, a "solid" binary STL with a wrong count,
 * paths that are not regular files, mixed legacy/new .msh, escaped message
 * text, end-of-file lines, and the inputs once silently accepted (OFF
 * counts, Gmsh tags, TetGen duplicates, junk after STL keywords). Each
 * case checks the reader contract: on error "FILE[:LINE]: " and an empty
 * mesh; on success every coordinate tb_coord_ok and every index in range. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "tb_test.h"
#include "core/tb_mesh_io.h"
#include "core/tb_spheres.h"
#include "core/tb_vtu.h"

/* Reads path expecting success and the contract; returns the mesh (caller frees). */
static tb_mesh read_good(const char *path, int nv, int ntri, int ntet) {
  tb_mesh m;
  tb_error err = {{0}};
  int rc = tb_mesh_read(path, &m, &err);
  TB_CHECK_MSG(rc == 0, "reading %s: %s", path, err.msg);
  if (rc) return m;
  TB_CHECK_MSG(m.nv == nv && m.ntri == ntri && m.ntet == ntet, "%s: %d/%d/%d, expected %d/%d/%d",
               path, m.nv, m.ntri, m.ntet, nv, ntri, ntet);
  for (int i = 0; i < m.nv; i++) TB_CHECK(tb_coord_ok(m.x[i]));
  for (int i = 0; i < 3 * m.ntri; i++) TB_CHECK(m.tri[i] >= 0 && m.tri[i] < m.nv);
  for (int i = 0; i < 4 * m.ntet; i++) TB_CHECK(m.tet[i] >= 0 && m.tet[i] < m.nv);
  return m;
}

#define TRI3 "v 0 0 0\nv 1 0 0\nv 0 1 0\n"
#define MSH2 "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n"
#define MSH4 "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n"
#define NOD3 "$NOD\n3\n1 0 0 0\n2 1 0 0\n3 0 1 0\n$ENDNOD\n"
#define NODES3 "$Nodes\n3\n1 0 0 0\n2 1 0 0\n3 0 1 0\n$EndNodes\n"
#define ELEMS1 "$Elements\n1\n1 2 0 1 2 3\n$EndElements\n"
#define VHDR "# vtk DataFile Version 3.0\nt\nASCII\nDATASET POLYDATA\n"
#define FACET(v2)                                                                      \
  " facet normal 0 0 1\n  outer loop\n   vertex 0 0 0\n   vertex 1 0 0\n   vertex " v2 \
  "\n"                                                                                 \
  "  endloop\n endfacet\n"

/* ---- coordinates beyond TB_COORD_MAX in every format ---- */
static void test_coord_bound(void) {
  static const tb_test_bad_file c[] = {
      {"c_item1.obj", "v 1e200 0 0\nv 0 1e200 0\nv 0 0 1e200\nf 1 2 3\n", 1, "beyond +-1e+90"},
      {"c_neg.obj", TRI3 "v 0 0 -1.0000001e90\n", 4, "vertex 4"},
      {"c.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1e91 0\n3 0 1 2\n", 5, "beyond +-1e+90"},
      {"c.stl", "solid t\n" FACET("0 1e300 0") "endsolid t\n", 6, "beyond +-1e+90"},
      {"c1.msh", "$NOD\n3\n1 0 0 0\n2 1 0 0\n3 0 -1e300 0\n$ENDNOD\n", 5, "beyond +-1e+90"},
      {"c2.msh", MSH2 "$Nodes\n1\n1 1e100 0 0\n$EndNodes\n", 6, "beyond +-1e+90"},
      {"c4.msh", MSH4 "$Nodes\n1 1 1 1\n0 1 0 1\n1\n0 0 2e90\n$EndNodes\n", 8, "beyond +-1e+90"},
      {"c.vtk", VHDR "POINTS 3 double\n0 0 0\n1 0 0\n0 1\n1e95\nPOLYGONS 1 4\n3 0 1 2\n", 9,
       "beyond +-1e+90"},
      {0, 0, 0, 0}};
  tb_test_expect_read_errors(c);
  /* a closed tetrahedron at +-1e300, as TetGen files */
  tb_test_file("c_tet.node",
               "4 3 0 0\n1 1e300 1e300 1e300\n2 -1e300 -1e300 1e300\n"
               "3 -1e300 1e300 -1e300\n4 1e300 -1e300 -1e300\n",
               -1);
  tb_test_file("c_tet.ele", "1 4 0\n1 1 2 3 4\n", -1);
  tb_test_expect_read_error(tb_test_tmp_path("c_tet.node"), 2, "beyond +-1e+90");
  tb_test_expect_read_error_in(tb_test_tmp_path("c_tet.ele"), tb_test_tmp_path("c_tet.node"), 2,
                               "beyond +-1e+90");
  /* the bound itself is accepted */
  tb_mesh m = read_good(tb_test_file("c_ok.obj", "v 1e90 -1e90 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", -1),
                        3, 1, 0);
  tb_mesh_free(&m);
  /* VTU, written by the project's own writer */
  tb_vec3 x[3] = {{0, 0, 0}, {1, 0, 0}, {0, 1e200, 0}};
  int tri[3] = {0, 1, 2};
  tb_vtu_piece p = {3, x, 1, tri, 0, NULL, 0, NULL};
  tb_error err = {{0}};
  if (tb_vtu_write(tb_test_tmp_path("c.vtu"), &p, 1, &err) == 0)
    tb_test_expect_read_error_in(tb_test_tmp_path("c.vtu"), tb_test_tmp_path("c.vtu"), -1,
                                 "is not finite or beyond +-1e+90");
  else
    TB_CHECK_MSG(strstr(err.msg, "c.vtu"), "%s", err.msg);
  /* and the CLI: exit 2 with the message */
  char args[800];
  snprintf(args, sizeof args, "mesh info %s", tb_test_tmp_path("c_item1.obj"));
  TB_CHECK_MSG(tb_test_cli_run(args) == 2 && strstr(tb_test_out, "c_item1.obj:1: "), "%s: %s", args,
               tb_test_out);
  snprintf(args, sizeof args, "mesh info %s", tb_test_tmp_path("c_tet.node"));
  TB_CHECK_MSG(tb_test_cli_run(args) == 2 && strstr(tb_test_out, "c_tet.node:2: ") &&
                   !strstr(tb_test_out, "nan"),
               "%s: %s", args, tb_test_out);
}

/* ---- a second $Elements section ---- */
static void test_msh_second_elements(void) {
  static const tb_test_bad_file c[] = {
      {"e2.msh", MSH2 NODES3 ELEMS1 ELEMS1, 14, "second element section"},
      {"e1.msh", NOD3 "$ELM\n1\n1 2 0 1 3 1 2 3\n$ENDELM\n$ELM\n0\n$ENDELM\n", 11,
       "second element section"},
      {"e4.msh",
       MSH4 "$Nodes\n1 3 1 3\n2 1 0 3\n1\n2\n3\n0 0 0\n1 0 0\n0 1 0\n$EndNodes\n"
            "$Elements\n1 1 1 1\n2 1 2 1\n1 1 2 3\n$EndElements\n"
            "$Elements\n1 1 1 1\n2 1 2 1\n1 1 2 3\n$EndElements\n",
       19, "second element section"},
      {0, 0, 0, 0}};
  tb_test_expect_read_errors(c);
  tb_mesh m = read_good(tb_test_file("e_one.msh", MSH2 NODES3 ELEMS1, -1), 3, 1, 0);
  tb_mesh_free(&m);
}

/* ---- upper-case TetGen extensions ---- */
static void test_tetgen_upper_case(void) {
  const char *node = "4 3 0 0\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n";
  tb_test_file("UP.NODE", node, -1);
  tb_test_file("UP.ELE", "1 4 0\n1 1 2 3 4\n", -1);
  tb_test_file("UP.FACE", "1 0\n1 1 2 3\n", -1);
  tb_mesh m = read_good(tb_test_tmp_path("UP.NODE"), 4, 1, 1);
  tb_mesh_free(&m);
  m = read_good(tb_test_tmp_path("UP.ELE"), 4, 1, 1);
  tb_mesh_free(&m);
  char args[800];
  snprintf(args, sizeof args, "mesh info %s", tb_test_tmp_path("UP.NODE"));
  TB_CHECK_MSG(tb_test_cli_run(args) == 0, "%s: %s", args, tb_test_out);
  /* lower case still reads lower-case partners */
  tb_test_file("lo.node", node, -1);
  tb_test_file("lo.ele", "1 4 0\n1 1 2 3 4\n", -1);
  m = read_good(tb_test_tmp_path("lo.ele"), 4, 0, 1);
  tb_mesh_free(&m);
  /* A.ELE without A.NODE names the upper-case partner */
  tb_test_file("NOPE.ELE", "1 4 0\n1 1 2 3 4\n", -1);
  tb_test_expect_read_error(tb_test_tmp_path("NOPE.ELE"), 0, "NOPE.NODE");
}

/* ---- byte-order marks ---- */
#define BOM "\xEF\xBB\xBF"
static void test_bom(void) {
  tb_mesh m;
  m = read_good(tb_test_file("b.obj", BOM TRI3 "f 1 2 3\n", -1), 3, 1, 0);
  tb_mesh_free(&m);
  m = read_good(tb_test_file("b.off", BOM "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n", -1), 3, 1,
                0);
  tb_mesh_free(&m);
  m = read_good(tb_test_file("b.stl", BOM "solid t\n" FACET("0 1 0") "endsolid t\n", -1), 3, 1, 0);
  tb_mesh_free(&m);
  m = read_good(tb_test_file("b.msh", BOM MSH2 NODES3 ELEMS1, -1), 3, 1, 0);
  tb_mesh_free(&m);
  m = read_good(tb_test_file("b1.msh", BOM NOD3, -1), 3, 0, 0);
  tb_mesh_free(&m);
  m = read_good(tb_test_file("b.vtk", BOM VHDR "POINTS 3 double\n0 0 0 1 0 0 0 1 0\n", -1), 3, 0,
                0);
  tb_mesh_free(&m);
  tb_test_file("bt.node", BOM "3 3 0 0\n1 0 0 0\n2 1 0 0\n3 0 1 0\n", -1);
  tb_test_file("bt.face", BOM "1 0\n1 1 2 3\n", -1);
  m = read_good(tb_test_tmp_path("bt.node"), 3, 1, 0);
  tb_mesh_free(&m);
  static const tb_test_bad_file c[] = {
      {"b_mid.obj", TRI3 BOM "f 1 2 3\n", 4, "byte-order mark inside the file"},
      {"b_two.obj", BOM BOM TRI3, 1, "byte-order mark inside the file"},
      {"b_mid.off", "OFF\n3 1 0\n0 0 0\n" BOM "1 0 0\n0 1 0\n3 0 1 2\n", 4,
       "byte-order mark inside the file"},
      {"b_mid.msh", MSH2 BOM NODES3, 4, "byte-order mark inside the file"},
      {0, 0, 0, 0}};
  tb_test_expect_read_errors(c);
  /* .sph files use the same tokenizer */
  tb_spheres s;
  tb_error err = {{0}};
  const char *p = tb_test_file("b.sph", BOM "sph 1.0\nsphe 1 0 0 0 1\n", -1);
  TB_CHECK_MSG(tb_spheres_read(p, &s, &err) == 0 && s.n == 1, "%s", err.msg);
  tb_spheres_free(&s);
  p = tb_test_file("b_mid.sph", "sph 1.0\nsphe 1 0 0 0 1" BOM "\n", -1);
  TB_CHECK(tb_spheres_read(p, &s, &err) != 0 && strstr(err.msg, "b_mid.sph:2: byte-order mark"));
}

/* ---- a binary STL whose header starts with "solid", wrong count ---- */
static void test_stl_solid_binary(void) {
  unsigned char buf[84 + 50 * 2];
  memset(buf, 0, sizeof buf);
  memcpy(buf, "solid exported by a CAD tool", 28);
  buf[80] = 3; /* says 3 triangles, holds 2 */
  const char *p = tb_test_file("sb.stl", (const char *)buf, sizeof buf);
  tb_test_expect_read_error(p, 0, "binary STL (its header starts with 'solid') of 3 triangles");
  tb_mesh m;
  tb_error err = {{0}};
  TB_CHECK(tb_mesh_read(p, &m, &err) != 0 && !strstr(err.msg, "NUL byte"));
  buf[80] = 2; /* the right count reads */
  m = read_good(tb_test_file("sb2.stl", (const char *)buf, sizeof buf), 1, 2, 0);
  tb_mesh_free(&m);
}

/* ---- paths that are not regular files ---- */
static void test_not_regular(void) {
  static const char *const names[] = {"d.stl", "d.obj", "d.off", "d.msh",
                                      "d.vtk", "d.vtu", "d.node"};
  for (size_t i = 0; i < sizeof names / sizeof names[0]; i++) {
    mkdir(tb_test_tmp_path(names[i]), 0700);
    tb_test_expect_read_error(tb_test_tmp_path(names[i]), 0, "is a directory");
  }
  char args[800];
  snprintf(args, sizeof args, "mesh info %s", tb_test_tmp_path("d.stl"));
  TB_CHECK_MSG(tb_test_cli_run(args) == 2 && strstr(tb_test_out, "is a directory") &&
                   !strstr(tb_test_out, "9223372036854775807"),
               "%s: %s", args, tb_test_out);
  /* a FIFO: refused at once, never waited on */
  const char *fifo = tb_test_tmp_path("fifo.obj");
  if (mkfifo(fifo, 0600) == 0)
    tb_test_expect_read_error(fifo, 0, "not a regular file");
  else
    tb_test_fail(__FILE__, __LINE__, "mkfifo %s failed", fifo);
  /* a directory beside a TetGen .node where the .ele should be */
  tb_test_file("dd.node", "3 3 0 0\n1 0 0 0\n2 1 0 0\n3 0 1 0\n", -1);
  mkdir(tb_test_tmp_path("dd.ele"), 0700);
  tb_test_expect_read_error_in(tb_test_tmp_path("dd.node"), tb_test_tmp_path("dd.ele"), 0,
                               "is a directory");
}

/* ---- the legacy and the new .msh format mixed ---- */
static void test_msh_mixed(void) {
  static const tb_test_bad_file c[] = {
      {"mx1.msh", NOD3 MSH2, 7, "the legacy (version 1) and the new format mixed"},
      {"mx2.msh", NOD3 NODES3, 7, "the legacy (version 1) and the new format mixed"},
      {"mx3.msh", MSH2 NOD3, 4, "the legacy and the new format mixed"},
      {0, 0, 0, 0}};
  tb_test_expect_read_errors(c);
  tb_test_expect_read_error(tb_test_file("mx4.msh", MSH2 MSH2, -1), 4, "second $MeshFormat");
}

/* ---- file text in messages is escaped ---- */
static void test_escaped_messages(void) {
  static const tb_test_bad_file c[] = {
      {"x_esc.obj", TRI3 "\x1b[31mred 1 2 3\n", 4, "unknown OBJ statement '\\x1B[31mred'"},
      {"x_bad.obj", TRI3 "v 1 \xff\xfe 3\n", 4, "y coordinate '\\xFF\\xFE' is not a number"},
      {"x_c1.obj",
       "v 1 2 \xc2\x9b"
       "31m\n",
       1, "'\\xC2\\x9B31m' is not a number"},
      {"x_bel.off", "OFF\n3 1 0\n0 0 0\n1 0 \a\n", 4, "'\\x07' is not a number"},
      {"x_utf8.obj", "v 1 2 caf\xc3\xa9\n", 1, "'caf\xc3\xa9' is not a number"},
      {0, 0, 0, 0}};
  tb_test_expect_read_errors(c);
  /* the whole message is free of control bytes, and the quoted text stays short */
  char big[300] = "v 1 2 ";
  for (int i = 6; i < 250; i++) big[i] = (char)(i % 2 ? 0x1b : 0x07);
  big[250] = '\n';
  big[251] = 0;
  tb_mesh m;
  tb_error err = {{0}};
  TB_CHECK(tb_mesh_read(tb_test_file("x_long.obj", big, -1), &m, &err) != 0);
  for (const char *s = err.msg; *s; s++) TB_CHECK((unsigned char)*s >= 0x20 && *s != 0x7f);
  TB_CHECK_MSG(strlen(err.msg) < strlen(tb_test_tmp_path("x_long.obj")) + 40 + 4 * 40, "%s",
               err.msg);
}

/* ---- errors at end of file cite the last line, not one past it ---- */
static void test_eof_line(void) {
  static const tb_test_bad_file c[] = {
      {"z_nl.off", "OFF\n3 1 0\n0 0 0\n", 3, "unexpected end of file (expected vertex 2 of 3)"},
      {"z_nonl.off", "OFF\n3 1 0\n0 0 0", 3, "unexpected end of file (expected vertex 2 of 3)"},
      {"z_blank.off", "OFF\n3 1 0\n0 0 0\n\n\n", 5, "unexpected end of file"},
      {"z_msh.msh", MSH2 "$Nodes\n1\n1 0 0 0\n", 6, "expected $EndNodes"},
      {"z_stl.stl", "solid t\n" FACET("0 1 0"), 8, "unexpected end of file"},
      {"z_empty.obj", "", 0, "empty file"},
      {"z_comment.obj", "# a\n# b\n", 2, "empty file"},
      {"z_nopiece.vtu",
       "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"1.0\">\n"
       "<UnstructuredGrid>\n</UnstructuredGrid>\n</VTKFile>\n",
       5, "no Piece"},
      {"z_trunc.vtu", "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\">\n<Unstr", 3,
       "XML error"},
      {"z_trunc2.vtu", "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\">\n", 2,
       "XML error: no element found"},
      {0, 0, 0, 0}};
  tb_test_expect_read_errors(c);
}

/* ---- inputs once silently accepted ---- */
static void test_off_counts(void) {
  static const tb_test_bad_file c[] = {
      {"o_ne.off", "OFF\n3 1 -1\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n", 2, "edge count -1 out of range"},
      {"o_nv.off", "OFF\n-3 1 0\n", 2, "vertex count -3 out of range"},
      {"o_nf.off", "OFF\n3 -1 0\n", 2, "face count -1 out of range"},
      {"o_nv2.off", "-3 1 0\n", 1, "vertex count -3 out of range"},
      {"o_ne2.off", "3 1 -5\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n", 1, "edge count -5 out of range"},
      {0, 0, 0, 0}};
  tb_test_expect_read_errors(c);
}

static void test_msh_tags(void) {
  static const tb_test_bad_file c[] = {
      {"t0_v1.msh", "$NOD\n2\n1 0 0 0\n0 1 0 0\n$ENDNOD\n", 4, "node tag 0 out of range"},
      {"tn_v2.msh", MSH2 "$Nodes\n1\n-4 0 0 0\n$EndNodes\n", 6, "node tag -4 out of range"},
      {"t0_v4.msh", MSH4 "$Nodes\n1 1 0 0\n0 1 0 1\n0\n0 0 0\n$EndNodes\n", 7,
       "node tag 0 out of range"},
      {0, 0, 0, 0}};
  tb_test_expect_read_errors(c);
}

static void test_tetgen_duplicates(void) {
  const char *node = "4 3 0 0\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n";
  tb_test_file("dup.node", node, -1);
  tb_test_file("dup.ele", "3 4 0\n1 1 2 3 4\n2 1 2 4 3\n1 2 1 3 4\n", -1);
  tb_test_expect_read_error_in(tb_test_tmp_path("dup.node"), tb_test_tmp_path("dup.ele"), 4,
                               "duplicate tetrahedron number 1 (also on line 2)");
  tb_test_file("dupf.node", node, -1);
  tb_test_file("dupf.face", "2 0\n7 1 2 3\n7 1 2 4\n", -1);
  tb_test_expect_read_error_in(tb_test_tmp_path("dupf.node"), tb_test_tmp_path("dupf.face"), 3,
                               "duplicate face number 7 (also on line 2)");
  tb_test_expect_read_error(tb_test_file("dupn.node", "2 3 0 0\n1 0 0 0\n1 1 0 0\n", -1), 3,
                            "node number 1 out of sequence");
  /* distinct numbers, in any order, still read */
  tb_test_file("okid.node", node, -1);
  tb_test_file("okid.ele", "2 4 0\n5 1 2 3 4\n2 1 2 4 3\n", -1);
  tb_mesh m = read_good(tb_test_tmp_path("okid.node"), 4, 0, 2);
  tb_mesh_free(&m);
}

static void test_stl_junk(void) {
  static const tb_test_bad_file c[] = {
      {"j_normal.stl",
       "solid t\n facet normal 0 0 1 junk\n  outer loop\n   vertex 0 0 0\n   vertex 1 0 0\n"
       "   vertex 0 1 0\n  endloop\n endfacet\nendsolid t\n",
       2, "unexpected 'junk' at end of line"},
      {"j_facet.stl",
       "solid t\n facet junk\n  outer loop\n   vertex 0 0 0\n   vertex 1 0 0\n"
       "   vertex 0 1 0\n  endloop\n endfacet\nendsolid t\n",
       2, "expected 'normal' after 'facet', found 'junk'"},
      {"j_outer.stl",
       "solid t\n facet normal 0 0 1\n  outer loop x\n   vertex 0 0 0\n   vertex 1 0 0\n"
       "   vertex 0 1 0\n  endloop\n endfacet\nendsolid t\n",
       3, "unexpected 'x' at end of line"},
      {"j_endloop.stl",
       "solid t\n facet normal 0 0 1\n  outer loop\n   vertex 0 0 0\n   vertex 1 0 0\n"
       "   vertex 0 1 0\n  endloop x\n endfacet\nendsolid t\n",
       7, "unexpected 'x' at end of line"},
      {"j_endfacet.stl",
       "solid t\n facet normal 0 0 1\n  outer loop\n   vertex 0 0 0\n   vertex 1 0 0\n"
       "   vertex 0 1 0\n  endloop\n endfacet 1 2\nendsolid t\n",
       8, "unexpected '1' at end of line"},
      {"j_endsolid.stl", "solid t\n" FACET("0 1 0") "endsolid t 1 2 3\n", 9,
       "unexpected 't 1 2 3' after 'endsolid'"},
      {0, 0, 0, 0}};
  tb_test_expect_read_errors(c);
  tb_mesh m;
  m = read_good(
      tb_test_file("j_ok1.stl", "solid my part\n" FACET("0 1 0") "endsolid my part\n", -1), 3, 1,
      0);
  tb_mesh_free(&m);
  m = read_good(tb_test_file("j_ok2.stl", "solid a\n" FACET("0 1 0") "endsolid b\n", -1), 3, 1, 0);
  tb_mesh_free(&m);
  m = read_good(tb_test_file("j_ok3.stl",
                             "solid\n facet\n  outer loop\n   vertex 0 0 0\n"
                             "   vertex 1 0 0\n   vertex 0 1 0\n  endloop\n"
                             " endfacet\nendsolid\nsolid b\n" FACET("0 2 0") "endsolid\n",
                             -1),
                4, 2, 0);
  tb_mesh_free(&m);
}

const tb_test_case tb_tests_io_hostile[] = {{"coord_bound", test_coord_bound},
                                            {"msh_second_elements", test_msh_second_elements},
                                            {"tetgen_upper_case", test_tetgen_upper_case},
                                            {"bom", test_bom},
                                            {"stl_solid_binary", test_stl_solid_binary},
                                            {"not_regular", test_not_regular},
                                            {"msh_mixed", test_msh_mixed},
                                            {"escaped_messages", test_escaped_messages},
                                            {"eof_line", test_eof_line},
                                            {"off_counts", test_off_counts},
                                            {"msh_tags", test_msh_tags},
                                            {"tetgen_duplicates", test_tetgen_duplicates},
                                            {"stl_junk", test_stl_junk},
                                            {0, 0}};
