/* STL reader, ASCII and binary (3D Systems, StereoLithography Interface
 * Specification, 1989). A file is binary exactly when its size is 84 + 50 n
 * for the little-endian count n at byte 80: binary files may start with
 * "solid" too. Identical vertices are merged exactly (a hash on the
 * coordinates; -0 equals +0) so the mesh comes out indexed. */
#include <limits.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "io_internal.h"

_Static_assert(sizeof(float) == 4, "binary STL needs 32-bit floats");

/* Open-addressing table: slot holds vertex index + 1, 0 when empty. */
typedef struct vmap {
  int *slot;
  size_t cap; /* a power of two */
} vmap;

static size_t hash3(tb_vec3 x) {
  double c[3] = {x.x + 0.0, x.y + 0.0, x.z + 0.0}; /* -0 + 0 = +0 */
  uint64_t h = 0x9e3779b97f4a7c15u, w;
  for (int k = 0; k < 3; k++) {
    memcpy(&w, &c[k], sizeof w);
    h = (h ^ w) * 0xff51afd7ed558ccdu;
    h ^= h >> 32;
  }
  return (size_t)h;
}

static void vmap_put(vmap *h, const tb_vec3 *x, int v) {
  size_t i = hash3(x[v]) & (h->cap - 1);
  while (h->slot[i]) i = (i + 1) & (h->cap - 1);
  h->slot[i] = v + 1;
}

/* Index of vertex x in b, added when new; -1 when out of memory. */
static int vmap_get(vmap *h, tb_build *b, tb_vec3 x) {
  if (2 * ((size_t)b->m.nv + 1) > h->cap) {
    vmap g = {calloc(h->cap ? 2 * h->cap : 1024, sizeof(int)), h->cap ? 2 * h->cap : 1024};
    if (!g.slot) return -1;
    for (int v = 0; v < b->m.nv; v++) vmap_put(&g, b->m.x, v);
    free(h->slot);
    *h = g;
  }
  size_t i = hash3(x) & (h->cap - 1);
  for (; h->slot[i]; i = (i + 1) & (h->cap - 1)) {
    tb_vec3 y = b->m.x[h->slot[i] - 1];
    if (y.x == x.x && y.y == x.y && y.z == x.z) return h->slot[i] - 1;
  }
  if (tb_build_vert(b, x)) return -1;
  h->slot[i] = b->m.nv;
  return b->m.nv - 1;
}

static uint32_t le32(const unsigned char *p) {
  return (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
}
static double lefloat(const unsigned char *p) {
  uint32_t u = le32(p);
  float f;
  memcpy(&f, &u, sizeof f);
  return f;
}

static int read_binary(tb_lex *lx, unsigned long n, tb_build *b, vmap *h) {
  unsigned char rec[50];
  if (n == 0) return tb_error_set(lx->err, lx->path, 0, "binary STL with 0 triangles");
  if (n > (unsigned long)INT_MAX / 3)
    return tb_error_set(lx->err, lx->path, 0, "binary STL with %lu triangles: too many", n);
  for (unsigned long t = 0; t < n; t++) {
    long off = 84 + 50 * (long)t;
    if (fread(rec, 1, sizeof rec, lx->f) != sizeof rec)
      return tb_error_set(lx->err, lx->path, 0, "triangle %lu (byte offset %ld): read error", t + 1,
                          off);
    int v[3];
    for (int k = 0; k < 3; k++) {
      const unsigned char *p = rec + 12 + 12 * k;
      tb_vec3 x = tb_v3(lefloat(p), lefloat(p + 4), lefloat(p + 8));
      if (!tb_coord_ok(x))
        return tb_error_set(lx->err, lx->path, 0,
                            "triangle %lu (byte offset %ld): coordinate not finite or beyond +-%g",
                            t + 1, off + 12 + 12 * k, TB_COORD_MAX);
      if ((v[k] = vmap_get(h, b, x)) < 0)
        return tb_error_set(lx->err, lx->path, 0, "out of memory");
    }
    if (tb_build_tri(b, v[0], v[1], v[2]))
      return tb_error_set(lx->err, lx->path, 0, "out of memory");
  }
  return 0;
}

/* Reads the next line and checks its first word(s) are kw (and kw2). */
static int expect(tb_lex *lx, const char *kw, const char *kw2) {
  char what[40];
  snprintf(what, sizeof what, "'%s%s%s'", kw, kw2 ? " " : "", kw2 ? kw2 : "");
  if (tb_lex_need(lx, what)) return -1;
  char *w = tb_lex_word(lx), *w2 = kw2 ? tb_lex_word(lx) : NULL;
  if (strcasecmp(w, kw) || (kw2 && (!w2 || strcasecmp(w2, kw2))))
    return tb_lex_fail(lx, "expected %s, found '%.40s'", what, w);
  return 0;
}

/* expect(), then nothing else on the line. */
static int expect_line(tb_lex *lx, const char *kw, const char *kw2) {
  return expect(lx, kw, kw2) || tb_lex_end(lx) ? -1 : 0;
}

/* The rest of "facet": nothing, or "normal nx ny nz". */
static int facet_normal(tb_lex *lx) {
  double n;
  char *w = tb_lex_word(lx);
  if (!w) return 0;
  if (strcasecmp(w, "normal"))
    return tb_lex_fail(lx, "expected 'normal' after 'facet', found '%.40s'", w);
  if (tb_lex_real(lx, &n, "normal x") || tb_lex_real(lx, &n, "normal y") ||
      tb_lex_real(lx, &n, "normal z"))
    return -1;
  return tb_lex_end(lx);
}

static int facet(tb_lex *lx, tb_build *b, vmap *h) {
  int v[3];
  if (facet_normal(lx) || expect_line(lx, "outer", "loop")) return -1;
  for (int k = 0; k < 3; k++) {
    tb_vec3 x;
    if (expect(lx, "vertex", NULL) || tb_lex_real(lx, &x.x, "x coordinate") ||
        tb_lex_real(lx, &x.y, "y coordinate") || tb_lex_real(lx, &x.z, "z coordinate") ||
        tb_lex_end(lx))
      return -1;
    if (!tb_coord_ok(x))
      return tb_lex_fail(lx, "vertex (%g, %g, %g): coordinate beyond +-%g", x.x, x.y, x.z,
                         TB_COORD_MAX);
    if ((v[k] = vmap_get(h, b, x)) < 0) return tb_lex_fail(lx, "out of memory");
  }
  if (expect_line(lx, "endloop", NULL) || expect_line(lx, "endfacet", NULL)) return -1;
  return tb_build_tri(b, v[0], v[1], v[2]) ? tb_lex_fail(lx, "out of memory") : 0;
}

/* Starts with "solid" (after a UTF-8 byte-order mark and blanks) as ASCII
 * STL does? */
static int solid_prefix(FILE *f) {
  char s[6] = {0};
  unsigned char bom[3];
  int c;
  rewind(f);
  if (fread(bom, 1, 3, f) != 3 || memcmp(bom, "\xEF\xBB\xBF", 3)) rewind(f);
  while ((c = getc(f)) == ' ' || c == '\t' || c == '\r' || c == '\n') continue;
  s[0] = (char)c;
  size_t n = fread(s + 1, 1, 4, f);
  rewind(f);
  return n == 4 && strncasecmp(s, "solid", 5) == 0;
}

/* A NUL byte among the first 4 kB: binary data (ASCII STL has none; a binary
 * STL's triangle count and floats nearly always hold one). */
static int has_nul(FILE *f) {
  unsigned char buf[4096];
  rewind(f);
  size_t n = fread(buf, 1, sizeof buf, f);
  rewind(f);
  return memchr(buf, 0, n) != NULL;
}

/* The rest of the current line, words joined by one space, into out. */
static void rest_of_line(tb_lex *lx, char *out, size_t cap) {
  char *w;
  size_t n = 0;
  out[0] = 0;
  while ((w = tb_lex_word(lx)) != NULL && n + 1 < cap)
    n += (size_t)snprintf(out + n, cap - n, "%s%s", n ? " " : "", w);
}

/* "solid [name]", facets, "endsolid [name]"; more solids may follow. The
 * name after endsolid is the solid's own or one word. */
static int read_ascii(tb_lex *lx, tb_build *b, vmap *h) {
  char name[256], end[256];
  if (tb_lex_need(lx, "'solid'")) return -1;
  for (;;) {
    char *w = tb_lex_word(lx);
    if (strcasecmp(w, "solid"))
      return tb_lex_fail(lx, "expected 'solid' or end of file, found '%.40s'", w);
    rest_of_line(lx, name, sizeof name);
    for (;;) {
      if (tb_lex_need(lx, "'facet' or 'endsolid'")) return -1;
      char *kw = tb_lex_word(lx);
      if (!strcasecmp(kw, "endsolid")) break;
      if (strcasecmp(kw, "facet"))
        return tb_lex_fail(lx, "expected 'facet' or 'endsolid', found '%.40s'", kw);
      if (facet(lx, b, h)) return -1;
    }
    int words = tb_lex_left(lx);
    rest_of_line(lx, end, sizeof end);
    if (words > 1 && strcmp(end, name))
      return tb_lex_fail(lx, "unexpected '%.40s' after 'endsolid' (a name only: '%.40s')", end,
                         name);
    int r = tb_lex_line(lx);
    if (r <= 0) return r;
  }
}

int tb_read_stl(const char *path, tb_build *b, tb_error *err) {
  tb_lex lx;
  vmap h = {NULL, 0};
  unsigned char head[84] = {0};
  if (tb_lex_open(&lx, path, 0, err)) return -1;
  long size = fseek(lx.f, 0, SEEK_END) == 0 ? ftell(lx.f) : -1;
  int rc;
  if (size < 0 || fseek(lx.f, 0, SEEK_SET)) {
    rc = tb_error_set(err, path, 0, "cannot seek");
  } else if (size >= 84 && fread(head, 1, 84, lx.f) == 84 &&
             size - 84 == 50 * (long)le32(head + 80)) {
    rc = read_binary(&lx, le32(head + 80), b, &h);
  } else if (size >= 84 && solid_prefix(lx.f) && has_nul(lx.f)) {
    rc = tb_error_set(err, path, 0,
                      "binary STL (its header starts with 'solid') of %lu triangles should be "
                      "%ld bytes, the file has %ld (wrong triangle count or truncated)",
                      (unsigned long)le32(head + 80), 84 + 50 * (long)le32(head + 80), size);
  } else if (solid_prefix(lx.f)) {
    rc = read_ascii(&lx, b, &h);
    if (rc == 0) rc = tb_lex_done(&lx, b);
  } else if (size == 0) {
    rc = tb_error_set(err, path, 0, "empty file (no data)");
  } else if (size < 84) {
    rc = tb_lex_fail(&lx,
                     "not an STL file: no 'solid' at the start, and %ld bytes is too short for "
                     "binary STL",
                     size);
  } else {
    rc = tb_lex_fail(&lx,
                     "not an STL file: no 'solid' at the start, and %ld bytes is not the %ld of "
                     "a binary STL of %lu triangles (truncated?)",
                     size, 84 + 50 * (long)le32(head + 80), (unsigned long)le32(head + 80));
  }
  free(h.slot);
  tb_lex_close(&lx);
  return rc;
}
