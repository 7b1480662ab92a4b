/* SOFA's sphere files (.sph, read by SOFA's SphereLoader): "sph 1.0",
 * "#..." comments ("#nums N" is kept as the declared count, advisory),
 * "sphe ID X Y Z R". The rules are in core/tb_spheres.h; the tokenizer is the
 * mesh readers' (core/io_lex.c), opened without a comment character so that
 * "#nums" can be seen before the comment is cut off. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "io_internal.h"
#include "tb_spheres.h"

void tb_spheres_free(tb_spheres *s) {
  free(s->c);
  free(s->r);
  s->c = NULL;
  s->r = NULL;
  s->n = 0;
}

int tb_spheres_push(tb_spheres *s, tb_vec3 c, double r) {
  int n = s->n;
  if (n == 0 || (n >= 8 && (n & (n - 1)) == 0)) { /* capacity: 8, then powers of two */
    if (n > (1 << 29)) return -1;
    size_t cap = n == 0 ? 8 : 2 * (size_t)n;
    tb_vec3 *nc = realloc(s->c, cap * sizeof *nc);
    if (!nc) return -1;
    s->c = nc;
    double *nr = realloc(s->r, cap * sizeof *nr);
    if (!nr) return -1;
    s->r = nr;
  }
  s->c[n] = c;
  s->r[n] = r;
  s->n = n + 1;
  return 0;
}

/* Cuts a "#..." comment off the current line; a line starting "#nums N"
 * sets *declared to N (left alone when N is not a whole number >= 0). */
static void strip_comment(tb_lex *lx, int *declared) {
  char *h = strchr(lx->cur, '#');
  if (!h) return;
  char *s = lx->cur;
  while (*s == ' ' || *s == '\t') s++;
  if (s == h && !strncmp(h, "#nums", 5)) {
    *h = 0;
    lx->cur = h + 5;
    long n;
    char *t = tb_lex_word(lx);
    if (t && !tb_lex_left(lx) && !tb_parse_long(t, &n) && n >= 0 && n <= 0x7fffffff)
      *declared = (int)n;
  }
  *h = 0;
}

static int header(tb_lex *lx, const char *w) {
  double v;
  if (strcmp(w, "sph")) return tb_lex_fail(lx, "expected the header 'sph 1.0', found '%.40s'", w);
  char *t = tb_lex_word(lx);
  if (!t) return tb_lex_fail(lx, "missing version after 'sph' (expected 'sph 1.0')");
  if (tb_parse_real(t, &v) || v != 1.0)
    return tb_lex_fail(lx, "unsupported version '%.40s' (expected 'sph 1.0')", t);
  return tb_lex_end(lx);
}

static int sphere(tb_lex *lx, tb_spheres *s) {
  long id;
  tb_vec3 c;
  double r;
  if (tb_lex_long(lx, &id, "sphere id") || tb_lex_real(lx, &c.x, "x") ||
      tb_lex_real(lx, &c.y, "y") || tb_lex_real(lx, &c.z, "z") || tb_lex_real(lx, &r, "radius"))
    return -1;
  if (!(r > 0)) return tb_lex_fail(lx, "radius %.17g is not positive", r);
  if (!tb_coord_ok(c) || r > TB_COORD_MAX)
    return tb_lex_fail(lx, "sphere (%g, %g, %g) radius %g: beyond +-%g", c.x, c.y, c.z, r,
                       TB_COORD_MAX);
  if (tb_lex_end(lx)) return -1;
  if (tb_spheres_push(s, c, r)) return tb_lex_fail(lx, "out of memory");
  return 0;
}

int tb_spheres_read(const char *path, tb_spheres *s, tb_error *err) {
  memset(s, 0, sizeof *s);
  s->declared = -1;
  tb_lex lx;
  if (tb_lex_open(&lx, path, 0, err)) return -1;
  int r, rc = 0, seen_header = 0;
  while (rc == 0 && (r = tb_lex_line(&lx)) > 0) {
    strip_comment(&lx, &s->declared);
    char *w = tb_lex_word(&lx);
    if (!w) continue; /* a comment line */
    if (!seen_header) {
      rc = header(&lx, w);
      seen_header = 1;
    } else if (!strcmp(w, "sphe"))
      rc = sphere(&lx, s);
    else if (!strcmp(w, "sph"))
      rc = tb_lex_fail(&lx, "second 'sph' header");
    else
      rc = tb_lex_fail(&lx, "unknown .sph statement '%.40s' (expected 'sphe ID X Y Z R')", w);
  }
  if (rc == 0 && r < 0) rc = -1;
  if (rc == 0 && !seen_header) rc = tb_lex_fail(&lx, "empty file (expected 'sph 1.0')");
  if (rc == 0 && s->n == 0) rc = tb_lex_fail(&lx, "no spheres (expected 'sphe ID X Y Z R' lines)");
  tb_lex_close(&lx);
  if (rc) {
    tb_spheres_free(s);
    s->declared = -1;
  }
  return rc;
}

int tb_spheres_write(const char *path, const tb_spheres *s, tb_error *err) {
  if (s->n < 1) return tb_error_set(err, path, 0, "no spheres to write");
  for (int i = 0; i < s->n; i++)
    if (!tb_coord_ok(s->c[i]) || !(s->r[i] > 0) || !(s->r[i] <= TB_COORD_MAX))
      return tb_error_set(err, path, 0,
                          "sphere %d: centre not finite or beyond +-%g, or radius not in (0, %g]",
                          i + 1, TB_COORD_MAX, TB_COORD_MAX);
  FILE *f = fopen(path, "w");
  if (!f) return tb_error_set(err, path, 0, "cannot write");
  fprintf(f, "sph 1.0\n#nums %d\n", s->n);
  for (int i = 0; i < s->n; i++)
    fprintf(f, "sphe %d %.17g %.17g %.17g %.17g\n", i + 1, s->c[i].x, s->c[i].y, s->c[i].z,
            s->r[i]);
  int bad = ferror(f);
  if (fclose(f) || bad) return tb_error_set(err, path, 0, "write failed");
  return 0;
}
