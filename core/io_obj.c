/* Wavefront OBJ reader (Wavefront "Object Files" appendix B1): "v x y z [w]"
 * and "f" statements; polygons are fan-triangulated; indices may be
 * v, v/vt, v/vt/vn or v//vn, and negative (relative to the last vertex).
 * Texture, normal, grouping and material statements are ignored; points,
 * lines and free-form curves/surfaces are counted in nskipped. FCL's meshes
 * start with a line "nv nf", which is checked against the data. */
#include <string.h>

#include "io_internal.h"

static const char *const ignored[] = {
    "vt",         "vn",        "vp",    "o",     "g",      "s",        "usemtl",   "mtllib",
    "cstype",     "deg",       "bmat",  "step",  "parm",   "trim",     "hole",     "scrv",
    "sp",         "end",       "con",   "mg",    "bevel",  "c_interp", "d_interp", "lod",
    "shadow_obj", "trace_obj", "ctech", "stech", "usemap", "maplib",   NULL};
static const char *const skipped[] = {"p", "l", "curv", "curv2", "surf", NULL};

static int listed(const char *const *list, const char *w) {
  for (; *list; list++)
    if (!strcmp(*list, w)) return 1;
  return 0;
}

/* One face corner "v[/vt[/vn]]" to a 0-based vertex index. */
static int corner(tb_lex *lx, char *tok, int nv, int *out) {
  char *part[3] = {tok, NULL, NULL};
  for (int k = 1; k < 3; k++) {
    char *s = strchr(part[k - 1], '/');
    if (!s) break;
    *s = 0;
    part[k] = s + 1;
  }
  if (part[2] && strchr(part[2], '/')) return tb_lex_fail(lx, "bad face corner: too many '/'");
  long v, t;
  for (int k = 1; k < 3; k++)
    if (part[k] && *part[k] && tb_parse_long(part[k], &t))
      return tb_lex_fail(lx, "bad texture/normal index '%.40s'", part[k]);
  int r = tb_parse_long(part[0], &v);
  if (r) return tb_lex_fail(lx, "vertex index '%.40s' is not an integer", part[0]);
  long i = v < 0 ? nv + v : v - 1;
  if (v == 0 || i < 0 || i >= nv)
    return tb_lex_fail(lx, "vertex index %ld out of range (%d vertices so far)", v, nv);
  *out = (int)i;
  return 0;
}

static int face(tb_lex *lx, tb_build *b) {
  int n = tb_lex_left(lx), first, prev, cur;
  if (n < 3) return tb_lex_fail(lx, "face with %d vertices (need at least 3)", n);
  if (corner(lx, tb_lex_word(lx), b->m.nv, &first) || corner(lx, tb_lex_word(lx), b->m.nv, &prev))
    return -1;
  for (int k = 2; k < n; k++) {
    if (corner(lx, tb_lex_word(lx), b->m.nv, &cur)) return -1;
    if (tb_build_tri(b, first, prev, cur)) return tb_lex_fail(lx, "out of memory");
    prev = cur;
  }
  return 0;
}

static int vertex(tb_lex *lx, tb_build *b) {
  tb_vec3 x;
  double extra;
  if (tb_lex_real(lx, &x.x, "x coordinate") || tb_lex_real(lx, &x.y, "y coordinate") ||
      tb_lex_real(lx, &x.z, "z coordinate"))
    return -1;
  int n = tb_lex_left(lx);
  if (n > 4) return tb_lex_fail(lx, "vertex with %d values (expected 3 to 7)", n + 3);
  for (int k = 0; k < n; k++)
    if (tb_lex_real(lx, &extra, "vertex weight/colour")) return -1;
  return tb_lex_vert(lx, b, x);
}

/* FCL's leading "nv nf" line: 1 when the line is one (counts stored). */
static int fcl_header(tb_lex *lx, const char *w, long hdr[2]) {
  if (tb_parse_long(w, &hdr[0]) || tb_lex_left(lx) != 1) return 0;
  return tb_lex_long(lx, &hdr[1], "face count") ? -1 : 1;
}

int tb_read_obj(const char *path, tb_build *b, tb_error *err) {
  tb_lex lx;
  if (tb_lex_open(&lx, path, '#', err)) return -1;
  long hdr[2] = {-1, -1}, hdr_line = 0, nface = 0;
  int r = 0, rc = 0;
  while (rc == 0 && (r = tb_lex_line(&lx)) > 0) {
    char *w = tb_lex_word(&lx);
    if (!strcmp(w, "v")) {
      rc = vertex(&lx, b);
    } else if (!strcmp(w, "f")) {
      rc = face(&lx, b);
      nface++;
    } else if (listed(skipped, w)) {
      b->m.nskipped++;
    } else if (!listed(ignored, w)) {
      int h = hdr_line == 0 && b->m.nv == 0 && nface == 0 ? fcl_header(&lx, w, hdr) : 0;
      if (h > 0)
        hdr_line = lx.line;
      else
        rc = h < 0 ? -1 : tb_lex_fail(&lx, "unknown OBJ statement '%.40s'", w);
    }
  }
  if (rc == 0 && r < 0) rc = -1;
  if (rc == 0) rc = tb_lex_done(&lx, b);
  if (rc == 0 && hdr_line && (hdr[0] != b->m.nv || hdr[1] != nface)) {
    lx.line = hdr_line;
    rc = tb_lex_fail(&lx, "header counts %ld vertices, %ld faces but the file has %d and %ld",
                     hdr[0], hdr[1], b->m.nv, nface);
  }
  tb_lex_close(&lx);
  return rc;
}
