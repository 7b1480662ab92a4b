/* Object File Format reader (Geomview's OFF): an optional header keyword
 * [ST][C][N]OFF, the counts "nv nf [ne]", nv vertex lines "x y z [...]" and
 * nf face lines "n i0 ... i(n-1) [colour]" with 0-based indices; polygons
 * are fan-triangulated. The counts are checked: a short file or data after
 * the last face is an error. */
#include <limits.h>
#include <string.h>

#include "io_internal.h"

/* Reads the keyword and counts; *extra: vertex lines may carry more values. */
static int header(tb_lex *lx, long *nv, long *nf, int *extra) {
  long ne;
  if (tb_lex_need(lx, "OFF header")) return -1;
  char *w = tb_lex_word(lx);
  size_t n = strlen(w);
  int kw = n >= 3 && !strcmp(w + n - 3, "OFF");
  if (kw) {
    if (strspn(w, "STCN") != n - 3) return tb_lex_fail(lx, "unsupported OFF variant '%.40s'", w);
    *extra = n > 3;
    if (tb_lex_left(lx) == 0 && tb_lex_need(lx, "vertex and face counts")) return -1;
  } else if (tb_parse_long(w, nv)) {
    return tb_lex_fail(lx, "not an OFF file: expected 'OFF' or counts, found '%.40s'", w);
  } else if (*nv < 0 || *nv > INT_MAX) {
    return tb_lex_fail(lx, "vertex count %ld out of range (0..%d)", *nv, INT_MAX);
  }
  if ((kw && tb_lex_range(lx, nv, 0, INT_MAX, "vertex count")) ||
      tb_lex_range(lx, nf, 0, INT_MAX, "face count") ||
      (tb_lex_left(lx) > 0 && tb_lex_range(lx, &ne, 0, LONG_MAX, "edge count")))
    return -1;
  return tb_lex_end(lx);
}

static int vertex(tb_lex *lx, tb_build *b, long i, long nv, int extra) {
  tb_vec3 x;
  double e;
  if (tb_lex_item(lx, i, nv, "vertex") || tb_lex_real(lx, &x.x, "x coordinate") ||
      tb_lex_real(lx, &x.y, "y coordinate") || tb_lex_real(lx, &x.z, "z coordinate"))
    return -1;
  while (extra && tb_lex_left(lx) > 0)
    if (tb_lex_real(lx, &e, "vertex colour/normal")) return -1;
  if (tb_lex_end(lx)) return -1;
  return tb_lex_vert(lx, b, x);
}

static int face(tb_lex *lx, tb_build *b, long j, long nf) {
  long n, v[3];
  double c;
  if (tb_lex_item(lx, j, nf, "face") || tb_lex_long(lx, &n, "face size")) return -1;
  if (n < 3) return tb_lex_fail(lx, "face with %ld vertices (need at least 3)", n);
  for (long k = 0; k < n; k++) {
    if (tb_lex_range(lx, &v[k < 2 ? k : 2], 0, b->m.nv - 1L, "vertex index")) return -1;
    if (k >= 2 && tb_build_tri(b, (int)v[0], (int)v[1], (int)v[2]))
      return tb_lex_fail(lx, "out of memory");
    if (k >= 2) v[1] = v[2];
  }
  if (tb_lex_left(lx) > 4)
    return tb_lex_fail(lx, "too many values after the face's %ld indices", n);
  while (tb_lex_left(lx) > 0)
    if (tb_lex_real(lx, &c, "face colour")) return -1;
  return 0;
}

int tb_read_off(const char *path, tb_build *b, tb_error *err) {
  tb_lex lx;
  long nv = 0, nf = 0;
  int extra = 0, rc;
  if (tb_lex_open(&lx, path, '#', err)) return -1;
  rc = header(&lx, &nv, &nf, &extra);
  for (long i = 0; rc == 0 && i < nv; i++) rc = vertex(&lx, b, i, nv, extra);
  for (long j = 0; rc == 0 && j < nf; j++) rc = face(&lx, b, j, nf);
  if (rc == 0) rc = tb_lex_trailing(&lx, "the last face");
  if (rc == 0) rc = tb_lex_done(&lx, b);
  tb_lex_close(&lx);
  return rc;
}
