/* TetGen's .node, .ele and .face files (TetGen 1.5 manual, section 5.2).
 * .node: "n 3 nattr nmark", then "id x y z [attributes] [marker]"; the first
 * id (0 or 1) sets the numbering every file uses. .ele: "n 4|10 nattr", then
 * "id v0 .. v3 [6 more] [attributes]" (corners kept). .face: "n nmark", then
 * "id a b c [marker] [2 adjacent tets]". Reading foo.node also reads foo.ele
 * and foo.face when present; reading foo.ele needs foo.node. */
#include <errno.h>
#include <limits.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>

#include "io_internal.h"

static int read_node(tb_lex *lx, tb_build *b, long *base) {
  long n, dim, nattr = 0, nmark = 0, id, k;
  double a;
  if (tb_lex_need(lx, "node count line") || tb_lex_range(lx, &n, 1, INT_MAX, "node count") ||
      tb_lex_range(lx, &dim, 3, 3, "dimension") ||
      (tb_lex_left(lx) && tb_lex_range(lx, &nattr, 0, 1000, "attribute count")) ||
      (tb_lex_left(lx) && tb_lex_range(lx, &nmark, 0, 1, "boundary marker count")) ||
      tb_lex_end(lx))
    return -1;
  for (long i = 0; i < n; i++) {
    tb_vec3 x;
    if (tb_lex_item(lx, i, n, "node") || tb_lex_long(lx, &id, "node number")) return -1;
    if (i == 0 && id != 0 && id != 1)
      return tb_lex_fail(lx, "first node number %ld is not 0 or 1", id);
    if (i == 0) *base = id;
    if (id != *base + i)
      return tb_lex_fail(lx, "node number %ld out of sequence (expected %ld)", id, *base + i);
    if (tb_lex_real(lx, &x.x, "x coordinate") || tb_lex_real(lx, &x.y, "y coordinate") ||
        tb_lex_real(lx, &x.z, "z coordinate"))
      return -1;
    for (k = 0; k < nattr; k++)
      if (tb_lex_real(lx, &a, "node attribute")) return -1;
    if ((nmark && tb_lex_long(lx, &k, "boundary marker")) || tb_lex_end(lx)) return -1;
    if (tb_lex_vert(lx, b, x)) return -1;
  }
  return tb_lex_trailing(lx, "the last node");
}

/* Element numbers read so far, with their lines, to refuse duplicates. */
typedef struct elem_id {
  long id, line;
} elem_id;

static int cmp_id(const void *a, const void *b) {
  const elem_id *x = a, *y = b;
  return x->id != y->id ? (x->id > y->id) - (x->id < y->id)
                        : (x->line > y->line) - (x->line < y->line);
}

/* Error at the later line of the first duplicate number among the n in ids. */
static int check_ids(tb_lex *lx, elem_id *ids, long n, const char *what) {
  if (n < 2) return 0;
  qsort(ids, (size_t)n, sizeof *ids, cmp_id);
  long dup = -1;
  for (long i = 1; i < n; i++)
    if (ids[i].id == ids[i - 1].id && (dup < 0 || ids[i].line < ids[dup].line)) dup = i;
  if (dup < 0) return 0;
  lx->line = ids[dup].line;
  return tb_lex_fail(lx, "duplicate %s number %ld (also on line %ld)", what, ids[dup].id,
                     ids[dup - 1].line);
}

/* Reads the line of element i of n: its number (to (*ids)[i], grown with
 * *cap) and nc node indices (to v, 0-based). */
static int indices(tb_lex *lx, const tb_build *b, long base, long i, long n, int nc, int *v,
                   elem_id **ids, int *cap) {
  long id, t;
  elem_id *p = tb_io_grow(*ids, cap, i + 1, sizeof *p);
  if (!p) return tb_lex_fail(lx, "out of memory");
  *ids = p;
  if (tb_lex_item(lx, i, n, nc == 3 ? "face" : "tetrahedron") ||
      tb_lex_long(lx, &id, "element number"))
    return -1;
  p[i] = (elem_id){id, lx->line};
  for (int k = 0; k < nc; k++) {
    if (tb_lex_range(lx, &t, base, base + b->m.nv - 1, "node index")) return -1;
    v[k] = (int)(t - base);
  }
  return 0;
}

static int read_ele(tb_lex *lx, tb_build *b, long base) {
  long n, npt, nattr = 0;
  int v[10];
  double a;
  if (tb_lex_need(lx, "tetrahedron count line") ||
      tb_lex_range(lx, &n, 0, INT_MAX, "tetrahedron count") ||
      tb_lex_long(lx, &npt, "nodes per tetrahedron") ||
      (tb_lex_left(lx) && tb_lex_range(lx, &nattr, 0, 1000, "attribute count")) || tb_lex_end(lx))
    return -1;
  if (npt != 4 && npt != 10)
    return tb_lex_fail(lx, "%ld nodes per tetrahedron (expected 4 or 10)", npt);
  elem_id *ids = NULL;
  int cap = 0, rc = 0;
  for (long i = 0; rc == 0 && i < n; i++) {
    rc = indices(lx, b, base, i, n, (int)npt, v, &ids, &cap);
    for (long k = 0; rc == 0 && k < nattr; k++) rc = tb_lex_real(lx, &a, "tetrahedron attribute");
    if (rc == 0) rc = tb_lex_end(lx);
    if (rc == 0 && tb_build_tet(b, v)) rc = tb_lex_fail(lx, "out of memory");
  }
  if (rc == 0) rc = tb_lex_trailing(lx, "the last tetrahedron");
  if (rc == 0) rc = check_ids(lx, ids, n, "tetrahedron");
  free(ids);
  return rc;
}

static int read_face(tb_lex *lx, tb_build *b, long base) {
  long n, nmark = 0, t;
  int v[3];
  if (tb_lex_need(lx, "face count line") || tb_lex_range(lx, &n, 0, INT_MAX, "face count") ||
      (tb_lex_left(lx) && tb_lex_range(lx, &nmark, 0, 1, "boundary marker count")) ||
      tb_lex_end(lx))
    return -1;
  elem_id *ids = NULL;
  int cap = 0, rc = 0;
  for (long i = 0; rc == 0 && i < n; i++) {
    if ((rc = indices(lx, b, base, i, n, 3, v, &ids, &cap)) != 0) break;
    int left = tb_lex_left(lx); /* the marker, then maybe two adjacent tets (tetgen -nn) */
    if (left != nmark && left != nmark + 2)
      rc = tb_lex_fail(lx, "%d values after the face's nodes (expected %ld or %ld)", left, nmark,
                       nmark + 2);
    while (rc == 0 && left-- > 0) rc = tb_lex_long(lx, &t, "face marker or neighbour");
    if (rc == 0 && tb_build_tri(b, v[0], v[1], v[2])) rc = tb_lex_fail(lx, "out of memory");
  }
  if (rc == 0) rc = tb_lex_trailing(lx, "the last face");
  if (rc == 0) rc = check_ids(lx, ids, n, "face");
  free(ids);
  return rc;
}

/* Reads name = base + ext of part kind (0 node, 1 ele, 2 face); when the
 * file does not exist, sets *absent and returns 0. */
static int read_part(char *name, size_t len, int kind, int upper, tb_build *b, long *base,
                     int *absent, tb_error *err) {
  static const char *const ext[2][3] = {{".node", ".ele", ".face"}, {".NODE", ".ELE", ".FACE"}};
  tb_lex lx;
  strcpy(name + len, ext[upper][kind]);
  struct stat st;
  *absent = stat(name, &st) != 0 && errno == ENOENT;
  if (*absent) return 0;
  if (tb_lex_open(&lx, name, '#', err)) return -1;
  int rc = kind == 0   ? read_node(&lx, b, base)
           : kind == 1 ? read_ele(&lx, b, *base)
                       : read_face(&lx, b, *base);
  tb_lex_close(&lx);
  return rc;
}

int tb_read_tetgen(const char *path, tb_build *b, tb_error *err) {
  const char *dot = strrchr(path, '.');
  size_t len = dot ? (size_t)(dot - path) : strlen(path);
  int from_ele = dot && strcasecmp(dot, ".ele") == 0, absent;
  /* The partner files take the case of the extension given: A.NODE reads A.ELE. */
  int upper = dot && dot[1] >= 'A' && dot[1] <= 'Z';
  char *name = malloc(len + 6);
  if (!name) return tb_error_set(err, path, 0, "out of memory");
  memcpy(name, path, len);
  long base = 1;
  int rc = read_part(name, len, 0, upper, b, &base, &absent, err);
  if (rc == 0 && absent)
    rc = from_ele ? tb_error_set(err, path, 0, "missing companion %s", name)
                  : tb_error_set(err, path, 0, "cannot open: %s", strerror(ENOENT));
  for (int kind = 1; kind < 3 && rc == 0; kind++) {
    rc = read_part(name, len, kind, upper, b, &base, &absent, err);
    if (rc == 0 && absent && kind == 1 && from_ele)
      rc = tb_error_set(err, path, 0, "cannot open: %s", strerror(ENOENT));
  }
  free(name);
  return rc;
}
