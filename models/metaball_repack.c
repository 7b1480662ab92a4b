/* The end of the metaball patent's cut: the point set back to spheres
 * (CN doc. 12722810, step 3 (4), "维诺图生成元球"). models/metaball_cut.c's
 * head says how boundary points, poles, the greedy choice, rest centres and
 * links are defined; this file follows it top to bottom. The skin and the
 * spheres made to follow the cut surface's pieces: models/metaball_pieces.c. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "metaball_priv.h"
#include "tb_meshless.h"
#include "meshgen/tb_sphpack.h"

/* ---- points binned on a uniform grid, for range queries ---- */
typedef struct pgrid {
  tb_vec3 lo;
  double cell;
  int dim[3], *start, *idx;
} pgrid;

static int cell_of(const pgrid *g, double v, double lo, int a) {
  int k = (int)floor((v - lo) / g->cell);
  return k < 0 ? 0 : (k >= g->dim[a] ? g->dim[a] - 1 : k);
}

static int pgrid_build(pgrid *g, const tb_vec3 *x, int n, double cell) {
  tb_vec3 lo = x[0], hi = x[0];
  for (int i = 1; i < n; i++) lo = tb_vmin(lo, x[i]), hi = tb_vmax(hi, x[i]);
  for (double cells = INFINITY; cells > 8.0 * n + 64; cell *= 1.5) {
    cells = 1;
    for (int a = 0; a < 3; a++)
      cells *= g->dim[a] = (int)fmin((tb_comp(hi, a) - tb_comp(lo, a)) / cell, 1e6) + 1;
    g->cell = cell;
  }
  g->lo = lo;
  int nc = g->dim[0] * g->dim[1] * g->dim[2];
  g->start = calloc((size_t)nc + 1, sizeof(int)), g->idx = malloc(sizeof(int) * (size_t)n);
  if (!g->start || !g->idx) return -1;
  int *key = malloc(sizeof(int) * (size_t)n);
  if (!key) return -1;
  for (int i = 0; i < n; i++) {
    key[i] = (cell_of(g, x[i].z, lo.z, 2) * g->dim[1] + cell_of(g, x[i].y, lo.y, 1)) * g->dim[0] +
             cell_of(g, x[i].x, lo.x, 0);
    g->start[key[i] + 1]++;
  }
  for (int k = 0; k < nc; k++) g->start[k + 1] += g->start[k];
  for (int i = 0; i < n; i++) g->idx[g->start[key[i]]++] = i;
  for (int k = nc; k > 0; k--) g->start[k] = g->start[k - 1];
  g->start[0] = 0;
  free(key);
  return 0;
}

/* The points within R of c, ascending per cell, into out; their count. */
static int pgrid_within(const pgrid *g, const tb_vec3 *x, tb_vec3 c, double R, int *out) {
  int lo[3], hi[3], n = 0;
  for (int a = 0; a < 3; a++) {
    lo[a] = cell_of(g, tb_comp(c, a) - R, tb_comp(g->lo, a), a);
    hi[a] = cell_of(g, tb_comp(c, a) + R, tb_comp(g->lo, a), a);
  }
  for (int k = lo[2]; k <= hi[2]; k++)
    for (int j = lo[1]; j <= hi[1]; j++)
      for (int i = lo[0]; i <= hi[0]; i++) {
        int cell = (k * g->dim[1] + j) * g->dim[0] + i;
        for (int q = g->start[cell]; q < g->start[cell + 1]; q++)
          if (tb_dist(x[g->idx[q]], c) <= R) out[n++] = g->idx[q];
      }
  return n;
}

/* ---- boundary points and their outward normals ---- */

/* 1 when point i is on the boundary, with its outward normal; -1 a stray. */
static int boundary(const tb_metaball_cutstate *c, const tb_vec3 *x, const tb_vec3 *centre, int i,
                    tb_vec3 *normal) {
  const int *nb;
  int k = tb_meshless_neighbours(c->ml, i, &nb);
  if (k == 0) return -1;
  tb_vec3 off = tb_v3(0, 0, 0), pn = tb_sub(x[i], centre[c->gen[i]]);
  double len = 0, cone = cos(c->set.boundary_angle * M_PI / 180), best = -2;
  for (int q = 0; q < k; q++) {
    tb_vec3 e = tb_sub(x[nb[q]], x[i]);
    off = tb_add(off, e), len += tb_len(e);
    double l = tb_len(e) * tb_len(pn);
    if (l > 0) best = fmax(best, tb_dot(e, pn) / l);
  }
  off = tb_scale(off, 1.0 / k), len /= k;
  int lonely = tb_len(pn) > 1e-9 * len && best < cone;
  int skew = tb_len(off) > c->set.boundary_offset * len;
  *normal = tb_len(off) > 1e-3 * len ? tb_normalize(tb_scale(off, -1)) : tb_normalize(pn);
  return k < 4 || lonely || skew;
}

/* ---- the greedy choice of centres ---- */

typedef struct cand {
  tb_vec3 c;
  double r;
  int id;
} cand;

static int by_radius(const void *a, const void *b) {
  const cand *p = a, *q = b;
  if (p->r != q->r) return p->r > q->r ? -1 : 1;
  for (int k = 0; k < 3; k++)
    if (tb_comp(p->c, k) != tb_comp(q->c, k)) return tb_comp(p->c, k) < tb_comp(q->c, k) ? -1 : 1;
  return p->id - q->id;
}

/* The rigid fit of the points listed (rest X to current x): the rotation of
 * the polar decomposition of sum (x - xm)(X - Xm)^T, by the iterated turns
 * of Müller et al. 2016 from the identity; the centroids into xm, Xm. */
static tb_mat3 fit(const tb_vec3 *X, const tb_vec3 *x, const int *list, int n, tb_vec3 *xm,
                   tb_vec3 *Xm) {
  *xm = *Xm = tb_v3(0, 0, 0);
  for (int q = 0; q < n; q++) *xm = tb_add(*xm, x[list[q]]), *Xm = tb_add(*Xm, X[list[q]]);
  *xm = tb_scale(*xm, 1.0 / n), *Xm = tb_scale(*Xm, 1.0 / n);
  tb_mat3 A = {{{0}}}, R = tb_m3_identity();
  for (int q = 0; q < n; q++) {
    tb_vec3 d = tb_sub(x[list[q]], *xm), e = tb_sub(X[list[q]], *Xm);
    for (int a = 0; a < 3; a++)
      for (int b = 0; b < 3; b++) A.m[a][b] += tb_comp(d, a) * tb_comp(e, b);
  }
  return n >= 4 ? tb_metaball_turns(A, R, 50, 1e-14) : R;
}

typedef struct work {
  tb_vec3 *bp, *bn, *pole, *centre, *nc, *nc0, *nv, *vel;
  double *pole_r, *nr;
  int *list;
  unsigned char *covered, *isb;
  tb_mat3 *nrot;
  cand *cd;
  int *pairs;
  pgrid g;
} work;

static void work_free(work *w) {
  free(w->bp), free(w->bn), free(w->pole), free(w->centre), free(w->nc), free(w->nc0), free(w->nv);
  free(w->pole_r), free(w->nr), free(w->list), free(w->covered), free(w->isb), free(w->nrot),
      free(w->cd);
  free(w->pairs), free(w->g.start), free(w->g.idx), free(w->vel);
}

/* Picks the new spheres into w->nc, w->nr; returns their count. */
static int choose(const tb_metaball_cutstate *c, const tb_vec3 *x, work *w, int ncand,
                  int *uncovered, int *filled) {
  static const double alpha[] = {1, 0.5, 0.25, 0};
  int nnew = 0, left = 0;
  for (int p = 0; p < c->np; p++) left += !w->covered[p];
  for (int pass = 0; pass < 4 && left > 0; pass++)
    for (int k = 0; k < ncand && left > 0; k++) {
      if (w->cd[k].id < 0) continue;
      tb_vec3 cc = w->cd[k].c;
      double r = w->cd[k].r;
      int near = 0;
      for (int j = 0; j < nnew && !near; j++) near = tb_dist(cc, w->nc[j]) < alpha[pass] * w->nr[j];
      if (near) continue;
      int n = pgrid_within(&w->g, x, cc, r + c->spacing, w->list), fresh = 0;
      for (int q = 0; q < n; q++) fresh += !w->covered[w->list[q]];
      if (!fresh) continue;
      for (int q = 0; q < n; q++) w->covered[w->list[q]] = 1;
      left -= fresh, w->cd[k].id = -1;
      w->nc[nnew] = cc, w->nr[nnew++] = r;
    }
  /* the last pass: each point still uncovered, in order, centres a sphere
   * reaching to the nearest boundary point (at least a spacing, at most
   * four) and covers the points within its radius plus a spacing */
  *filled = 0;
  for (int p = 0; p < c->np && left > 0; p++) {
    if (w->covered[p]) continue;
    double r = 4 * c->spacing;
    if (w->isb[p]) r = c->spacing;
    int n = pgrid_within(&w->g, x, x[p], r, w->list);
    for (int q = 0; q < n; q++)
      if (w->isb[w->list[q]] && w->list[q] != p) r = fmin(r, tb_dist(x[p], x[w->list[q]]));
    r = fmax(r, c->spacing);
    n = pgrid_within(&w->g, x, x[p], r + c->spacing, w->list);
    for (int q = 0; q < n; q++) left -= !w->covered[w->list[q]], w->covered[w->list[q]] = 1;
    w->nc[nnew] = x[p], w->nr[nnew++] = r, (*filled)++;
  }
  *uncovered = left;
  return nnew;
}

/* New sphere j's rest centre, rotation and velocity from its points. */
static void place(const tb_metaball_cutstate *c, const tb_vec3 *x, work *w, int j) {
  int n = pgrid_within(&w->g, x, w->nc[j], w->nr[j], w->list), kept = 0;
  for (int q = 0; q < n; q++)
    if (!tb_metaball_cut_crosses((void *)c, w->nc[j], x[w->list[q]])) w->list[kept++] = w->list[q];
  if (kept == 0) { /* cannot happen for a pole within a spacing of a point: keep it as is */
    w->nc0[j] = w->nc[j], w->nrot[j] = tb_m3_identity(), w->nv[j] = tb_v3(0, 0, 0);
    return;
  }
  tb_vec3 xm, Xm, v = tb_v3(0, 0, 0);
  tb_mat3 R = fit(c->X, x, w->list, kept, &xm, &Xm);
  for (int q = 0; q < kept; q++) v = tb_add(v, w->vel[w->list[q]]);
  w->nc0[j] = tb_add(Xm, tb_m3_mulv(tb_m3_transpose(R), tb_sub(w->nc[j], xm)));
  w->nrot[j] = R, w->nv[j] = tb_scale(v, 1.0 / kept);
}

/* Appends the link a-b unless its centre segment crosses the fold. */
static int add_link(const tb_metaball *m, work *w, int *nl, size_t *cap, int a, int b) {
  if (tb_metaball_cut_crosses(m->cut, m->c[a], m->c[b])) return 0;
  if (2 * (size_t)*nl + 2 > *cap) {
    int *grown = realloc(w->pairs, sizeof(int) * (*cap *= 2));
    if (!grown) return -1;
    w->pairs = grown;
  }
  w->pairs[2 * *nl] = a, w->pairs[2 * *nl + 1] = b, (*nl)++;
  return 0;
}

/* Old links kept unless they cross the fold, then new sphere j against
 * every alive sphere i < j overlapping it at rest, not across the fold. */
static int relink(tb_metaball *m, int first, work *w) {
  size_t cap = 2 * (size_t)m->nl + 64;
  int nl = 0;
  if (!(w->pairs = malloc(sizeof(int) * cap))) return -1;
  for (int e = 0; e < m->nl; e++)
    if (add_link(m, w, &nl, &cap, m->link[2 * e], m->link[2 * e + 1])) return -1;
  for (int j = first; j < m->n; j++)
    for (int i = 0; i < j; i++)
      if (m->alive[i] && tb_dist(m->c0[i], m->c0[j]) < m->set.overlap * (m->r[i] + m->r[j]) &&
          add_link(m, w, &nl, &cap, i, j))
        return -1;
  return tb_metaball_set_links(m, nl, w->pairs);
}

int tb_metaball_cut_end(tb_metaball *m, tb_metaball_cut_report *rep, tb_error *err) {
  tb_metaball_cutstate *c = m->cut;
  tb_metaball_cut_report r = {0};
  if (!c || !c->cutting) return tb_error_set(err, "metaball cut", 0, "no cut running");
  r.removed = c->nrem, r.removed_r = c->nrem ? c->rsum / c->nrem : 0;
  if (!c->ml) { /* nothing was cut */
    c->cutting = 0;
    if (rep) *rep = r;
    return 0;
  }
  int np = c->np, rc = -1, nb = 0;
  const tb_vec3 *x = tb_meshless_positions(c->ml);
  double mean_vol = 0; /* the spacing the thresholds use: the points' mean (per sphere: varies) */
  for (int p = 0; p < np; p++) mean_vol += c->vol[p] / np;
  c->spacing = cbrt(mean_vol);
  work w = {0};
  size_t P = (size_t)np;
  w.bp = malloc(sizeof(tb_vec3) * P), w.bn = malloc(sizeof(tb_vec3) * P);
  w.pole = malloc(sizeof(tb_vec3) * P), w.pole_r = malloc(sizeof(double) * P);
  w.centre = calloc((size_t)m->n, sizeof(tb_vec3)), w.list = malloc(sizeof(int) * P);
  w.covered = calloc(P, 1), w.isb = calloc(P, 1), w.cd = malloc(sizeof(cand) * P),
  w.vel = malloc(sizeof(tb_vec3) * P);
  w.nc = malloc(sizeof(tb_vec3) * P), w.nc0 = malloc(sizeof(tb_vec3) * P);
  w.nr = malloc(sizeof(double) * P), w.nrot = malloc(sizeof(tb_mat3) * P);
  w.nv = malloc(sizeof(tb_vec3) * P);
  if (!w.bp || !w.bn || !w.pole || !w.pole_r || !w.centre || !w.list || !w.covered || !w.isb ||
      !w.cd || !w.nc || !w.nc0 || !w.nr || !w.nrot || !w.nv || !w.vel ||
      pgrid_build(&w.g, x, np, c->spacing))
    goto oom;
  memcpy(w.vel, tb_meshless_velocities(c->ml), sizeof(tb_vec3) * P);
  for (int k = 0; k < c->nrem; k++) { /* each removed sphere's centre now: its points' mean */
    tb_vec3 s = tb_v3(0, 0, 0);
    for (int p = c->pstart[k]; p < c->pstart[k + 1]; p++) s = tb_add(s, x[p]);
    int cnt = c->pstart[k + 1] - c->pstart[k];
    w.centre[c->removed[k]] = cnt ? tb_scale(s, 1.0 / cnt) : m->c[c->removed[k]];
  }
  for (int p = 0; p < np; p++) {
    int b = boundary(c, x, w.centre, p, &w.bn[nb]);
    w.covered[p] = b < 0;
    r.strays += b < 0, r.driven += b >= 0 && c->driver[p] >= 0;
    w.isb[p] = b > 0;
    if (b > 0) w.bp[nb++] = x[p];
  }
  r.points = np, r.boundary = nb;
  if (nb >= 4 && tb_voronoi_poles(w.bp, w.bn, nb, w.pole, w.pole_r)) {
    tb_error_set(err, "metaball cut", 0, "CGAL's Delaunay triangulation of %d points failed", nb);
    goto fail;
  }
  int ncand = 0;
  for (int i = 0; i < (nb >= 4 ? nb : 0); i++) {
    if (!(w.pole_r[i] >= c->spacing) || !tb_isfinite3(w.pole[i])) continue;
    if (pgrid_within(&w.g, x, w.pole[i], c->spacing, w.list) == 0) continue;
    if (tb_metaball_cut_crosses(c, w.bp[i], w.pole[i])) continue;
    w.cd[ncand].c = w.pole[i], w.cd[ncand].r = w.pole_r[i], w.cd[ncand].id = ncand, ncand++;
  }
  qsort(w.cd, (size_t)ncand, sizeof(cand), by_radius);
  r.candidates = ncand;
  int nfill = 0, nnew = choose(c, x, &w, ncand, &r.uncovered, &nfill), first = m->n;
  for (int j = 0; j < nnew; j++) place(c, x, &w, j);
  if (tb_metaball_add(m, nnew, w.nc0, w.nc, w.nrot, w.nr, w.nv) || relink(m, first, &w)) goto oom;
  for (int j = first; j < m->n; j++) { /* a new sphere left without a link would float: it goes */
    int deg = 0;
    for (int e = 0; e < 2 * m->nl && !deg; e++) deg = m->link[e] == j;
    if (!deg) tb_metaball_remove(m, j);
    r.created += deg, r.created_r += deg ? m->r[j] : 0, r.dropped += !deg;
    r.filled += deg && j - first >= nnew - nfill;
  }
  r.uncovered = 0; /* recounted over the kept spheres */
  for (int p = 0; p < np; p++) {
    if (c->driver[p] >= 0 || !tb_meshless_neighbours(c->ml, p, NULL)) continue;
    int in = 0;
    for (int j = first; j < m->n && !in; j++)
      in = m->alive[j] && tb_dist(x[p], w.nc[j - first]) <= m->r[j] + c->spacing;
    r.uncovered += !in;
  }
  r.created_r = r.created ? r.created_r / r.created : 0;
  tb_metaball_cut_free_points(c);
  c->cutting = 0, rc = 0;
  if (rep) *rep = r;
  goto fail;
oom:
  tb_error_set(err, "metaball cut", 0, "out of memory (%d points)", np);
fail:
  work_free(&w);
  return rc;
}
