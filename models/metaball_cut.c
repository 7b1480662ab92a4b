/* The volume side of the metaball patent's cut (CN doc. 12722810, step 3
 * (1)-(4), "从元球到点集再到元球"; tb_metaball.h):
 *
 * (1) Spheres to points. Spheres the blade's folded plane touches
 * (tb_fold_sphere at their current centres) turn into points and are removed
 * logically (tb_metaball_remove). Sampling, as the patent offers: a uniform
 * grid over the organ's rest bounding box shared by all spheres, spacing a
 * fraction of the smallest radius (a grid point belongs to the first
 * converted sphere containing it); or, for very unequal radii, about N
 * points per sphere on its own lattice (spacing r (4 pi / 3 N)^(1/3)),
 * dropping lattice points closer than min_dist x spacing to points already
 * taken (the patent's minimum distance in overlaps). A sphere smaller than
 * `coarse` x the mean radius is sampled at the spacing of one of that
 * radius, so fewer points (the patent's other option, "the spacing chosen
 * by classes of radii"): the point set's stiffest stencils, and so its
 * substeps, come from its smallest spacing (the gallbladder's smallest
 * spheres, r 0.04 against a mean of 0.23, made its cut frames 32 ms).
 * Default 0.3: at 0.5 the sparse points of small spheres near the surface
 * made ill-conditioned stencils, and steak-cut blew up (strains of 1.6). A point's rest position
 * is the lattice point X; its current one c + R (X - c0) by its sphere's
 * motion (R: the sphere's unit-constraint rotation).
 *
 * (2) The point set is the simplified meshless body of models/meshless.c,
 * created uncut from the first spheres converted and cut at the current
 * positions by the whole fold (tb_meshless_relink). Spheres converted later
 * add their points to it (tb_meshless_add: the new links cut by the whole
 * fold, earlier points keep their state, new ones take their sphere's
 * velocity), keeping its support h; it is rebuilt over all points (0.5-1.6
 * ms a frame on every conversion) only when the
 * mean spacing a rebuild would take drifts more than 10% from h / 2, and a
 * rebuild links two old points only if they were linked (tb_meshless_unlink):
 * what the blade parted stays parted. The fold grows each frame:
 * every advance re-cuts the links, and when the new fold extends the last one (same depth, the old
 * path a prefix) only against the pieces the blade swept since (the last
 * old piece and the new ones), spheres too: material that later moves
 * across a piece the blade has left is not cut again. Each piece has its
 * box; a link is tested exactly only against pieces whose box meets its
 * own. Stencils with det A <= flatness (tr A / 3)^3 are inactive
 * (tb_meshless_set_flatness; 0.02, against the module's 1e-3): the nearly
 * flat stencils of a coarse, irregular cloud are the stiffest and alone
 * set the explicit step (on the 570-sphere liver 0.02 cut the substeps
 * about fourfold). So are stencils of fewer than MIN_STENCIL neighbours: a
 * point with three or four fits their motion exactly, like a lone tet, and
 * turned inside out under a random blade across the steak (a point's
 * position reached 1e34 within one frame of 44 substeps at the bound).
 *
 * (3) Coupling. A point whose rest position lies inside a sphere still alive
 * (searched among the spheres its own sphere was linked to; the deepest,
 * smallest d / r) is driven by it: its position is prescribed to
 * c + R (X - c0), interpolated linearly over the frame's substeps. Points of
 * a fixed sphere inside no alive sphere are held. Back from points to
 * spheres, the "energy constraint" (能量约束) is read as the gradient of the
 * point set's elastic energy U with respect to each sphere's position: the
 * driven points move with their sphere, so -dU/dc_s = sum over its driven
 * points p of f_p, the elastic force on p (tb_meshless_forces), which is
 * added, times `coupling`, to the sphere's force in tb_metaball_step (the
 * patent says only that small motions of the points return to the spheres
 * by energy constraints; rotations are not fed back). Explicitly that force
 * blows a light sphere up (k_s dt^2 / m_s >> 1 for a small sphere on a stiff
 * point set), so it enters linearly implicitly, one backward-Euler step of
 * the coupling stiffness k_s (Baraff & Witkin 1998, "Large steps in cloth
 * simulation", for one degree of freedom): with b = dt^2 k_s / m_s, G the
 * sphere's other forces and v its velocity, F_eff = (F - b G - b m_s v / dt)
 * / (1 + b), which keeps every equilibrium (F = -G, v = 0) and is stable
 * for any k_s; k_s bounds the stiffness of the sphere's driven points moved
 * together (tb_meshless_group_stiffness, from the stencils; an upper bound
 * only damps the coupling more), recomputed whenever the points or links
 * change. The meshless body is explicit (stable for dt omega < 2):
 * substeps of at most cfl x 2 / omega, omega an upper bound of its largest
 * free frequency with the forces linearised at the frame's start
 * (tb_meshless_frequency_at: per stencil, no iteration; models/meshless.c's
 * head). Power iteration on finite differences of the forces (40
 * iterations, one force evaluation per sphere) would take 80% of a frame;
 * block Gershgorin is 1.7-2.5x the iterated omega, this bound 1.05-1.3x.
 * cfl is 0.7: at 0.9, dt omega reaches 1.8 with omega taken at the frame's
 * start, and the liver's cut in the metaball suite blows up.
 *
 * (4) Points back to spheres (cut_end). Boundary points: a point with no
 * neighbour inside the cone of half-angle boundary_angle about its normal
 * (the patent's normal, from its generating sphere's centre, here the
 * centroid of that sphere's points now, to the point), or whose neighbour
 * centroid is off by more than boundary_offset of its mean neighbour
 * distance (the patent's test alone misses a cut face on the far side of
 * the centre); points with fewer than 4 neighbours too; points with none
 * are strays and ignored. The outward normal is minus the neighbour-centroid
 * direction. The inner Voronoi poles of the boundary points (CGAL,
 * tb_voronoi_poles) are the medial axis; a pole is a candidate when its
 * radius (the distance to the nearest boundary point: its Delaunay ball is
 * empty) is at least one spacing, it lies within one spacing of some point
 * (inside the cloud) and its segment to its sample does not cross the fold.
 * Largest first, in passes with alpha = 1, 0.5, 0.25, 0, a candidate is
 * taken when its centre is not within alpha R of a sphere taken (centre C,
 * radius R) and it reaches a point not yet covered (within its radius plus
 * a spacing, the points' own extent; also the points inside spheres still
 * whole must be covered, so the removed spheres' volume is filled again:
 * counting those as covered left a hole along the cut, 21 new spheres for
 * 85 removed on the liver, 37 now); stop when every point is covered. A last pass covers what is
 * left: each point still uncovered, in index order, centres a sphere whose radius reaches the
 * nearest boundary point (one to four spacings; a boundary point's own is one spacing), covering
 * the points within it plus a spacing (the report's `filled`). Points then uncovered belong only to
 * dropped spheres (below). The patent's "or to the spheres already placed" as the radius would make
 * tangent spheres, which do not link: here the placed spheres only space the centres. A new
 * sphere's rest centre and rotation come from the rigid fit (rest to current) of the points inside
 * it on its side of the cut. Links: the old ones kept (unless they cross
 * the fold), new ones between a new sphere and any alive sphere overlapping
 * it at rest whose centre segment (current) does not cross the fold; then
 * the unit constraints are rebuilt. A new sphere left with no link (a
 * small one in a corner) would float free: it is removed again (dropped).
 *
 * Skin (step 3 (5), re-binding): tb_metaball_set_skin binds vertices at the
 * current configuration, with the rest offset x0 solving
 * sum_s w_s (c_s + R_s (x0 - c0_s)) = x, so the skin reproduces x. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "metaball_priv.h"
#include "tb_meshless.h"
#include "cutting/tb_fold.h"

#define MIN_STENCIL 6

void tb_metaball_cut_settings_default(tb_metaball_cut_settings *s) {
  s->spacing = 0.3, s->per_sphere = 0, s->min_dist = 0.6;
  s->E = 1000, s->nu = 0.3, s->density = 0, s->damping = 2, s->coupling = 1;
  s->substeps = 0, s->cfl = 0.7, s->boundary_angle = 45, s->boundary_offset = 0.25;
  s->flatness = 0.02, s->coarse = 0.3;
}

void tb_metaball_cut_free_points(tb_metaball_cutstate *c) {
  tb_meshless_destroy(c->ml);
  free(c->X), free(c->x), free(c->held), free(c->vol), free(c->gen), free(c->driver);
  free(c->removed), free(c->pstart), free(c->ids), free(c->fx0), free(c->fx1), free(c->fx);
  free(c->fpts), free(c->fsph), free(c->fel), free(c->ks), free(c->isdriven), free(c->row);
  free(c->vbuf);
  c->isdriven = NULL, c->row = NULL, c->vbuf = NULL;
  c->ks = NULL, c->fel = NULL, c->ml = NULL, c->X = c->x = c->held = NULL, c->vol = NULL,
  c->gen = c->driver = NULL;
  c->removed = c->pstart = c->ids = NULL, c->fx0 = c->fx1 = c->fx = c->fpts = c->fsph = NULL;
  c->np = c->pcap = c->nrem = c->rcap = c->nd = c->dcap = 0, c->rsum = 0;
  free(c->apart), c->apart = NULL, c->napart = 0;
}

void tb_metaball_cut_release(tb_metaball *m) {
  if (!m->cut) return;
  tb_metaball_cut_free_points(m->cut);
  tb_fold_free(&m->cut->fold);
  free(m->cut->plo), free(m->cut->phi);
  free(m->cut);
  m->cut = NULL;
}

static int by_key(const void *a, const void *b) {
  long long p = *(const long long *)a, q = *(const long long *)b;
  return (p > q) - (p < q);
}

int tb_metaball_apart(const tb_metaball *m, int a, int b) {
  if (a == b) return 0;
  if (m->piece && m->piece[a] >= 0 && m->piece[b] >= 0 && m->piece[a] != m->piece[b]) return 1;
  const tb_metaball_cutstate *c = m->cut;
  if (!c || !c->napart) return 0;
  long long key = a < b ? (long long)a * m->n + b : (long long)b * m->n + a;
  int lo = 0, hi = c->napart;
  while (lo < hi) {
    int mid = (lo + hi) / 2;
    if (c->apart[mid] < key)
      lo = mid + 1;
    else
      hi = mid;
  }
  return lo < c->napart && c->apart[lo] == key;
}

int tb_metaball_cut_begin(tb_metaball *m, const tb_metaball_cut_settings *s, tb_error *err) {
  if (m->cut && m->cut->cutting) return tb_error_set(err, "metaball cut", 0, "a cut is running");
  if (!(s->E > 0) || !(s->nu > -1 && s->nu < 0.5) || !(s->density >= 0) || !(s->damping >= 0) ||
      !(s->coupling >= 0) || s->substeps < 0 || !(s->cfl > 0 && s->cfl <= 1) ||
      !(s->boundary_angle > 0 && s->boundary_angle <= 90) || !(s->boundary_offset > 0) ||
      s->per_sphere < 0 || s->per_sphere > 100000 || !(s->min_dist >= 0 && s->min_dist <= 1) ||
      !(s->flatness >= 0 && s->flatness <= 0.5) || !(s->coarse >= 0 && s->coarse <= 1) ||
      (s->per_sphere == 0 && !(s->spacing > 0 && s->spacing <= 1)))
    return tb_error_set(
        err, "metaball cut", 0,
        "bad settings (E > 0, -1 < nu < 1/2, spacing in (0, 1], cfl in (0, 1], "
        "boundary_angle in (0, 90], flatness in [0, 0.5], coarse in [0, 1], the rest >= 0)");
  if (!m->cut && !(m->cut = calloc(1, sizeof *m->cut)))
    return tb_error_set(err, "metaball cut", 0, "out of memory");
  tb_metaball_cutstate *c = m->cut;
  tb_metaball_cut_free_points(c);
  c->set = *s, c->density = s->density > 0 ? s->density : m->set.density;
  if (m->ncontact > 0) { /* the pairs across earlier cracks, for tb_metaball_apart */
    if (!(c->apart = malloc(sizeof(long long) * (size_t)m->ncontact)))
      return tb_error_set(err, "metaball cut", 0, "out of memory");
    for (int k = 0; k < m->ncontact; k++) {
      long long a = m->contact[2 * k], b = m->contact[2 * k + 1];
      c->apart[k] = a < b ? a * m->n + b : b * m->n + a;
    }
    c->napart = m->ncontact;
    qsort(c->apart, (size_t)c->napart, sizeof(long long), by_key);
  }
  double rmin = INFINITY, rmax = 0, rsum = 0;
  int alive = 0;
  tb_vec3 lo = tb_v3(INFINITY, INFINITY, INFINITY);
  for (int i = 0; i < m->n; i++) {
    if (!m->alive[i]) continue;
    rmin = fmin(rmin, m->r[i]), rmax = fmax(rmax, m->r[i]), rsum += m->r[i], alive++;
    lo = tb_vmin(lo, tb_sub(m->c0[i], tb_v3(m->r[i], m->r[i], m->r[i])));
  }
  if (!(rmax > 0)) return tb_error_set(err, "metaball cut", 0, "no sphere left to cut");
  c->glo = lo;
  if (s->per_sphere > 0) {
    c->rfloor = alive ? s->coarse * rsum / alive : 0;
    c->spacing = fmax(rmin, c->rfloor) * cbrt(4 * M_PI / (3.0 * s->per_sphere));
  } else {
    c->spacing = s->spacing * rmin;
    double most = 4.0 / 3.0 * M_PI * pow(rmax / c->spacing, 3), all = 0;
    for (int i = 0; i < m->n; i++)
      if (m->alive[i]) all += 4.0 / 3.0 * M_PI * pow(m->r[i] / c->spacing, 3);
    if (most > 2e6 || all > 2e6)
      return tb_error_set(err, "metaball cut", 0,
                          "the shared grid puts %.3g points in the largest sphere and up to %.3g "
                          "in all (radii %g to %g): use per_sphere",
                          most, all, rmin, rmax);
  }
  c->cutting = 1;
  return 0;
}

/* ---- (1) spheres to points ---- */

static int push_point(tb_metaball_cutstate *c, tb_vec3 X, tb_vec3 x, double vol, int gen) {
  if (c->np == c->pcap) {
    int cap = c->pcap ? 2 * c->pcap : 1024;
    tb_vec3 *a = realloc(c->X, sizeof(tb_vec3) * (size_t)cap);
    if (a) c->X = a;
    tb_vec3 *b = realloc(c->x, sizeof(tb_vec3) * (size_t)cap);
    if (b) c->x = b;
    double *v = realloc(c->vol, sizeof(double) * (size_t)cap);
    if (v) c->vol = v;
    int *g = realloc(c->gen, sizeof(int) * (size_t)cap);
    if (g) c->gen = g;
    if (!a || !b || !v || !g) return -1;
    c->pcap = cap;
  }
  c->X[c->np] = X, c->x[c->np] = x, c->vol[c->np] = vol, c->gen[c->np++] = gen;
  return 0;
}

/* 1 when X is already taken by a sphere converted before (shared grid: it
 * lies in one; per sphere: a point of one is closer than dmin). */
static int taken(const tb_metaball *m, const tb_metaball_cutstate *c, int s, tb_vec3 X,
                 double dmin) {
  for (int k = 0; k < c->nrem; k++) {
    int j = c->removed[k];
    if (!(tb_dist(m->c0[s], m->c0[j]) < m->r[s] + m->r[j] + dmin) || tb_metaball_apart(m, s, j))
      continue;
    if (c->set.per_sphere == 0) {
      if (tb_dist(X, m->c0[j]) <= m->r[j]) return 1;
      continue;
    }
    for (int p = c->pstart[k]; p < c->pstart[k + 1]; p++)
      if (tb_dist(X, c->X[p]) < dmin) return 1;
  }
  return 0;
}

/* Sphere s's points (see the head), appended; s is recorded as removed. */
static int convert(tb_metaball *m, tb_metaball_cutstate *c, int s) {
  if (c->nrem + 1 >= c->rcap) {
    int cap = c->rcap ? 2 * c->rcap : 64;
    int *a = realloc(c->removed, sizeof(int) * (size_t)cap);
    if (a) c->removed = a;
    int *b = realloc(c->pstart, sizeof(int) * (size_t)(cap + 1));
    if (b) c->pstart = b;
    if (!a || !b) return -1;
    c->rcap = cap;
  }
  double r = m->r[s], h = c->set.per_sphere > 0
                              ? fmax(r, c->rfloor) * cbrt(4 * M_PI / (3.0 * c->set.per_sphere))
                              : c->spacing;
  double dmin = c->set.per_sphere > 0 ? c->set.min_dist * h : 0;
  tb_vec3 o = c->set.per_sphere > 0 ? m->c0[s] : tb_madd(c->glo, 0.5, tb_v3(h, h, h));
  int lo[3], hi[3];
  for (int a = 0; a < 3; a++) {
    lo[a] = (int)floor((tb_comp(m->c0[s], a) - r - tb_comp(o, a)) / h);
    hi[a] = (int)ceil((tb_comp(m->c0[s], a) + r - tb_comp(o, a)) / h);
  }
  c->pstart[c->nrem] = c->np;
  for (int k = lo[2]; k <= hi[2]; k++)
    for (int j = lo[1]; j <= hi[1]; j++)
      for (int i = lo[0]; i <= hi[0]; i++) {
        tb_vec3 X = tb_add(o, tb_v3(i * h, j * h, k * h));
        if (tb_dist(X, m->c0[s]) > r || taken(m, c, s, X, dmin)) continue;
        tb_vec3 x = tb_add(m->c[s], tb_m3_mulv(m->rot[s], tb_sub(X, m->c0[s])));
        if (push_point(c, X, x, h * h * h, s)) return -1;
      }
  c->removed[c->nrem++] = s, c->pstart[c->nrem] = c->np, c->rsum += r;
  return 0; /* removed with the others the call converts (tb_metaball_remove_set) */
}

static int disjoint(tb_vec3 lo, tb_vec3 hi, tb_vec3 blo, tb_vec3 bhi) {
  return lo.x > bhi.x || lo.y > bhi.y || lo.z > bhi.z || hi.x < blo.x || hi.y < blo.y ||
         hi.z < blo.z;
}

/* The meshless cut test: a quick box reject against the whole fold, then
 * per piece from piece_from on (see the head): its box, then the exact
 * segment test on that piece alone (a one-piece view of the fold's arrays:
 * the same triangles, so the same answer as tb_fold_segment on the fold). */
int tb_metaball_cut_crosses(void *ctx, tb_vec3 a, tb_vec3 b) {
  const tb_metaball_cutstate *c = ctx;
  tb_vec3 lo = tb_vmin(a, b), hi = tb_vmax(a, b);
  int fresh = c->piece_from > 0 && c->piece_from == c->nfrom; /* the new pieces' box */
  if (disjoint(lo, hi, fresh ? c->nlo : c->flo, fresh ? c->nhi : c->fhi)) return 0;
  for (int k = c->piece_from; k < c->fold.npieces; k++) {
    if (disjoint(lo, hi, c->plo[k], c->phi[k])) continue;
    tb_fold one = {2, 1, c->fold.depth, c->fold.p + k, c->fold.q + k, c->fold.piece + k};
    if (tb_fold_segment(&one, a, b, NULL)) return 1;
  }
  return 0;
}

/* Copies f with its boxes; piece_from: the first piece new since the last
 * fold when f extends it (same depth, the old path a prefix of the new),
 * else 0. */
static int copy_fold(tb_metaball_cutstate *c, const tb_fold *f, tb_error *err) {
  int from = 0;
  if (c->has_fold && c->fold.count <= f->count &&
      !memcmp(&c->fold.depth, &f->depth, sizeof f->depth) &&
      !memcmp(c->fold.p, f->p, sizeof(tb_vec3) * (size_t)c->fold.count))
    from = c->fold.npieces - 1; /* the blade's last piece again, and every new one */
  tb_fold_free(&c->fold);
  c->has_fold = 0;
  if (tb_fold_init(&c->fold, f->p, f->count, f->depth, err)) return -1;
  int np = c->fold.npieces;
  tb_vec3 *lo = realloc(c->plo, sizeof(tb_vec3) * (size_t)np);
  if (lo) c->plo = lo;
  tb_vec3 *hi = realloc(c->phi, sizeof(tb_vec3) * (size_t)np);
  if (hi) c->phi = hi;
  if (!lo || !hi) return tb_error_set(err, "metaball cut", 0, "out of memory");
  c->flo = c->fold.p[0], c->fhi = c->fold.p[0];
  for (int k = 0; k < np; k++) {
    const tb_vec3 *p = c->fold.p + k, *q = c->fold.q + k;
    c->plo[k] = tb_vmin(tb_vmin(p[0], p[1]), tb_vmin(q[0], q[1]));
    c->phi[k] = tb_vmax(tb_vmax(p[0], p[1]), tb_vmax(q[0], q[1]));
    c->flo = tb_vmin(c->flo, c->plo[k]), c->fhi = tb_vmax(c->fhi, c->phi[k]);
  }
  c->nlo = c->plo[from], c->nhi = c->phi[from];
  for (int k = from; k < np; k++)
    c->nlo = tb_vmin(c->nlo, c->plo[k]), c->nhi = tb_vmax(c->nhi, c->phi[k]);
  c->piece_from = c->nfrom = from, c->has_fold = 1;
  return 0;
}

/* realloc to n elements of size sz, or NULL leaving *p as it was. */
static int grow_to(void **p, size_t n, size_t sz) {
  void *q = realloc(*p, n * sz);
  if (!q) return -1;
  *p = q;
  return 0;
}

/* Each point's driver (see the head) and the per-frame buffers. A driver
 * changes only when it is removed (a point's candidates can only die during
 * a cut, so its deepest one stays the deepest while alive): points from
 * `from` on are new, and the others are looked at again only when their
 * driver is gone. */
static int drive(tb_metaball *m, tb_metaball_cutstate *c, int from) {
  if (c->np > c->dcap) {
    size_t n = (size_t)c->np, v3 = sizeof(tb_vec3);
    if (grow_to((void **)&c->driver, n, sizeof(int)) || grow_to((void **)&c->held, n, v3) ||
        grow_to((void **)&c->ids, n, sizeof(int)) || grow_to((void **)&c->fx0, n, v3) ||
        grow_to((void **)&c->fx1, n, v3) || grow_to((void **)&c->fx, n, v3) ||
        grow_to((void **)&c->fpts, n, v3) || grow_to((void **)&c->isdriven, n, 1) ||
        grow_to((void **)&c->row, 2 * n, sizeof(double)))
      return -1;
    c->dcap = c->np;
  }
  if (!c->fsph) {
    c->fsph = malloc(sizeof(tb_vec3) * (size_t)m->n),
    c->fel = malloc(sizeof(tb_vec3) * (size_t)m->n);
    c->ks = calloc((size_t)m->n, sizeof(double));
    if (!c->fsph || !c->fel || !c->ks) return -1;
  }
  c->nd = 0;
  for (int p = 0; p < c->np; p++) {
    if (p < from && !(c->driver[p] >= 0 && !m->alive[c->driver[p]])) {
      if (c->driver[p] != -1) c->ids[c->nd++] = p;
      continue;
    }
    int g = c->gen[p], best = -1;
    double kb = INFINITY;
    for (int q = m->cstart[g]; q < m->cstart[g + 1]; q++) {
      int s = m->cmember[q];
      double k = tb_dist(c->X[p], m->c0[s]) / m->r[s];
      if (m->alive[s] && k <= 1 && k < kb) kb = k, best = s;
    }
    if (best < 0 && m->fixed[g]) best = -2, c->held[p] = c->x[p];
    c->driver[p] = best;
    if (best != -1) c->ids[c->nd++] = p;
  }
  for (int p = 0; p < c->np; p++) c->isdriven[p] = c->driver[p] != -1;
  return 0;
}

/* Each driving sphere's coupling stiffness, from the stencils in one pass,
 * and each stencil's bound of omega^2 at rest (row + np; the frame's bound
 * scales them by the strain) (models/meshless.c's head; no iteration, no
 * force evaluation). */
static void stiffness(tb_metaball_cutstate *c, int nsph) {
  tb_meshless_rest_bounds(c->ml, c->isdriven, c->row, c->row + c->np);
  tb_meshless_group_stiffness(c->ml, c->driver, nsph, c->ks, c->fel); /* fel: scratch here */
}

static int total_links(const tb_meshless *ml) {
  int n = tb_meshless_count(ml), sum = 0;
  for (int i = 0; i < n; i++) sum += tb_meshless_neighbours(ml, i, NULL);
  return sum;
}

/* The old body's links, for the rebuild (old points below n). */
typedef struct old_links {
  int n, *start, *nbr;
} old_links;

/* A link between two old points is kept only when they were linked: the
 * blade parted them, and material that has since moved past the pieces it
 * left is not joined again (the whole fold at the current positions cannot
 * tell: the falling half of steak-cut hung below the fold and its links
 * came back, 0.9 -> 16 in strain energy, then a blow-up). */
static int was_linked(void *ctx, int i, int j) {
  const old_links *o = ctx;
  if (i >= o->n || j >= o->n) return 1;
  int lo = o->start[i], hi = o->start[i + 1];
  while (lo < hi) { /* ascending lists */
    int mid = (lo + hi) / 2;
    if (o->nbr[mid] < j)
      lo = mid + 1;
    else
      hi = mid;
  }
  return lo < o->start[i + 1] && o->nbr[lo] == j;
}

/* The body anew over all the points (positions c->x, velocities c->vbuf):
 * a new support h from all of them, the links between old points only
 * where they were (was_linked); the caller re-cuts it by the whole fold
 * (piece_from = 0). */
static int rebuild(tb_metaball_cutstate *c, tb_error *err) {
  old_links o = {0, NULL, NULL};
  if (c->ml) {
    o.n = tb_meshless_count(c->ml);
    int total = 0;
    for (int i = 0; i < o.n; i++) total += tb_meshless_neighbours(c->ml, i, NULL);
    o.start = malloc(sizeof(int) * (size_t)(o.n + 1));
    o.nbr = malloc(sizeof(int) * (size_t)(total > 0 ? total : 1));
    if (!o.start || !o.nbr) {
      free(o.start), free(o.nbr);
      return tb_error_set(err, "metaball cut", 0, "out of memory");
    }
    for (int i = 0, at = 0; i < o.n; i++) {
      const int *list;
      int k = tb_meshless_neighbours(c->ml, i, &list);
      o.start[i] = at, memcpy(o.nbr + at, list, sizeof(int) * (size_t)k), at += k;
    }
    o.start[o.n] = total;
  }
  tb_meshless_destroy(c->ml);
  c->ml = NULL;
  if (c->np < 2) {
    free(o.start), free(o.nbr);
    return tb_error_set(err, "metaball cut", 0, "the spheres cut gave %d points", c->np);
  }
  c->ml = tb_meshless_create(c->np, c->X, c->vol, c->set.E, c->set.nu, c->density, NULL, NULL, err);
  if (c->ml && o.start) tb_meshless_unlink(c->ml, was_linked, &o);
  free(o.start), free(o.nbr);
  if (!c->ml) return -1;
  tb_meshless_set_damping(c->ml, c->set.damping);
  tb_meshless_set_flatness(c->ml, c->set.flatness);
  tb_meshless_set_min_neighbours(c->ml, MIN_STENCIL);
  tb_meshless_set_positions(c->ml, c->x);
  tb_meshless_set_velocities(c->ml, c->vbuf);
  c->piece_from = 0;
  return 0;
}

/* Points i and j may stay linked: their spheres are not apart. */
static int same_side(void *ctx, int i, int j) {
  const tb_metaball *m = ctx;
  return !tb_metaball_apart(m, m->cut->gen[i], m->cut->gen[j]);
}

int tb_metaball_cut_advance(tb_metaball *m, const tb_fold *f, tb_error *err) {
  tb_metaball_cutstate *c = m->cut;
  if (!c || !c->cutting) return tb_error_set(err, "metaball cut", 0, "no cut running");
  if (!f || f->count < 2) return tb_error_set(err, "metaball cut", 0, "no folded plane");
  if (copy_fold(c, f, err)) return -1;
  int np0 = c->np, converted = 0;
  if (c->ml) {
    tb_vec3 *vb = realloc(c->vbuf, sizeof(tb_vec3) * (size_t)np0);
    if (!vb) return tb_error_set(err, "metaball cut", 0, "out of memory");
    c->vbuf = vb;
    memcpy(c->x, tb_meshless_positions(c->ml), sizeof(tb_vec3) * (size_t)np0);
    memcpy(c->vbuf, tb_meshless_velocities(c->ml), sizeof(tb_vec3) * (size_t)np0);
  }
  /* spheres: against the new pieces only (the blade is there; see the head) */
  int from = c->piece_from;
  tb_fold fresh = {c->fold.count - from, c->fold.npieces - from, c->fold.depth,
                   c->fold.p + from,     c->fold.q + from,       c->fold.piece + from};
  tb_vec3 blo = c->nlo, bhi = c->nhi;
  for (int s = 0; s < m->n; s++) {
    tb_vec3 rr = tb_v3(m->r[s], m->r[s], m->r[s]);
    if (!m->alive[s] || disjoint(tb_sub(m->c[s], rr), tb_add(m->c[s], rr), blo, bhi) ||
        !tb_fold_sphere(&fresh, m->c[s], m->r[s], NULL))
      continue;
    if (convert(m, c, s)) return tb_error_set(err, "metaball cut", 0, "out of memory");
    converted++;
  }
  tb_metaball_remove_set(m, converted, c->removed + c->nrem - converted);
  if (converted) {
    tb_vec3 *vb = realloc(c->vbuf, sizeof(tb_vec3) * (size_t)c->np);
    if (!vb) return tb_error_set(err, "metaball cut", 0, "out of memory");
    c->vbuf = vb; /* velocities: the old points keep theirs, new ones take their sphere's */
    for (int p = np0; p < c->np; p++) c->vbuf[p] = m->v[c->gen[p]];
    c->piece_from = 0; /* new links: the whole fold */
    if (c->ml && tb_meshless_add(c->ml, c->np - np0, c->X + np0, c->x + np0, c->vbuf + np0,
                                 c->vol + np0, tb_metaball_cut_crosses, c, err))
      return -1;
    if (c->ml && fabs(2 * tb_meshless_spacing(c->ml) / tb_meshless_support(c->ml) - 1) <= 0.1)
      c->piece_from = from; /* the old links: the new pieces only */
    else if (rebuild(c, err))
      return -1;
    if (c->napart || m->piece) tb_meshless_unlink(c->ml, same_side, m);
    if (drive(m, c, np0)) return tb_error_set(err, "metaball cut", 0, "out of memory");
  }
  if (!c->ml) return converted;
  int before = total_links(c->ml);
  tb_meshless_relink(c->ml, tb_metaball_cut_crosses, c, err);

  c->piece_from = 0; /* the repacking and the skin test against the whole fold */
  if (converted || total_links(c->ml) != before) stiffness(c, m->n);
  return converted;
}

/* ---- (3) the coupled frame ---- */

static tb_vec3 follow(const tb_metaball *m, const tb_metaball_cutstate *c, int p) {
  int s = c->driver[p];
  if (s < 0) return c->held[p];
  return tb_add(m->c[s], tb_m3_mulv(m->rot[s], tb_sub(c->X[p], m->c0[s])));
}

int tb_metaball_cut_step(tb_metaball *m, double dt, tb_vec3 gravity, const tb_vec3 *force,
                         tb_error *err) {
  tb_metaball_cutstate *c = m->cut;
  if (!c || !c->cutting) return tb_error_set(err, "metaball cut", 0, "no cut running");
  if (!(dt > 0)) return tb_error_set(err, "metaball cut", 0, "dt must be positive");
  if (!c->ml) {
    tb_metaball_step(m, dt, gravity, force);
    return 0;
  }
  if (tb_meshless_forces(c->ml, c->fpts))
    return tb_error_set(err, "metaball cut", 0, "out of memory");
  c->omega = tb_meshless_frequency_at(c->ml, c->row + c->np); /* at the frame's start */
  for (int i = 0; i < m->n; i++) c->fsph[i] = force ? force[i] : tb_v3(0, 0, 0);
  const tb_vec3 *x = tb_meshless_positions(c->ml);
  for (int k = 0; k < c->nd; k++) c->fx0[k] = x[c->ids[k]];
  for (int s = 0; s < m->n; s++) c->fel[s] = tb_v3(0, 0, 0);
  for (int k = 0; k < c->nd; k++) {
    int p = c->ids[k], s = c->driver[p];
    if (s >= 0) c->fel[s] = tb_madd(c->fel[s], c->set.coupling, c->fpts[p]);
  }
  for (int s = 0; s < m->n; s++) { /* linearly implicit: F_eff = (F - b G - b m v / dt) / (1 + b) */
    if (!m->alive[s] || m->fixed[s] || c->ks[s] == 0) continue;
    double b = dt * dt * c->set.coupling * c->ks[s] * m->w[s];
    tb_vec3 G = tb_madd(c->fsph[s], m->m[s], gravity);
    tb_vec3 f = tb_madd(tb_madd(c->fel[s], -b, G), -b * m->m[s] / dt, m->v[s]);
    c->fsph[s] = tb_add(c->fsph[s], tb_scale(f, 1 / (1 + b)));
  }
  tb_metaball_step(m, dt, gravity, c->fsph);
  for (int k = 0; k < c->nd; k++) c->fx1[k] = follow(m, c, c->ids[k]);
  int K = c->set.substeps;
  if (K == 0) K = (int)fmin(ceil(dt * c->omega / (2 * c->set.cfl)), 1e6);
  if (K < 1) K = 1;
  c->last_substeps = K;
  for (int j = 1; j <= K; j++) {
    double t = (double)j / K;
    for (int k = 0; k < c->nd; k++) c->fx[k] = tb_lerp(c->fx0[k], c->fx1[k], t);
    if (tb_meshless_step(c->ml, dt / K, gravity, c->nd, c->ids, c->fx, err)) return -1;
  }
  return 0;
}

/* ---- getters ---- */

int tb_metaball_cutting(const tb_metaball *m) { return m->cut && m->cut->cutting; }
int tb_metaball_cut_points(const tb_metaball *m, const tb_vec3 **x) {
  const tb_metaball_cutstate *c = m->cut;
  int has = c && c->cutting && c->ml;
  if (x) *x = has ? tb_meshless_positions(c->ml) : NULL;
  return has ? c->np : 0;
}
const tb_meshless *tb_metaball_cut_meshless(const tb_metaball *m) {
  return m->cut && m->cut->cutting ? m->cut->ml : NULL;
}
int tb_metaball_cut_driver(const tb_metaball *m, int i) {
  const tb_metaball_cutstate *c = m->cut;
  return c && c->ml && i >= 0 && i < c->np ? c->driver[i] : -1;
}
int tb_metaball_alive(const tb_metaball *m, int i) { return i >= 0 && i < m->n && m->alive[i]; }
int tb_metaball_cut_substeps(const tb_metaball *m) { return m->cut ? m->cut->last_substeps : 0; }
double tb_metaball_cut_omega(const tb_metaball *m) { return m->cut ? m->cut->omega : 0; }
