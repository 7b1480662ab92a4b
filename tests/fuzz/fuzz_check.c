/* The readers' contract, checked after every read: see fuzz_check.h. One rule per check; a rule
 * another change adds to the readers is one more line here. */
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <string.h>

#include "fuzz_check.h"

static int broke(char *why, size_t cap, const char *fmt, ...) __attribute__((format(printf, 3, 4)));
static int broke(char *why, size_t cap, const char *fmt, ...) {
  va_list ap;
  va_start(ap, fmt);
  vsnprintf(why, cap, fmt, ap);
  va_end(ap);
  return -1;
}

static int finite3(tb_vec3 x) { return isfinite(x.x) && isfinite(x.y) && isfinite(x.z); }

/* The length of the file name m starts with: path itself, or for a TetGen
 * .node file the .ele or .face beside it (read with it); 0 when neither. */
static size_t named(const char *m, const char *path) {
  size_t n = strlen(path);
  if (!strncmp(m, path, n) && m[n] == ':') return n;
  if (n < 5 || strcmp(path + n - 5, ".node") || strncmp(m, path, n - 4)) return 0;
  static const char *const beside[] = {"ele", "face"};
  for (int i = 0; i < 2; i++) {
    size_t k = strlen(beside[i]);
    if (!strncmp(m + n - 4, beside[i], k) && m[n - 4 + k] == ':') return n - 4 + k;
  }
  return 0;
}

int tb_fuzz_check_error(const char *path, const tb_error *err, char *why, size_t cap) {
  const char *m = err->msg;
  if (!memchr(m, 0, sizeof err->msg)) return broke(why, cap, "error message not terminated");
  size_t n = named(m, path);
  if (!n) return broke(why, cap, "error message '%s' does not start with '%s:'", m, path);
  const char *s = m + n + 1;
  if (*s >= '0' && *s <= '9') { /* FILE:LINE: with LINE >= 1 */
    const char *d = s;
    while (*s >= '0' && *s <= '9') s++;
    if (*d == '0') return broke(why, cap, "error message '%s': line 0 or a leading 0", m);
    if (*s != ':') return broke(why, cap, "error message '%s': no ':' after the line", m);
    s++;
  }
  if (*s != ' ' || !s[1]) return broke(why, cap, "error message '%s': no reason after the name", m);
  /* bytes from the file are printed escaped (\xNN) */
  for (const unsigned char *c = (const unsigned char *)m; *c; c++)
    if (*c < 0x20 || *c == 0x7f)
      return broke(why, cap, "error message has the control byte 0x%02x", *c);
  return 0;
}

int tb_fuzz_check_mesh(const char *path, int rc, const tb_mesh *m, const tb_error *err, char *why,
                       size_t cap) {
  if (rc) {
    if (m->nv || m->ntri || m->ntet || m->x || m->tri || m->tet)
      return broke(why, cap, "failed read left a mesh: nv %d ntri %d ntet %d", m->nv, m->ntri,
                   m->ntet);
    return tb_fuzz_check_error(path, err, why, cap);
  }
  if (m->nv < 0 || m->ntri < 0 || m->ntet < 0 || m->nskipped < 0)
    return broke(why, cap, "negative count: nv %d ntri %d ntet %d nskipped %d", m->nv, m->ntri,
                 m->ntet, m->nskipped);
  if ((m->nv && !m->x) || (m->ntri && !m->tri) || (m->ntet && !m->tet))
    return broke(why, cap, "a count without its array");
  for (int i = 0; i < m->nv; i++) {
    if (!finite3(m->x[i]))
      return broke(why, cap, "vertex %d is (%g, %g, %g)", i, m->x[i].x, m->x[i].y, m->x[i].z);
    if (!tb_coord_ok(m->x[i])) /* the readers refuse beyond TB_COORD_MAX */
      return broke(why, cap, "vertex %d at (%g, %g, %g) beyond +-%g", i, m->x[i].x, m->x[i].y,
                   m->x[i].z, TB_COORD_MAX);
  }
  for (long k = 0; k < 3L * m->ntri; k++)
    if (m->tri[k] < 0 || m->tri[k] >= m->nv)
      return broke(why, cap, "triangle %ld: index %d of %d vertices", k / 3, m->tri[k], m->nv);
  for (long k = 0; k < 4L * m->ntet; k++)
    if (m->tet[k] < 0 || m->tet[k] >= m->nv)
      return broke(why, cap, "tet %ld: index %d of %d vertices", k / 4, m->tet[k], m->nv);
  return 0;
}

int tb_fuzz_check_spheres(const char *path, int rc, const tb_spheres *s, const tb_error *err,
                          char *why, size_t cap) {
  if (rc) {
    if (s->n || s->c || s->r) return broke(why, cap, "failed read left %d spheres", s->n);
    return tb_fuzz_check_error(path, err, why, cap);
  }
  if (s->n < 0 || (s->n && (!s->c || !s->r))) return broke(why, cap, "bad count %d", s->n);
  for (int i = 0; i < s->n; i++) {
    if (!finite3(s->c[i])) return broke(why, cap, "sphere %d: centre not finite", i);
    if (!(s->r[i] > 0) || !isfinite(s->r[i]))
      return broke(why, cap, "sphere %d: radius %g", i, s->r[i]);
    if (!tb_coord_ok(s->c[i]) || s->r[i] > TB_COORD_MAX)
      return broke(why, cap, "sphere %d beyond +-%g", i, TB_COORD_MAX);
  }
  return 0;
}

int tb_fuzz_check_pairs(const char *path, int rc, const tb_pairset *p, const tb_error *err,
                        char *why, size_t cap) {
  if (rc) {
    if (p->n || p->pairs) return broke(why, cap, "failed read left %d pairs", p->n);
    return tb_fuzz_check_error(path, err, why, cap);
  }
  if (p->n < 0 || (p->n && (!p->pairs || !p->expect))) return broke(why, cap, "bad count %d", p->n);
  for (int i = 0; i < p->n; i++) {
    for (int j = 0; j < 3; j++)
      if (!finite3(p->pairs[i].p[j]) || !finite3(p->pairs[i].q[j]))
        return broke(why, cap, "pair %d: a coordinate is not finite", i);
    if (p->expect[i] < -1 || p->expect[i] > 1)
      return broke(why, cap, "pair %d: expect %d", i, p->expect[i]);
  }
  return 0;
}

int tb_fuzz_check_points(const char *path, int rc, const tb_point *p, int n, const tb_error *err,
                         char *why, size_t cap) {
  if (rc) {
    if (n || p) return broke(why, cap, "failed read left %d points", n);
    return tb_fuzz_check_error(path, err, why, cap);
  }
  if (n < 0 || (n && !p)) return broke(why, cap, "bad count %d", n);
  for (int i = 0; i < n; i++) {
    if (p[i].line < 2 || (i && p[i].line <= p[i - 1].line))
      return broke(why, cap, "point %d: line %d", i, p[i].line);
    if (!memchr(p[i].model, 0, sizeof p[i].model) || !memchr(p[i].params, 0, sizeof p[i].params) ||
        !memchr(p[i].state, 0, sizeof p[i].state))
      return broke(why, cap, "point %d: a text field not terminated", i);
    if (p[i].resolution < 0 || p[i].nodes < 0)
      return broke(why, cap, "point %d: resolution %d nodes %d", i, p[i].resolution, p[i].nodes);
  }
  return 0;
}
