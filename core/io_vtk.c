/* VTK legacy reader ("VTK File Formats", Kitware, simple legacy formats),
 * ASCII only, as core/io_write.c writes it and a bit more: the "# vtk
 * DataFile Version" line, a title line, ASCII, then DATASET
 * UNSTRUCTURED_GRID (POINTS, CELLS, CELL_TYPES: tets (10) and triangles (5)
 * kept, other known types counted as skipped) or POLYDATA (POINTS and
 * POLYGONS, fan-triangulated; VERTICES, LINES and TRIANGLE_STRIPS skipped).
 * Numbers may wrap across lines. Reading stops at POINT_DATA / CELL_DATA
 * (attributes are not mesh data). */
#include <limits.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "io_internal.h"

typedef struct cells {
  int *idx; /* per cell: its size, then its indices */
  int cap, n, ncell, seen;
} cells;

/* The next token, on this line or a later one. */
static char *next(tb_lex *lx, const char *what) {
  if (tb_lex_left(lx) == 0 && tb_lex_need(lx, what)) return NULL;
  return tb_lex_word(lx);
}
static int next_range(tb_lex *lx, long *v, long lo, long hi, const char *what) {
  if (tb_lex_left(lx) == 0 && tb_lex_need(lx, what)) return -1;
  return tb_lex_range(lx, v, lo, hi, what);
}
static int next_real(tb_lex *lx, double *v, const char *what) {
  if (tb_lex_left(lx) == 0 && tb_lex_need(lx, what)) return -1;
  return tb_lex_real(lx, v, what);
}

static int header(tb_lex *lx, int *grid) {
  if (tb_lex_need(lx, "'# vtk DataFile Version'")) return -1;
  if (strncasecmp(lx->cur, "# vtk DataFile Version", 22))
    return tb_lex_fail(lx, "not a legacy VTK file (expected '# vtk DataFile Version')");
  long first = lx->line;
  if (tb_lex_need(lx, "title line")) return -1;
  if (lx->line == first + 1 && tb_lex_need(lx, "ASCII or BINARY")) return -1; /* title read */
  char *w = tb_lex_word(lx);
  if (!strcasecmp(w, "BINARY")) return tb_lex_fail(lx, "binary legacy VTK not supported");
  if (strcasecmp(w, "ASCII") || tb_lex_end(lx))
    return tb_lex_fail(lx, "expected ASCII or BINARY, found '%.40s'", w);
  if (!(w = next(lx, "DATASET")) || strcasecmp(w, "DATASET"))
    return w ? tb_lex_fail(lx, "expected DATASET, found '%.40s'", w) : -1;
  if (!(w = next(lx, "data set type"))) return -1;
  *grid = !strcasecmp(w, "UNSTRUCTURED_GRID");
  if (!*grid && strcasecmp(w, "POLYDATA"))
    return tb_lex_fail(lx, "DATASET %.40s not supported (UNSTRUCTURED_GRID or POLYDATA)", w);
  return tb_lex_end(lx);
}

static int points(tb_lex *lx, tb_build *b) {
  long n;
  if (b->m.nv) return tb_lex_fail(lx, "second POINTS section");
  if (tb_lex_range(lx, &n, 1, INT_MAX, "point count")) return -1;
  if (!tb_lex_word(lx)) return tb_lex_fail(lx, "POINTS needs a data type");
  if (tb_lex_end(lx)) return -1;
  for (long i = 0; i < n; i++) {
    tb_vec3 x;
    char what[3][40];
    for (int k = 0; k < 3; k++) snprintf(what[k], sizeof what[k], "point %ld of %ld", i + 1, n);
    if (next_real(lx, &x.x, what[0]) || next_real(lx, &x.y, what[1]) ||
        next_real(lx, &x.z, what[2]))
      return -1;
    if (tb_lex_vert(lx, b, x)) return -1;
  }
  return 0;
}

static int push(tb_lex *lx, cells *c, long v) {
  int *p = tb_io_grow(c->idx, &c->cap, (long)c->n + 1, sizeof *p);
  if (!p) return tb_lex_fail(lx, "out of memory");
  c->idx = p;
  p[c->n++] = (int)v;
  return 0;
}

/* A cell list "KEYWORD n size" then n lines "k i0 .. i(k-1)". */
static int read_cells(tb_lex *lx, const tb_build *b, const char *kw, cells *c) {
  long n, size, k, v;
  char what[80];
  if (!b->m.nv) return tb_lex_fail(lx, "%s before POINTS", kw);
  if (c->seen++) return tb_lex_fail(lx, "second %s section", kw);
  if (tb_lex_range(lx, &n, 0, INT_MAX, "cell count") ||
      tb_lex_range(lx, &size, 0, LONG_MAX, "list size") || tb_lex_end(lx))
    return -1;
  for (long i = 0; i < n; i++) {
    snprintf(what, sizeof what, "%s cell %ld of %ld", kw, i + 1, n);
    if (next_range(lx, &k, 1, 1000, what) || push(lx, c, k)) return -1;
    for (long j = 0; j < k; j++)
      if (next_range(lx, &v, 0, b->m.nv - 1L, "point index") || push(lx, c, v)) return -1;
  }
  c->ncell = (int)n;
  if (c->n != size)
    return tb_lex_fail(lx, "%s list size %ld, but its %ld cells hold %d numbers", kw, size, n,
                       c->n);
  return 0;
}

/* Points per cell of the VTK types skipped (0: any), -1 unknown. */
static int skipped_type(long t) {
  static const int npts[] = {-1, 1,  0,  2, 0, 3, 0,  0,  4,  4,  4, 8,  8,  6, 5,  -1, -1, -1,
                             -1, -1, -1, 3, 6, 8, 10, 20, 15, 13, 9, 27, 18, 6, 10, 12, 7,  13};
  return t >= 0 && t < (long)(sizeof npts / sizeof npts[0]) ? npts[t] : -1;
}

static int cell_types(tb_lex *lx, tb_build *b, const cells *c) {
  long n, t;
  if (!c->seen) return tb_lex_fail(lx, "CELL_TYPES before CELLS");
  if (tb_lex_range(lx, &n, c->ncell, c->ncell, "cell type count") || tb_lex_end(lx)) return -1;
  const int *p = c->idx;
  for (long i = 0; i < n; i++, p += 1 + p[0]) {
    char what[60];
    snprintf(what, sizeof what, "cell type %ld of %ld", i + 1, n);
    if (next_range(lx, &t, 0, 255, what)) return -1;
    int want = t == 10 ? 4 : t == 5 ? 3 : skipped_type(t);
    if (want < 0) return tb_lex_fail(lx, "unknown cell type %ld (reads 10 tetra, 5 triangle)", t);
    if (want > 0 && p[0] != want)
      return tb_lex_fail(lx, "cell %ld of type %ld has %d points, not %d", i, t, p[0], want);
    int bad = t == 10 ? tb_build_tet(b, p + 1) : t == 5 ? tb_build_tri(b, p[1], p[2], p[3]) : 0;
    if (bad) return tb_lex_fail(lx, "out of memory");
    if (t != 10 && t != 5) b->m.nskipped++;
  }
  return 0;
}

static int polygons(tb_lex *lx, tb_build *b, const cells *c) {
  const int *p = c->idx;
  for (int i = 0; i < c->ncell; i++, p += 1 + p[0]) {
    if (p[0] < 3) return tb_lex_fail(lx, "polygon %d has %d points", i, p[0]);
    for (int k = 2; k < p[0]; k++)
      if (tb_build_tri(b, p[1], p[k], p[k + 1])) return tb_lex_fail(lx, "out of memory");
  }
  return 0;
}

static int body(tb_lex *lx, tb_build *b, int grid) {
  cells c[1];
  memset(c, 0, sizeof c);
  int rc = 0, typed = 0;
  for (;;) {
    int r = tb_lex_line(lx);
    if (r <= 0) {
      rc = r;
      break;
    }
    char *w = tb_lex_word(lx);
    if (!strcasecmp(w, "POINT_DATA") || !strcasecmp(w, "CELL_DATA")) break;
    if (!strcasecmp(w, "POINTS")) {
      rc = points(lx, b);
    } else if (grid && !strcasecmp(w, "CELLS")) {
      rc = read_cells(lx, b, "CELLS", &c[0]);
    } else if (grid && !strcasecmp(w, "CELL_TYPES")) {
      rc = typed++ ? tb_lex_fail(lx, "second CELL_TYPES section") : cell_types(lx, b, &c[0]);
    } else if (!grid && !strcasecmp(w, "POLYGONS")) {
      rc = read_cells(lx, b, "POLYGONS", &c[0]);
      if (rc == 0) rc = polygons(lx, b, &c[0]);
    } else if (!grid && (!strcasecmp(w, "VERTICES") || !strcasecmp(w, "LINES") ||
                         !strcasecmp(w, "TRIANGLE_STRIPS"))) {
      cells skip = {0};
      rc = read_cells(lx, b, w, &skip);
      b->m.nskipped += skip.ncell;
      free(skip.idx);
    } else {
      rc = tb_lex_fail(lx, "unexpected '%.40s' in a %s data set", w,
                       grid ? "UNSTRUCTURED_GRID" : "POLYDATA");
    }
    if (rc) break;
  }
  if (rc == 0 && grid && c[0].seen && !typed) rc = tb_lex_fail(lx, "CELLS without CELL_TYPES");
  free(c[0].idx);
  return rc;
}

int tb_read_vtk(const char *path, tb_build *b, tb_error *err) {
  tb_lex lx;
  int grid = 0;
  if (tb_lex_open(&lx, path, 0, err)) return -1;
  int rc = header(&lx, &grid);
  if (rc == 0) rc = body(&lx, b, grid);
  if (rc == 0) rc = tb_lex_done(&lx, b);
  tb_lex_close(&lx);
  return rc;
}
