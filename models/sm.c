/* Meshless deformation by shape matching (Müller, Heidelberger, Teschner,
 * Gross 2005; thesis §3.4, eqs. 3-33..3-45; SPEC §2.3). The nodes are
 * particles; in each cluster the rest shape q_i = x0_i - x0_cm is matched to
 * the current positions: x_cm (eq. 3-34), A_pq = sum m p q^T and R its polar
 * rotation (eq. 3-36), goals g_i = T q_i + x_cm (eq. 3-37) with T = R
 * (rigid), beta A / cbrt(det A) + (1 - beta) R, A = A_pq A_qq^-1 (linear),
 * or beta A~ + (1 - beta) [R 0 0] on the 9-vector q~ (quadratic, eqs.
 * 3-43..3-45). A node's goal is the mean of its clusters' goals, and eq. 3-41
 * integrates:
 *   v += alpha (g - x) / h + h (gravity + f_ext / m);  v *= 1 - sm_damping;
 *   x += h v.
 * Choices beyond the paper, all fixed at create:
 *  - a node in n clusters weighs m / n in each (as in Rivers & James 2007),
 *    so every cluster's matching forces sum to zero and momentum is kept;
 *  - the quadratic monomials are centred by their weighted mean and the
 *    cluster is scaled to unit RMS radius first: a quadratic deformation is
 *    then reproduced exactly, and sum m q~ = 0 again keeps momentum;
 *  - A_qq (3x3 or 9x9) is inverted through its eigen-decomposition with
 *    eigenvalues below 1e-10 of the largest dropped (a pseudo-inverse): few
 *    or coplanar particles give a least-squares fit on the directions they
 *    span, never a NaN. Linear mode falls back to R when det A <= 0;
 *  - R comes from Higham's scaled Newton iteration (tb_m3_polar_newton; tb_m3_polar for inverted
 *    or singular A_pq): the same rotation, about 3x faster.
 * The step allocates nothing; the member loops read flat CSR arrays.
 *
 * Threads (core/tb_threads.h): each cluster is matched whole by one thread
 * (clusters handed out dynamically: their sizes differ), its goals written
 * per member into gm; then each node sums its clusters' goals in ascending
 * cluster order through a node -> member list (CSR) and integrates. That is
 * the order one pass over the clusters adds them in, so the positions are
 * the same bits for any thread count. */
#include <math.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>

#include "tb_sm.h"
#include "core/tb_threads.h"

/* Cluster members below which the step stays on one thread: a parallel
 * region costs more than it saves (on 2 cores, beside other work between
 * steps as the scaling suite runs them: 0.83x at 5000 members, 1.42x at
 * 35 000). */
#define SM_PARALLEL_MIN 8000

extern const tb_model_class tb_model_sm;

/* sm's settings (its table is at the end of this file). */
typedef struct sm_settings {
  double density, node_mass;
  int sm_mode;       /* TB_SM_* */
  double alpha;      /* stiffness in [0, 1] */
  double beta;       /* linear/quadratic blend in [0, 1] */
  int clusters;      /* number of regions (TB_CLUSTER_REGIONS); 1 = the whole body */
  double radius;     /* region radius (nodes outside every region join the nearest) */
  int cluster_mode;  /* TB_CLUSTER_* */
  double sm_damping; /* velocity damping per step in [0, 1) */
} sm_settings;

typedef struct sm {
  int nv, mode, dim; /* dim: 3 (rigid, linear) or 9 (quadratic) */
  double alpha, beta, damping;
  tb_vec3 *x, *v;        /* hot state */
  tb_vec3 *goal;         /* per step, one thread: the sum of the node's cluster goals */
  tb_vec3 *gm;           /* per step, threads: each member's goal in its cluster */
  int *nstart, *nmember; /* node -> its member slots in the clusters, ascending */
  unsigned char *fixed;  /* per step: prescribed nodes */
  double *mass, *inv_mass, *inv_count;
  /* clusters: CSR members, per member weight and rest vector, per cluster
   * 1 / sum of weights, length scale and A_qq^-1 (dim x dim) */
  tb_sm_clusters cl;
  double *w, *q, *inv_wsum, *scale, *aqq_inv;
  int *group; /* per node: its first cluster (pictures) */
} sm;

/* ---- precomputation ---- */

/* Pseudo-inverse of a symmetric positive semi-definite n x n matrix (n <= 9,
 * row-major) by cyclic Jacobi: eigenvalues <= 1e-10 * largest are dropped. */
static void sym_pinv(int n, const double *a_in, double *inv) {
  double a[81], v[81], fro = 0;
  memcpy(a, a_in, sizeof(double) * (size_t)(n * n));
  for (int i = 0; i < n * n; i++) v[i] = (i / n == i % n), fro += a[i] * a[i];
  for (int sweep = 0; sweep < 60; sweep++) {
    double off = 0;
    for (int p = 0; p < n; p++)
      for (int q = p + 1; q < n; q++) off += a[p * n + q] * a[p * n + q];
    if (off <= 1e-32 * fro) break;
    for (int p = 0; p < n; p++)
      for (int q = p + 1; q < n; q++) {
        double apq = a[p * n + q];
        if (apq == 0.0) continue;
        double theta = (a[q * n + q] - a[p * n + p]) / (2.0 * apq);
        double t = (theta >= 0 ? 1.0 : -1.0) / (fabs(theta) + sqrt(theta * theta + 1.0));
        double c = 1.0 / sqrt(t * t + 1.0), s = t * c;
        for (int k = 0; k < n; k++) { /* a <- a J */
          double akp = a[k * n + p], akq = a[k * n + q];
          a[k * n + p] = c * akp - s * akq, a[k * n + q] = s * akp + c * akq;
        }
        for (int k = 0; k < n; k++) { /* a <- J^T a */
          double apk = a[p * n + k], aqk = a[q * n + k];
          a[p * n + k] = c * apk - s * aqk, a[q * n + k] = s * apk + c * aqk;
        }
        for (int k = 0; k < n; k++) { /* v <- v J */
          double vkp = v[k * n + p], vkq = v[k * n + q];
          v[k * n + p] = c * vkp - s * vkq, v[k * n + q] = s * vkp + c * vkq;
        }
      }
  }
  double lmax = 0;
  for (int k = 0; k < n; k++) lmax = fmax(lmax, a[k * n + k]);
  memset(inv, 0, sizeof(double) * (size_t)(n * n));
  if (!(lmax > 0) || !isfinite(lmax)) return;
  for (int k = 0; k < n; k++) {
    double l = a[k * n + k];
    if (!(l > 1e-10 * lmax)) continue;
    for (int i = 0; i < n; i++)
      for (int j = 0; j < n; j++) inv[i * n + j] += v[i * n + k] * v[j * n + k] / l;
  }
}

/* The rest vectors of cluster c (members b..e-1): centred, and for the
 * quadratic mode scaled to unit RMS radius, extended to the 9 monomials and
 * centred again. Then A_qq^-1. */
static void precompute_cluster(sm *s, const tb_vec3 *x0, int c) {
  int b = s->cl.start[c], e = s->cl.start[c + 1], d = s->dim;
  double W = 0;
  tb_vec3 cm = tb_v3(0, 0, 0);
  for (int k = b; k < e; k++) W += s->w[k], cm = tb_madd(cm, s->w[k], x0[s->cl.node[k]]);
  cm = tb_scale(cm, 1.0 / W);
  s->inv_wsum[c] = 1.0 / W;
  double r2 = 0;
  for (int k = b; k < e; k++) {
    tb_vec3 q = tb_sub(x0[s->cl.node[k]], cm);
    r2 += s->w[k] * tb_dot(q, q);
    double *qk = s->q + (size_t)d * k;
    qk[0] = q.x, qk[1] = q.y, qk[2] = q.z;
  }
  double scale = d == 9 ? sqrt(r2 / W) : 1.0;
  if (!(scale > 0)) scale = 1.0;
  s->scale[c] = scale;
  double mean[9] = {0};
  for (int k = b; k < e && d == 9; k++) {
    double *f = s->q + (size_t)9 * k;
    double qx = f[0] / scale, qy = f[1] / scale, qz = f[2] / scale;
    f[0] = qx, f[1] = qy, f[2] = qz;
    f[3] = qx * qx, f[4] = qy * qy, f[5] = qz * qz;
    f[6] = qx * qy, f[7] = qy * qz, f[8] = qz * qx;
    for (int j = 0; j < 9; j++) mean[j] += s->w[k] * f[j] / W;
  }
  double aqq[81] = {0};
  for (int k = b; k < e; k++) {
    double *f = s->q + (size_t)d * k;
    if (d == 9)
      for (int j = 0; j < 9; j++) f[j] -= mean[j];
    for (int i = 0; i < d; i++)
      for (int j = 0; j < d; j++) aqq[i * d + j] += s->w[k] * f[i] * f[j];
  }
  sym_pinv(d, aqq, s->aqq_inv + (size_t)d * d * c);
}

static void destroy(void *self) {
  sm *s = self;
  if (!s) return;
  free(s->x), free(s->v), free(s->goal), free(s->gm), free(s->nstart), free(s->nmember),
      free(s->fixed);
  free(s->mass), free(s->inv_mass), free(s->inv_count);
  tb_sm_clusters_free(&s->cl);
  free(s->w), free(s->q), free(s->inv_wsum), free(s->scale), free(s->aqq_inv);
  free(s->group);
  free(s);
}

static void *create(const tb_mesh *mesh, const void *settings, tb_error *err) {
  const sm_settings *def = settings;
  if (def->sm_mode < TB_SM_RIGID || def->sm_mode > TB_SM_QUADRATIC) {
    tb_error_set(err, "sm", 0, "bad sm_mode %d", def->sm_mode);
    return NULL;
  }
  if (mesh->ntet < 1 && !(def->node_mass > 0)) {
    tb_error_set(err, "sm", 0,
                 "the mesh has no tets (a point cloud): set node_mass > 0 for the particle "
                 "masses");
    return NULL;
  }
  sm *s = calloc(1, sizeof *s);
  if (!s) {
    tb_error_set(err, "sm", 0, "out of memory");
    return NULL;
  }
  if (tb_sm_clusters_build(mesh, def->cluster_mode, def->clusters, def->radius, &s->cl, err)) {
    free(s);
    return NULL;
  }
  int nv = mesh->nv, nc = s->cl.n, nm = s->cl.start[nc];
  s->nv = nv, s->mode = def->sm_mode, s->dim = def->sm_mode == TB_SM_QUADRATIC ? 9 : 3;
  s->alpha = def->alpha, s->beta = def->beta, s->damping = def->sm_damping;
  size_t d = (size_t)s->dim;
  s->x = malloc(sizeof(tb_vec3) * (size_t)nv);
  s->v = calloc((size_t)nv, sizeof(tb_vec3));
  s->goal = malloc(sizeof(tb_vec3) * (size_t)nv);
  s->gm = malloc(sizeof(tb_vec3) * (size_t)nm);
  s->nstart = calloc((size_t)nv + 1, sizeof(int));
  s->nmember = malloc(sizeof(int) * (size_t)nm);
  s->fixed = calloc((size_t)nv, 1);
  s->mass = malloc(sizeof(double) * (size_t)nv);
  s->inv_mass = malloc(sizeof(double) * (size_t)nv);
  s->inv_count = calloc((size_t)nv, sizeof(double));
  s->w = malloc(sizeof(double) * (size_t)nm);
  s->q = malloc(sizeof(double) * d * (size_t)nm);
  s->inv_wsum = malloc(sizeof(double) * (size_t)nc);
  s->scale = malloc(sizeof(double) * (size_t)nc);
  s->aqq_inv = malloc(sizeof(double) * d * d * (size_t)nc);
  s->group = malloc(sizeof(int) * (size_t)nv);
  if (!s->x || !s->v || !s->goal || !s->gm || !s->nstart || !s->nmember || !s->fixed || !s->mass ||
      !s->inv_mass || !s->inv_count || !s->w || !s->q || !s->inv_wsum || !s->scale || !s->aqq_inv ||
      !s->group) {
    destroy(s);
    tb_error_set(err, "sm", 0, "out of memory");
    return NULL;
  }
  memcpy(s->x, mesh->x, sizeof(tb_vec3) * (size_t)nv);
  double *mass = s->mass;
  if (tb_lumped_masses(mesh, def->density, def->node_mass, mass, err)) {
    destroy(s);
    return NULL;
  }
  for (int k = 0; k < nm; k++) s->inv_count[s->cl.node[k]] += 1.0; /* counts for now */
  for (int k = 0; k < nm; k++) s->w[k] = mass[s->cl.node[k]] / s->inv_count[s->cl.node[k]];
  for (int i = 0; i < nv; i++)
    s->inv_count[i] = 1.0 / s->inv_count[i], s->inv_mass[i] = 1.0 / mass[i];
  for (int c = 0; c < nc; c++) precompute_cluster(s, mesh->x, c);
  /* node -> member slots: slots ascend with the cluster, so each node's do */
  for (int k = 0; k < nm; k++) s->nstart[s->cl.node[k] + 1]++;
  for (int i = 0; i < nv; i++) s->nstart[i + 1] += s->nstart[i];
  for (int k = 0; k < nm; k++) s->nmember[s->nstart[s->cl.node[k]]++] = k;
  for (int i = nv; i > 0; i--) s->nstart[i] = s->nstart[i - 1];
  s->nstart[0] = 0;
  for (int i = 0; i < nv; i++) s->group[i] = -1;
  for (int c = nc - 1; c >= 0; c--) /* downwards: the first cluster is written last */
    for (int k = s->cl.start[c]; k < s->cl.start[c + 1]; k++) s->group[s->cl.node[k]] = c;
  return s;
}

/* ---- the step ---- */

/* Member k's goal g: added to its node's sum (scatter, one thread), else
 * kept in its slot for the nodes to gather. */
static inline void put_goal(sm *s, int k, tb_vec3 g, int scatter) {
  if (scatter) {
    tb_vec3 *n = &s->goal[s->cl.node[k]];
    n->x += g.x, n->y += g.y, n->z += g.z;
  } else {
    s->gm[k] = g;
  }
}

/* Cluster goals, quadratic mode: A~_pq = sum w p q~^T, one pass per row (the
 * weighted sum of q~ is zero, so p may be taken from any reference point),
 * R from its linear block, T = beta A~_pq A~_qq^-1 + (1 - beta) [s R 0 0]. */
static void goals_quadratic(sm *s, int c, int scatter) {
  const int *node = s->cl.node;
  const tb_vec3 *x = s->x;
  double beta = s->beta;
  {
    int b = s->cl.start[c], e = s->cl.start[c + 1];
    tb_vec3 xr = x[node[b]];
    double sum[3], apq[3][9];
    for (int r = 0; r < 3; r++) { /* row by row: 10 accumulators stay in registers */
      double xrr = tb_comp(xr, r);
      double a0 = 0, a1 = 0, a2 = 0, a3 = 0, a4 = 0, a5 = 0, a6 = 0, a7 = 0, a8 = 0, sr = 0;
      for (int k = b; k < e; k++) {
        const double *q = s->q + (size_t)9 * k;
        double p = s->w[k] * (tb_comp(x[node[k]], r) - xrr);
        sr += p;
        a0 += p * q[0], a1 += p * q[1], a2 += p * q[2], a3 += p * q[3], a4 += p * q[4];
        a5 += p * q[5], a6 += p * q[6], a7 += p * q[7], a8 += p * q[8];
      }
      sum[r] = sr;
      apq[r][0] = a0, apq[r][1] = a1, apq[r][2] = a2, apq[r][3] = a3, apq[r][4] = a4;
      apq[r][5] = a5, apq[r][6] = a6, apq[r][7] = a7, apq[r][8] = a8;
    }
    double iw = s->inv_wsum[c];
    tb_vec3 cm = tb_v3(xr.x + sum[0] * iw, xr.y + sum[1] * iw, xr.z + sum[2] * iw);
    tb_mat3 lin;
    for (int i = 0; i < 3; i++)
      for (int j = 0; j < 3; j++) lin.m[i][j] = apq[i][j];
    tb_mat3 r = tb_m3_polar_newton(lin);
    const double *inv = s->aqq_inv + (size_t)81 * c;
    double t[3][9];
    for (int i = 0; i < 3; i++) {
      for (int j = 0; j < 9; j++) t[i][j] = 0;
      for (int l = 0; l < 9; l++) {
        double a = beta * apq[i][l];
        for (int j = 0; j < 9; j++) t[i][j] += a * inv[l * 9 + j];
      }
      for (int j = 0; j < 3; j++) t[i][j] += (1.0 - beta) * s->scale[c] * r.m[i][j];
    }
    for (int k = b; k < e; k++) {
      const double *q = s->q + (size_t)9 * k;
      double gx = cm.x, gy = cm.y, gz = cm.z;
      for (int j = 0; j < 9; j++) gx += t[0][j] * q[j], gy += t[1][j] * q[j], gz += t[2][j] * q[j];
      put_goal(s, k, tb_v3(gx, gy, gz), scatter);
    }
  }
}

/* Cluster goals, rigid and linear modes (3-vectors q). */
static void goals_linear(sm *s, int c, int scatter) {
  const int *node = s->cl.node;
  const tb_vec3 *x = s->x;
  double beta = s->beta;
  {
    int b = s->cl.start[c], e = s->cl.start[c + 1];
    tb_vec3 xr = x[node[b]];
    double sx = 0, sy = 0, sz = 0; /* scalar accumulators: they stay in registers */
    double a00 = 0, a01 = 0, a02 = 0, a10 = 0, a11 = 0, a12 = 0, a20 = 0, a21 = 0, a22 = 0;
    for (int k = b; k < e; k++) {
      const double *q = s->q + (size_t)3 * k;
      tb_vec3 xi = x[node[k]];
      double wk = s->w[k];
      double px = wk * (xi.x - xr.x), py = wk * (xi.y - xr.y), pz = wk * (xi.z - xr.z);
      sx += px, sy += py, sz += pz;
      a00 += px * q[0], a01 += px * q[1], a02 += px * q[2];
      a10 += py * q[0], a11 += py * q[1], a12 += py * q[2];
      a20 += pz * q[0], a21 += pz * q[1], a22 += pz * q[2];
    }
    tb_mat3 apq;
    apq.m[0][0] = a00, apq.m[0][1] = a01, apq.m[0][2] = a02;
    apq.m[1][0] = a10, apq.m[1][1] = a11, apq.m[1][2] = a12;
    apq.m[2][0] = a20, apq.m[2][1] = a21, apq.m[2][2] = a22;
    double iw = s->inv_wsum[c];
    tb_vec3 cm = tb_v3(xr.x + sx * iw, xr.y + sy * iw, xr.z + sz * iw);
    tb_mat3 t = tb_m3_polar_newton(apq);
    if (s->mode == TB_SM_LINEAR && beta > 0) {
      tb_mat3 inv;
      memcpy(inv.m, s->aqq_inv + (size_t)9 * c, sizeof inv.m);
      tb_mat3 a = tb_m3_mul(apq, inv);
      double det = tb_m3_det(a);
      if (det > 0 && isfinite(det)) {
        double f = beta / cbrt(det);
        for (int i = 0; i < 3; i++)
          for (int j = 0; j < 3; j++) t.m[i][j] = f * a.m[i][j] + (1.0 - beta) * t.m[i][j];
      }
    }
    for (int k = b; k < e; k++) {
      const double *q = s->q + (size_t)3 * k;
      put_goal(s, k, tb_add(cm, tb_m3_mulv(t, tb_v3(q[0], q[1], q[2]))), scatter);
    }
  }
}

/* Eq. 3-41 for free node i whose clusters' goals sum to g. */
static inline void advance(sm *s, int i, tb_vec3 g, const tb_step *in) {
  const double h = in->dt, ah = s->alpha / h, keep = 1.0 - s->damping;
  const tb_vec3 xi = s->x[i];
  g = tb_scale(g, s->inv_count[i]);
  tb_vec3 vi = tb_add(s->v[i], tb_add(tb_scale(tb_sub(g, xi), ah), tb_scale(in->gravity, h)));
  if (in->force) vi = tb_madd(vi, h * s->inv_mass[i], in->force[i]);
  vi = tb_scale(vi, keep);
  s->v[i] = vi;
  s->x[i] = tb_madd(xi, h, vi);
}

static int step(void *self, const tb_step *in, tb_error *err) {
  sm *s = self;
  int nv = s->nv;
  if (in->nfixed < 0 || (in->nfixed > 0 && (!in->fixed || !in->fixed_x)))
    return tb_error_set(err, "sm", 0, "bad prescribed-node list");
  for (int j = 0; j < in->nfixed; j++)
    if (in->fixed[j] < 0 || in->fixed[j] >= nv || (j > 0 && in->fixed[j] <= in->fixed[j - 1]))
      return tb_error_set(err, "sm", 0,
                          "prescribed nodes must be strictly ascending in [0, %d) (entry %d: %d)",
                          nv, j, in->fixed[j]);
  for (int j = 0; j < in->nfixed; j++) s->fixed[in->fixed[j]] = 1;
  const int nc = s->cl.n, quad = s->dim == 9, chunk = nc > 1024 ? 32 : 1;
  const double h = in->dt;
  if (tb_threads() > 1 && s->cl.start[nc] >= SM_PARALLEL_MIN) {
#pragma omp parallel
    {
#pragma omp for schedule(dynamic, chunk)
      for (int c = 0; c < nc; c++) {
        if (quad)
          goals_quadratic(s, c, 0);
        else
          goals_linear(s, c, 0);
      }
#pragma omp for schedule(static)
      for (int i = 0; i < nv; i++) {
        if (s->fixed[i]) continue;
        tb_vec3 g = tb_v3(0, 0, 0);
        for (int k = s->nstart[i]; k < s->nstart[i + 1]; k++) g = tb_add(g, s->gm[s->nmember[k]]);
        advance(s, i, g, in);
      }
    }
  } else {
    memset(s->goal, 0, sizeof(tb_vec3) * (size_t)nv);
    for (int c = 0; c < nc; c++) {
      if (quad)
        goals_quadratic(s, c, 1);
      else
        goals_linear(s, c, 1);
    }
    for (int i = 0; i < nv; i++)
      if (!s->fixed[i]) advance(s, i, s->goal[i], in);
  }
  for (int j = 0; j < in->nfixed; j++) { /* prescribed: ends exactly at fixed_x */
    int i = in->fixed[j];
    tb_vec3 xf = in->fixed_x[j];
    s->v[i] = tb_scale(tb_sub(xf, s->x[i]), 1.0 / h);
    s->x[i] = xf;
    s->fixed[i] = 0;
  }
  return 0;
}

static const tb_vec3 *positions(const void *self) { return ((const sm *)self)->x; }
static const tb_vec3 *velocities(const void *self) { return ((const sm *)self)->v; }
static double energy(const void *self) {
  (void)self;
  return NAN; /* shape matching is geometric: no potential energy is defined */
}

int tb_sm_cluster_stats(const tb_model *m, int *nclusters, double *mean_members) {
  if (!m || m->cls != &tb_model_sm || !m->self) return -1;
  const sm *s = m->self;
  if (nclusters) *nclusters = s->cl.n;
  if (mean_members) *mean_members = (double)s->cl.start[s->cl.n] / s->cl.n;
  return 0;
}

static const double *masses(const void *self) { return ((const sm *)self)->mass; }

static tb_model_groups groups(const void *self) {
  const sm *s = self;
  return (tb_model_groups){s->nv, s->cl.n, s->group};
}

static void correct(void *self, int n, const int *ids, const tb_vec3 *x, const tb_vec3 *v) {
  sm *s = self;
  for (int k = 0; k < n; k++) {
    if (x) s->x[ids[k]] = x[k];
    if (v) s->v[ids[k]] = v[k];
  }
}

#define S sm_settings
static const tb_setting settings[] = {
    TB_SETTINGS_MASS(S, 1.0), /* unit particle masses, as every suite runs sm */
    TB_SETTING_C(S, sm_mode, TB_SM_QUADRATIC, 2, "rigid|linear|quadratic",
                 "goal shapes (eqs. 3-37..3-45)"),
    TB_SETTING_R(S, alpha, 0.72, 0, 1, 0, "stiffness: pull towards the goals"),
    TB_SETTING_R(S, beta, 0.63, 0, 1, 0, "linear/quadratic blend with rigid"),
    TB_SETTING_I(S, clusters, 50, 1, 100000000,
                 "regions (cluster_mode=regions); 1: the whole body"),
    TB_SETTING_R(S, radius, 1.0, 0, HUGE_VAL, TB_OPEN_LO,
                 "region radius (nodes in no region join the nearest)"),
    TB_SETTING_C(S, cluster_mode, TB_CLUSTER_REGIONS, 1, "regions|tets",
                 "regions around sampled centres, or one per node with its tet neighbours"),
    TB_SETTING_R(S, sm_damping, 0, 0, 1, TB_OPEN_HI, "velocity damping per step"),
};
#undef S

const tb_model_class tb_model_sm = {
    .name = "sm",
    .summary =
        "meshless shape matching (Muller et al. 2005): rigid, linear or quadratic goals on "
        "overlapping clusters, eq. 3-41",
    .settings = settings,
    .nsettings = (int)(sizeof settings / sizeof settings[0]),
    .settings_size = sizeof(sm_settings),
    .create = create,
    .step = step,
    .positions = positions,
    .velocities = velocities,
    .energy = energy,
    .destroy = destroy,
    .masses = masses,
    .correct = correct,
    .groups = groups,
};
