/* Mass-spring model (thesis §3.2.1, eqs 3-1..3-6; SPEC §2.1).
 *
 * One spring per distinct tet edge, rest length from the rest mesh. The
 * Kelvin spring-damper of eq. 3-2 acts on node i as
 *   f_ij = k_e (|x_ij| - l_ij) x_ij / |x_ij| + kd (v_j - v_i),  x_ij = x_j - x_i,
 * summed per node (eq. 3-3), plus m_i g and the external forces (eq. 3-1),
 * integrated by symplectic Euler: v first (eq. 3-5), then x with the new v
 * (eq. 3-6). Lumped masses from density, or node_mass (default: unit
 * masses, as the thesis). A prescribed node
 * ends the step at fixed_x with velocity (fixed_x - x_old) / dt.
 *
 * calibrated=1: per-spring stiffness after Van Gelder 1998 ("Approximate
 * simulation of elastic membranes by triangulated spring meshes"), in its
 * tetrahedral form
 *   k_e = E * (sum of the volumes of the tets containing e) / l_e^2.
 * Normalisation: under an affine strain eps every edge stretches by
 * l (n^T eps n), so a tet stores (E V / 2) sum_{its 6 edges} (n^T eps n)^2.
 * Averaged over isotropically oriented edges, sum (n^T eps n)^2 =
 * 6 (tr(eps)^2 + 2 eps:eps) / 15, i.e. Lame mu = lambda = 0.4 E: Young's
 * modulus E exactly and Poisson ratio 1/4. nu cannot be set: central springs
 * obey the Cauchy relation (lambda = mu), so nu is not read. Exact for any
 * mesh: a dilation by s stores 3 E V_total (s - 1)^2 (bulk modulus 2E/3).
 * Real meshes are not isotropic and their nodes relax non-affinely, so the
 * effective modulus differs from E (measured in tests/test_msm.c). kd is
 * the same for every spring in both modes.
 *
 * Hot data are flat arrays: x, v, f, 1/m per node; (i, j), l0, k per spring.
 * A step allocates nothing.
 *
 * Node order. The model numbers the nodes internally in a spatial order
 * (tb_spatial_order: recursive coordinate bisection), fixed at create, and
 * keeps the springs sorted by (i, j), i < j, in that numbering; the step
 * reads the external forces and prescribed nodes through the permutation
 * and ends by copying x and v back into the mesh's node order, which
 * positions(), velocities(), correct() and masses() use. Every node sums,
 * after its external force, its springs in ascending spring order: first
 * its springs (i, n) by ascending i, then its springs (n, j) by ascending j.
 *
 * Threads (core/tb_threads.h). The nodes are split into nt contiguous parts
 * [n0, n1) of the internal numbering holding about ns / nt springs each (by
 * their first node): compact pieces of the body, so few springs cross
 * between them. A spring with i in a part and j beyond it ("crossing") is
 * computed first into fs (all parts at once); after one barrier each part,
 * alone: starts every node's force with the external force minus its
 * crossing springs from earlier parts (i < n0: the first of its (i, n)),
 * then runs the serial scatter over its own springs, taking a crossing
 * spring's force from fs, then integrates its nodes; after a second barrier
 * the copy back is split by mesh node. Every node thus sums its springs in
 * the same order for any part count: the same bits as the serial scatter,
 * which one thread runs.
 */
#include <math.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>

#include "tb_model.h"
#include "core/tb_threads.h"

/* Springs below which the step stays on one thread: a parallel region
 * costs more than it saves (on 2 cores, beside other work between steps as
 * the scaling suite runs them: 0.74x at 15 000 springs, 1.28x at 120 000). */
#define MSM_PARALLEL_MIN 40000
/* Parts of the threaded step at most (more threads share them). */
#define MSM_MAX_PARTS 256

/* msm's settings (its table is at the end of this file). */
typedef struct msm_settings {
  double density, node_mass, E, ks, kd;
  int calibrated;
} msm_settings;

typedef struct msm {
  int nv, ns;
  /* internal node order (see the head): old[n] is the mesh node of internal
   * node n, nw[m] the internal node of mesh node m */
  int *old, *nw;
  tb_vec3 *x, *v, *f; /* positions, velocities, force accumulator (internal) */
  tb_vec3 *xo, *vo;   /* positions and velocities in the mesh's node order */
  double *mass;       /* mesh order (masses()) */
  double *invm;       /* internal order */
  int *ij;            /* 2*ns internal node pairs, i < j, sorted */
  double *l0, *k;     /* rest lengths, stiffnesses */
  double kd;
  /* threads (see the head): crossing springs' forces; first[n]: the springs
   * whose first node is below n; node n's springs (i, n) are
   * in[in_start[n] .. in_start[n+1]), ascending, with their i in in_i */
  tb_vec3 *fs;
  int *first, *in_start, *in, *in_i;
  /* for the split into split_nt parts: part t is nodes [part[t], part[t+1]);
   * node n's springs first[n] .. cross[n] - 1 stay in its part, cross[n] ..
   * first[n+1] - 1 cross beyond it */
  int split_nt, part[MSM_MAX_PARTS + 1], *cross;
  int *fixedp; /* per step: 1 + the prescribed entry of internal node n, else 0 */
} msm;

static double edge_len(tb_vec3 a, tb_vec3 b) {
  double dx = b.x - a.x, dy = b.y - a.y, dz = b.z - a.z;
  return sqrt(dx * dx + dy * dy + dz * dz);
}

static void destroy(void *self) {
  msm *s = self;
  if (!s) return;
  free(s->old), free(s->nw), free(s->x), free(s->v), free(s->f), free(s->xo), free(s->vo);
  free(s->mass), free(s->invm);
  free(s->ij), free(s->l0), free(s->k);
  free(s->fs), free(s->first), free(s->in_start), free(s->in), free(s->in_i), free(s->fixedp);
  free(s->cross);
  free(s);
}

/* Index of edge (a, b), a < b, in the lexicographically sorted pairs, or -1. */
static int find_edge(const int *ij, int ns, int a, int b) {
  int lo = 0, hi = ns - 1;
  while (lo <= hi) {
    int mid = lo + (hi - lo) / 2;
    int c = ij[2 * mid] != a ? (ij[2 * mid] < a ? -1 : 1)
                             : (ij[2 * mid + 1] != b ? (ij[2 * mid + 1] < b ? -1 : 1) : 0);
    if (!c) return mid;
    if (c < 0)
      lo = mid + 1;
    else
      hi = mid - 1;
  }
  return -1;
}

/* Van Gelder stiffness: k_e = E * sum of adjacent tet volumes / l_e^2. */
static int calibrate(msm *s, const tb_mesh *mesh, double E, tb_error *err) {
  if (mesh->ntet < 1) return tb_error_set(err, "msm", 0, "calibrated springs need tets");
  memset(s->k, 0, sizeof(double) * (size_t)s->ns);
  static const int pairs[6][2] = {{0, 1}, {0, 2}, {0, 3}, {1, 2}, {1, 3}, {2, 3}};
  for (int t = 0; t < mesh->ntet; t++) {
    const int *n = mesh->tet + 4 * t;
    double vol = tb_tet_volume(mesh->x[n[0]], mesh->x[n[1]], mesh->x[n[2]], mesh->x[n[3]]);
    for (int p = 0; p < 6; p++) {
      int a = n[pairs[p][0]], b = n[pairs[p][1]];
      int e = a < b ? find_edge(s->ij, s->ns, a, b) : find_edge(s->ij, s->ns, b, a);
      if (e < 0) return tb_error_set(err, "msm", 0, "tet %d: edge %d-%d not found", t, a, b);
      s->k[e] += vol;
    }
  }
  for (int e = 0; e < s->ns; e++) s->k[e] *= E / (s->l0[e] * s->l0[e]);
  return 0;
}

/* The arrays of the threaded step (see the head and struct msm). */
static int node_springs(msm *s) {
  size_t ns = (size_t)s->ns, nv = (size_t)s->nv;
  s->fs = malloc(sizeof(tb_vec3) * (ns ? ns : 1));
  s->first = calloc(nv + 1, sizeof(int));
  s->in_start = calloc(nv + 1, sizeof(int));
  s->in = malloc(sizeof(int) * (ns ? ns : 1));
  s->in_i = malloc(sizeof(int) * (ns ? ns : 1));
  s->fixedp = calloc(nv ? nv : 1, sizeof(int));
  s->cross = malloc(sizeof(int) * (nv ? nv : 1));
  if (!s->fs || !s->first || !s->in_start || !s->in || !s->in_i || !s->fixedp || !s->cross)
    return -1;
  for (int e = 0; e < s->ns; e++) s->first[s->ij[2 * e] + 1]++, s->in_start[s->ij[2 * e + 1] + 1]++;
  for (int i = 0; i < s->nv; i++)
    s->first[i + 1] += s->first[i], s->in_start[i + 1] += s->in_start[i];
  int *fill = malloc(sizeof(int) * (nv ? nv : 1));
  if (!fill) return -1;
  memcpy(fill, s->in_start, sizeof(int) * nv);
  for (int e = 0; e < s->ns; e++) { /* ascending e */
    int q = fill[s->ij[2 * e + 1]]++;
    s->in[q] = e, s->in_i[q] = s->ij[2 * e];
  }
  free(fill);
  return 0;
}

/* The internal node order (see the head): nodes in the spatial order,
 * springs (mesh pairs, l0, k) renumbered and sorted by (i, j) again. */
static int renumber(msm *s, const tb_mesh *mesh) {
  const int nv = s->nv, ns = s->ns;
  s->old = malloc(sizeof(int) * (size_t)(nv ? nv : 1));
  s->nw = malloc(sizeof(int) * (size_t)(nv ? nv : 1));
  int *start = calloc((size_t)nv + 2, sizeof(int)), *ij = malloc(sizeof(int) * 2 * (ns ? ns : 1));
  double *l0 = malloc(sizeof(double) * (ns ? ns : 1)), *k = malloc(sizeof(double) * (ns ? ns : 1));
  int ok = s->old && s->nw && start && ij && l0 && k && !tb_spatial_order(mesh->x, nv, s->old);
  if (ok) {
    for (int n = 0; n < nv; n++) s->nw[s->old[n]] = n;
    for (int e = 0; e < ns; e++) {
      int a = s->nw[s->ij[2 * e]], b = s->nw[s->ij[2 * e + 1]];
      start[(a < b ? a : b) + 2]++;
    }
    for (int n = 0; n < nv; n++) start[n + 2] += start[n + 1];
    for (int e = 0; e < ns; e++) { /* into rows by first node (start[a + 1]: the fill) */
      int a = s->nw[s->ij[2 * e]], b = s->nw[s->ij[2 * e + 1]];
      int q = start[(a < b ? a : b) + 1]++;
      ij[2 * q] = a < b ? a : b, ij[2 * q + 1] = a < b ? b : a, l0[q] = s->l0[e], k[q] = s->k[e];
    }
    for (int n = 0; n < nv; n++) /* each row by second node (insertion: rows are short) */
      for (int q = start[n] + 1; q < start[n + 1]; q++) {
        int b = ij[2 * q + 1], r = q;
        double lq = l0[q], kq = k[q];
        for (; r > start[n] && ij[2 * (r - 1) + 1] > b; r--)
          ij[2 * r + 1] = ij[2 * (r - 1) + 1], l0[r] = l0[r - 1], k[r] = k[r - 1];
        ij[2 * r + 1] = b, l0[r] = lq, k[r] = kq;
      }
    free(s->ij), free(s->l0), free(s->k);
    s->ij = ij, s->l0 = l0, s->k = k;
    ij = NULL, l0 = k = NULL;
  }
  free(start), free(ij), free(l0), free(k);
  return ok ? 0 : -1;
}

static void *create(const tb_mesh *mesh, const void *settings, tb_error *err) {
  const msm_settings *def = settings;
  if (tb_check_tets(mesh, err)) return NULL;
  msm *s = calloc(1, sizeof *s);
  if (!s) {
    tb_error_set(err, "msm", 0, "out of memory");
    return NULL;
  }
  s->nv = mesh->nv;
  s->kd = def->kd;
  size_t nv = (size_t)mesh->nv;
  s->x = malloc(sizeof(tb_vec3) * (nv ? nv : 1));
  s->v = calloc(nv ? nv : 1, sizeof(tb_vec3));
  s->f = calloc(nv ? nv : 1, sizeof(tb_vec3));
  s->xo = malloc(sizeof(tb_vec3) * (nv ? nv : 1));
  s->vo = calloc(nv ? nv : 1, sizeof(tb_vec3));
  s->mass = malloc(sizeof(double) * (nv ? nv : 1));
  s->invm = malloc(sizeof(double) * (nv ? nv : 1));
  if (!s->x || !s->v || !s->f || !s->xo || !s->vo || !s->mass || !s->invm) {
    tb_error_set(err, "msm", 0, "out of memory");
    goto fail;
  }
  memcpy(s->xo, mesh->x, sizeof(tb_vec3) * nv);
  if (tb_lumped_masses(mesh, def->density, def->node_mass, s->mass, err)) goto fail;

  s->ns = tb_mesh_edges(mesh, &s->ij);
  if (s->ns < 0) {
    s->ns = 0;
    tb_error_set(err, "msm", 0, "out of memory");
    goto fail;
  }
  size_t ns = (size_t)s->ns;
  s->l0 = malloc(sizeof(double) * (ns ? ns : 1));
  s->k = malloc(sizeof(double) * (ns ? ns : 1));
  if (!s->l0 || !s->k) {
    tb_error_set(err, "msm", 0, "out of memory");
    goto fail;
  }
  for (int e = 0; e < s->ns; e++) {
    int i = s->ij[2 * e], j = s->ij[2 * e + 1];
    if (i < 0 || j >= s->nv) { /* triangles of a mesh without tets are not checked above */
      tb_error_set(err, "mesh", 0, "edge %d-%d refers to a node outside [0, %d)", i, j, s->nv);
      goto fail;
    }
    s->l0[e] = edge_len(mesh->x[i], mesh->x[j]);
    if (!(s->l0[e] > 0) || !isfinite(s->l0[e])) {
      tb_error_set(err, "mesh", 0, "edge %d-%d has rest length %g (coincident nodes)", i, j,
                   s->l0[e]);
      goto fail;
    }
    s->k[e] = def->ks;
  }
  if (def->calibrated && calibrate(s, mesh, def->E, err)) goto fail;
  if (renumber(s, mesh)) {
    tb_error_set(err, "msm", 0, "out of memory");
    goto fail;
  }
  for (int n = 0; n < s->nv; n++)
    s->x[n] = mesh->x[s->old[n]], s->invm[n] = 1.0 / s->mass[s->old[n]];
  if (node_springs(s)) {
    tb_error_set(err, "msm", 0, "out of memory");
    goto fail;
  }
  return s;
fail:
  destroy(s);
  return NULL;
}

/* Kelvin springs (eqs 3-2, 3-3) accumulated into f. (Summing f_i in
 * registers over i's run of sorted springs, or packing sqrt/div two at a
 * time with SSE2, gained at most 12% on the liver: not worth the code.) */
static void spring_forces(int ns, const int *restrict ij, const double *restrict l0,
                          const double *restrict k, double kd, const tb_vec3 *restrict x,
                          const tb_vec3 *restrict v, tb_vec3 *restrict f) {
  for (int e = 0; e < ns; e++) {
    const int i = ij[2 * e], j = ij[2 * e + 1];
    const double dx = x[j].x - x[i].x, dy = x[j].y - x[i].y, dz = x[j].z - x[i].z;
    const double len = sqrt(dx * dx + dy * dy + dz * dz);
    const double c = len > 0 ? k[e] * (len - l0[e]) / len : 0.0; /* no direction: no spring force */
    const double fx = c * dx + kd * (v[j].x - v[i].x);
    const double fy = c * dy + kd * (v[j].y - v[i].y);
    const double fz = c * dz + kd * (v[j].z - v[i].z);
    f[i].x += fx, f[i].y += fy, f[i].z += fz;
    f[j].x -= fx, f[j].y -= fy, f[j].z -= fz;
  }
}

/* Kelvin spring e's force on its first node (eq. 3-2). */
static inline tb_vec3 spring_force(const msm *s, int e, const tb_vec3 *restrict x,
                                   const tb_vec3 *restrict v) {
  const int i = s->ij[2 * e], j = s->ij[2 * e + 1];
  const double dx = x[j].x - x[i].x, dy = x[j].y - x[i].y, dz = x[j].z - x[i].z;
  const double len = sqrt(dx * dx + dy * dy + dz * dz);
  const double c = len > 0 ? s->k[e] * (len - s->l0[e]) / len : 0.0;
  return tb_v3(c * dx + s->kd * (v[j].x - v[i].x), c * dy + s->kd * (v[j].y - v[i].y),
               c * dz + s->kd * (v[j].z - v[i].z));
}

/* Node i's step with force fi: symplectic Euler (eqs 3-4..3-6), or, when
 * prescribed (fixedp[i] = p + 1), to fixed_x[p] with the velocity that
 * moved it there. */
static inline void advance(const msm *s, const tb_step *in, int i, tb_vec3 fi) {
  tb_vec3 *restrict x = s->x, *restrict v = s->v;
  const double dt = in->dt;
  if (s->fixedp[i]) {
    const tb_vec3 xe = in->fixed_x[s->fixedp[i] - 1];
    v[i].x = (xe.x - x[i].x) / dt, v[i].y = (xe.y - x[i].y) / dt, v[i].z = (xe.z - x[i].z) / dt;
    x[i] = xe;
    return;
  }
  const double invm = s->invm[i];
  const tb_vec3 g = in->gravity;
  v[i].x += dt * (g.x + fi.x * invm);
  v[i].y += dt * (g.y + fi.y * invm);
  v[i].z += dt * (g.z + fi.z * invm);
  x[i].x += dt * v[i].x, x[i].y += dt * v[i].y, x[i].z += dt * v[i].z;
}

/* Mesh nodes [m0, m1) of x and v copied into the mesh's order. */
static void copy_back(msm *s, int m0, int m1) {
  const int *restrict nw = s->nw;
  for (int m = m0; m < m1; m++) s->xo[m] = s->x[nw[m]], s->vo[m] = s->v[nw[m]];
}

/* The first node of part t of nt: the smallest n with first[n] >= t ns / nt. */
static int part_start(const msm *s, int t, int nt) {
  if (t >= nt) return s->nv;
  long target = (long)s->ns * t / nt;
  int lo = 0, hi = s->nv;
  while (lo < hi) {
    int mid = lo + (hi - lo) / 2;
    if (s->first[mid] >= target)
      hi = mid;
    else
      lo = mid + 1;
  }
  return lo;
}

/* The split into nt parts (part, cross), kept until nt changes. */
static void split(msm *s, int nt) {
  if (s->split_nt == nt) return;
  for (int t = 0; t <= nt; t++) s->part[t] = part_start(s, t, nt);
  for (int t = 0; t < nt; t++)
    for (int n = s->part[t]; n < s->part[t + 1]; n++) {
      int e = s->first[n + 1];
      while (e > s->first[n] && s->ij[2 * (e - 1) + 1] >= s->part[t + 1]) e--;
      s->cross[n] = e;
    }
  s->split_nt = nt;
}

/* Part [n0, n1)'s springs that cross beyond n1, into fs. */
static void part_crossing(msm *s, int n0, int n1) {
  const tb_vec3 *restrict x = s->x, *restrict v = s->v;
  tb_vec3 *restrict fs = s->fs;
  for (int n = n0; n < n1; n++)
    for (int e = s->cross[n]; e < s->first[n + 1]; e++) fs[e] = spring_force(s, e, x, v);
}

/* Part [n0, n1) after the crossing springs: its nodes' forces in ascending
 * spring order (see the head), then their integration. */
static void part_step(msm *s, const tb_step *in, int n0, int n1) {
  tb_vec3 *restrict x = s->x, *restrict v = s->v, *restrict f = s->f;
  const tb_vec3 *restrict fs = s->fs, *restrict ext = in->force;
  const int *restrict ij = s->ij, *restrict in_start = s->in_start, *restrict in_e = s->in,
                      *restrict in_i = s->in_i, *restrict first = s->first,
                      *restrict cross = s->cross, *restrict old = s->old;
  const double *restrict l0 = s->l0, *restrict k = s->k;
  const double kd = s->kd;
  for (int n = n0; n < n1; n++) { /* external force, crossing springs from below */
    tb_vec3 fn = ext ? ext[old[n]] : tb_v3(0, 0, 0);
    for (int q = in_start[n]; q < in_start[n + 1] && in_i[q] < n0; q++) {
      const tb_vec3 c = fs[in_e[q]];
      fn.x -= c.x, fn.y -= c.y, fn.z -= c.z;
    }
    f[n] = fn;
  }
  for (int i = n0; i < n1; i++) { /* the serial scatter, node by node */
    for (int e = first[i]; e < cross[i]; e++) {
      const int j = ij[2 * e + 1];
      const double dx = x[j].x - x[i].x, dy = x[j].y - x[i].y, dz = x[j].z - x[i].z;
      const double len = sqrt(dx * dx + dy * dy + dz * dz);
      const double c = len > 0 ? k[e] * (len - l0[e]) / len : 0.0;
      const double fx = c * dx + kd * (v[j].x - v[i].x);
      const double fy = c * dy + kd * (v[j].y - v[i].y);
      const double fz = c * dz + kd * (v[j].z - v[i].z);
      f[i].x += fx, f[i].y += fy, f[i].z += fz;
      f[j].x -= fx, f[j].y -= fy, f[j].z -= fz;
    }
    for (int e = cross[i]; e < first[i + 1]; e++) /* its springs beyond the part: last */
      f[i].x += fs[e].x, f[i].y += fs[e].y, f[i].z += fs[e].z;
  }
  for (int n = n0; n < n1; n++) advance(s, in, n, f[n]);
}

/* The threaded step's forces and integration in nt parts (see the head). */
static void step_threads(msm *s, const tb_step *in, int nt) {
  const int *part = s->part;
#pragma omp parallel
  {
#pragma omp for schedule(static)
    for (int t = 0; t < nt; t++) part_crossing(s, part[t], part[t + 1]);
#pragma omp for schedule(static)
    for (int t = 0; t < nt; t++) part_step(s, in, part[t], part[t + 1]);
#pragma omp for schedule(static)
    for (int t = 0; t < nt; t++)
      copy_back(s, (int)((long)s->nv * t / nt), (int)((long)s->nv * (t + 1) / nt));
  }
}

static int step(void *self, const tb_step *in, tb_error *err) {
  msm *s = self;
  const int nv = s->nv, nfixed = in->nfixed;
  if (nfixed < 0 || (nfixed > 0 && (!in->fixed || !in->fixed_x)))
    return tb_error_set(err, "msm", 0, "bad prescribed set (nfixed %d)", nfixed);
  for (int p = 0; p < nfixed; p++)
    if (in->fixed[p] < 0 || in->fixed[p] >= nv || (p > 0 && in->fixed[p] <= in->fixed[p - 1]))
      return tb_error_set(err, "msm", 0,
                          "prescribed nodes must be strictly ascending in [0, %d): entry %d is %d",
                          nv, p, in->fixed[p]);
  /* fixed_x may alias the positions (holding nodes where they are): it is
   * read before the copy back */
  for (int p = 0; p < nfixed; p++) s->fixedp[s->nw[in->fixed[p]]] = p + 1;
  const int nt = tb_threads() < MSM_MAX_PARTS ? tb_threads() : MSM_MAX_PARTS;
  if (nt > 1 && s->ns >= MSM_PARALLEL_MIN) {
    split(s, nt);
    step_threads(s, in, nt);
  } else {
    tb_vec3 *f = s->f;
    const int *old = s->old;
    /* external forces (eq. 3-1); gravity is added as an acceleration */
    for (int n = 0; n < nv; n++) f[n] = in->force ? in->force[old[n]] : tb_v3(0, 0, 0);
    spring_forces(s->ns, s->ij, s->l0, s->k, s->kd, s->x, s->v, f);
    for (int n = 0; n < nv; n++) advance(s, in, n, f[n]);
    copy_back(s, 0, nv);
  }
  for (int p = 0; p < nfixed; p++) s->fixedp[s->nw[in->fixed[p]]] = 0;
  return 0;
}

static const tb_vec3 *positions(const void *self) { return ((const msm *)self)->xo; }
static const tb_vec3 *velocities(const void *self) { return ((const msm *)self)->vo; }

/* sum 1/2 k (|x_ij| - l_ij)^2 + sum 1/2 m |v|^2 (no gravity potential) */
static double energy(const void *self) {
  const msm *s = self;
  double w = 0, t = 0;
  for (int e = 0; e < s->ns; e++) {
    double d = edge_len(s->x[s->ij[2 * e]], s->x[s->ij[2 * e + 1]]) - s->l0[e];
    w += 0.5 * s->k[e] * d * d;
  }
  for (int i = 0; i < s->nv; i++) t += 0.5 * s->mass[i] * tb_dot(s->vo[i], s->vo[i]);
  return w + t;
}

static const double *masses(const void *self) { return ((const msm *)self)->mass; }

static void correct(void *self, int n, const int *ids, const tb_vec3 *x, const tb_vec3 *v) {
  msm *s = self;
  for (int k = 0; k < n; k++) {
    if (x) s->x[s->nw[ids[k]]] = s->xo[ids[k]] = x[k];
    if (v) s->v[s->nw[ids[k]]] = s->vo[ids[k]] = v[k];
  }
}

#define S msm_settings
static const tb_setting settings[] = {
    TB_SETTINGS_MASS(S, 1.0), /* the thesis's unit node masses */
    TB_SETTING_R(S, ks, 180.0, 0.0, HUGE_VAL, 0, "spring stiffness (eq. 3-2)"),
    TB_SETTING_R(S, kd, 5.0, 0.0, HUGE_VAL, 0, "spring damping (eq. 3-2)"),
    TB_SETTING_I(S, calibrated, 0, 0, 1,
                 "1: stiffness per spring from E (Van Gelder 1998) instead of ks"),
    TB_SETTING_YOUNG(S, "Young's modulus the calibrated springs follow"),
};
#undef S

const tb_model_class tb_model_msm = {
    .name = "msm",
    .summary =
        "mass-spring: Kelvin springs on the tet edges, symplectic Euler (thesis eqs "
        "3-1..3-6)",
    .settings = settings,
    .nsettings = (int)(sizeof settings / sizeof settings[0]),
    .settings_size = sizeof(msm_settings),
    .create = create,
    .step = step,
    .positions = positions,
    .velocities = velocities,
    .energy = energy,
    .destroy = destroy,
    .masses = masses,
    .correct = correct,
};
