/* Shared by the mesh readers: a line-oriented tokenizer that tracks
 * FILE:LINE, strict strtod/strtol number parsing (whole token, finite, in
 * range) and the growable arrays of a mesh under construction. */
#include <errno.h>
#include <limits.h>
#include <math.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "io_internal.h"

#define TB_LEX_MAXLINE (1L << 20)

static int is_space(int c) { return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f'; }

int tb_lex_fail(tb_lex *lx, const char *fmt, ...) {
  char reason[400];
  va_list ap;
  va_start(ap, fmt);
  vsnprintf(reason, sizeof reason, fmt, ap);
  va_end(ap);
  return tb_error_set(lx->err, lx->path, lx->line, "%s", reason);
}

FILE *tb_io_open(const char *path, tb_error *err) {
  struct stat st;
  /* stat first: opening a FIFO would wait for a writer */
  if (stat(path, &st) == 0 && !S_ISREG(st.st_mode)) {
    tb_error_set(err, path, 0, S_ISDIR(st.st_mode) ? "is a directory" : "not a regular file");
    return NULL;
  }
  FILE *f = fopen(path, "rb");
  if (!f) {
    tb_error_set(err, path, 0, "cannot open: %s", strerror(errno));
    return NULL;
  }
  if (fstat(fileno(f), &st)) {
    tb_error_set(err, path, 0, "cannot stat: %s", strerror(errno));
    fclose(f);
    return NULL;
  }
  if (!S_ISREG(st.st_mode)) {
    tb_error_set(err, path, 0, S_ISDIR(st.st_mode) ? "is a directory" : "not a regular file");
    fclose(f);
    return NULL;
  }
  return f;
}

int tb_lex_open(tb_lex *lx, const char *path, int comment, tb_error *err) {
  memset(lx, 0, sizeof *lx);
  lx->path = path;
  lx->err = err;
  lx->comment = comment;
  lx->line = 1;
  lx->f = tb_io_open(path, err);
  if (!lx->f) return -1;
  lx->cap = 256;
  lx->buf = malloc(lx->cap);
  if (!lx->buf) {
    tb_lex_close(lx);
    return tb_error_set(err, path, 0, "out of memory");
  }
  lx->buf[0] = 0;
  lx->cur = lx->buf;
  return 0;
}

void tb_lex_close(tb_lex *lx) {
  if (lx->f) fclose(lx->f);
  free(lx->buf);
  lx->f = NULL;
  lx->buf = NULL;
}

/* One physical line into buf: 1 read, 0 end of file, -1 error. At end of
 * file, line is the file's last line (0 for an empty file), never one past. */
static int read_raw(tb_lex *lx) {
  size_t n = 0;
  int c = EOF;
  lx->buf[0] = 0;
  lx->cur = lx->buf;
  if (lx->eof) {
    lx->line = lx->last;
    return 0;
  }
  lx->line = lx->nl + 1;
  while ((c = getc(lx->f)) != EOF && c != '\n') {
    if (c == 0) return tb_lex_fail(lx, "NUL byte: binary data in a text file");
    if (n + 1 >= lx->cap) {
      if (lx->cap >= (size_t)TB_LEX_MAXLINE)
        return tb_lex_fail(lx, "line longer than %ld bytes", TB_LEX_MAXLINE);
      char *nb = realloc(lx->buf, 2 * lx->cap);
      if (!nb) return tb_lex_fail(lx, "out of memory");
      lx->buf = nb;
      lx->cap *= 2;
    }
    lx->buf[n++] = (char)c;
  }
  if (ferror(lx->f)) return tb_lex_fail(lx, "read error: %s", strerror(errno));
  lx->buf[n] = 0;
  lx->cur = lx->buf;
  if (c == '\n') {
    lx->nl++;
  } else {
    lx->eof = 1;
    if (n == 0) {
      lx->line = lx->last;
      return 0;
    }
  }
  lx->last = lx->line;
  /* A UTF-8 byte-order mark may open the file; anywhere else it is named. */
  static const char bom[] = "\xEF\xBB\xBF";
  if (lx->line == 1 && !strncmp(lx->buf, bom, 3)) lx->cur = lx->buf + 3;
  if (strstr(lx->cur, bom)) return tb_lex_fail(lx, "byte-order mark inside the file");
  if (lx->comment) {
    char *h = strchr(lx->cur, lx->comment);
    if (h) *h = 0;
  }
  return 1;
}

int tb_lex_line(tb_lex *lx) {
  for (;;) {
    int r = read_raw(lx);
    if (r <= 0) return r;
    if (tb_lex_left(lx) > 0) {
      lx->seen = 1;
      return 1;
    }
  }
}

int tb_lex_need(tb_lex *lx, const char *what) {
  int r = tb_lex_line(lx);
  if (r < 0) return -1;
  if (r) return 0;
  return tb_lex_fail(lx, "%s (expected %s)", lx->seen ? "unexpected end of file" : "empty file",
                     what);
}

int tb_lex_item(tb_lex *lx, long i, long n, const char *what) {
  char need[80];
  snprintf(need, sizeof need, "%s %ld of %ld", what, i + 1, n);
  return tb_lex_need(lx, need);
}

char *tb_lex_word(tb_lex *lx) {
  char *s = lx->cur;
  while (is_space(*s)) s++;
  if (!*s) {
    lx->cur = s;
    return NULL;
  }
  char *e = s;
  while (*e && !is_space(*e)) e++;
  if (*e) *e++ = 0;
  lx->cur = e;
  return s;
}

int tb_lex_left(const tb_lex *lx) {
  int n = 0;
  for (const char *s = lx->cur; *s;) {
    while (is_space(*s)) s++;
    if (!*s) break;
    n++;
    while (*s && !is_space(*s)) s++;
  }
  return n;
}

int tb_parse_real(const char *s, double *v) {
  char *end;
  if (!*s) return 1;
  double d = strtod(s, &end);
  if (end == s || *end) return 1;
  if (!isfinite(d)) return 2;
  *v = d;
  return 0;
}

int tb_parse_long(const char *s, long *v) {
  char *end;
  if (!*s) return 1;
  errno = 0;
  long n = strtol(s, &end, 10);
  if (end == s || *end) return 1;
  if (errno == ERANGE) return 2;
  *v = n;
  return 0;
}

int tb_lex_real(tb_lex *lx, double *v, const char *what) {
  char *t = tb_lex_word(lx);
  if (!t) return tb_lex_fail(lx, "missing %s", what);
  int r = tb_parse_real(t, v);
  if (r == 1) return tb_lex_fail(lx, "%s '%.40s' is not a number", what, t);
  if (r == 2) return tb_lex_fail(lx, "%s '%.40s' is not finite", what, t);
  return 0;
}

int tb_lex_long(tb_lex *lx, long *v, const char *what) {
  char *t = tb_lex_word(lx);
  if (!t) return tb_lex_fail(lx, "missing %s", what);
  int r = tb_parse_long(t, v);
  if (r == 1) return tb_lex_fail(lx, "%s '%.40s' is not an integer", what, t);
  if (r == 2) return tb_lex_fail(lx, "%s '%.40s' is out of range", what, t);
  return 0;
}

int tb_lex_range(tb_lex *lx, long *v, long lo, long hi, const char *what) {
  if (tb_lex_long(lx, v, what)) return -1;
  if (*v < lo || *v > hi)
    return tb_lex_fail(lx, "%s %ld out of range (%ld..%ld)", what, *v, lo, hi);
  return 0;
}

int tb_lex_end(tb_lex *lx) {
  char *t = tb_lex_word(lx);
  return t ? tb_lex_fail(lx, "unexpected '%.40s' at end of line", t) : 0;
}

int tb_lex_trailing(tb_lex *lx, const char *after) {
  int r = tb_lex_line(lx);
  if (r < 0) return -1;
  return r ? tb_lex_fail(lx, "unexpected data after %s (wrong counts?)", after) : 0;
}

int tb_lex_done(tb_lex *lx, const tb_build *b) {
  if (b->m.nv > 0) return 0;
  return tb_lex_fail(lx, lx->seen ? "no vertices" : "empty file (no data)");
}

/* ---- growable arrays ---- */
void *tb_io_grow(void *p, int *cap, long need, size_t sz) {
  if (need <= *cap) return p;
  if (need > INT_MAX) return NULL;
  long nc = *cap > 0 ? *cap : 16;
  while (nc < need) nc = nc > INT_MAX / 2 ? INT_MAX : 2 * nc;
  if ((size_t)nc > SIZE_MAX / sz) return NULL;
  void *q = realloc(p, (size_t)nc * sz);
  if (!q) return NULL;
  *cap = (int)nc;
  return q;
}

int tb_build_vert(tb_build *b, tb_vec3 x) {
  if (!tb_coord_ok(x)) return 1;
  tb_vec3 *p = tb_io_grow(b->m.x, &b->capv, (long)b->m.nv + 1, sizeof *p);
  if (!p) return -1;
  b->m.x = p;
  p[b->m.nv++] = x;
  return 0;
}

int tb_lex_vert(tb_lex *lx, tb_build *b, tb_vec3 x) {
  int r = tb_build_vert(b, x);
  if (r > 0)
    return tb_lex_fail(lx, "vertex %d (%g, %g, %g): coordinate beyond +-%g", b->m.nv + 1, x.x, x.y,
                       x.z, TB_COORD_MAX);
  return r ? tb_lex_fail(lx, "out of memory") : 0;
}

int tb_build_tri(tb_build *b, int a, int c, int d) {
  int *p = tb_io_grow(b->m.tri, &b->captri, (long)b->m.ntri + 1, 3 * sizeof *p);
  if (!p) return -1;
  b->m.tri = p;
  p += 3 * b->m.ntri++;
  p[0] = a;
  p[1] = c;
  p[2] = d;
  return 0;
}

int tb_build_tet(tb_build *b, const int v[4]) {
  int *p = tb_io_grow(b->m.tet, &b->captet, (long)b->m.ntet + 1, 4 * sizeof *p);
  if (!p) return -1;
  b->m.tet = p;
  memcpy(p + 4 * b->m.ntet++, v, 4 * sizeof *p);
  return 0;
}

void tb_build_free(tb_build *b) {
  free(b->m.x);
  free(b->m.tri);
  free(b->m.tet);
  memset(b, 0, sizeof *b);
}
