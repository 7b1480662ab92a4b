/* One step of the position-based models (the 2022 patent's method, SPEC
 * §2.5; XPBD after Macklin, Müller & Chentanez 2016).
 *
 *  0. Damping (Müller et al. 2007, "Position based dynamics", §3.5): each
 *     velocity's deviation from the body's rigid motion (v_cm + w x r_i, w
 *     from the angular momentum and inertia) is reduced by the share
 *     1 - exp(-damping dt), so rigid motion (a fall, a slide) is not slowed.
 *     Sums in node order: the same for any thread count.
 *     Constraint damping (stiffness-proportional, like fem's Rayleigh b =
 *     rayleigh_stiffness; gamma = b / dt): XPBD uses Macklin et al. 2016,
 *     eq. 26, with grad C . (p - x_n) the constraint's change over the step:
 *     dlambda = (-C - a lambda - gamma grad C.(p - x_n)) / ((1 + gamma) sum
 *     w |grad C|^2 + a); its fixed point is the undamped one. PBD has no
 *     compliance (a -> 0 makes eq. 26's gamma = a b / dt vanish), and eq. 26
 *     with a = 0 divides every correction by 1 + gamma, which changes PBD's
 *     stiffness and so where it comes to rest. PBD instead damps velocities
 *     after the step (4.): each tet's strain rate dC/dt = sum_j g_j . v_j
 *     loses the share gamma / (1 + gamma) (what eq. 26 removes from a stiff
 *     constraint's rate), v_j -= w_j g_j share dC/dt / sum w |g|^2, colour
 *     by colour. A body at rest has v = 0: the damping cannot move it.
 *  1. Prediction, by the integrator setting, with a = gravity + w f:
 *     euler (PBD's and XPBD's usual; patent eqs. 2-3): v <- v + dt a,
 *       p <- x + dt v;
 *     bdf2 (default of pbd-stvk): the second-order backward difference for
 *       both, v~ = (4 v_n - v_{n-1}) / 3 + 2/3 dt a, p = (4 x_n - x_{n-1}) / 3
 *       + 2/3 dt v~, so that the velocity of step 4 gives back v~ when no
 *       constraint acts (exact for a free fall);
 *     patent: eqs. 2-3 followed by the BDF2 velocity of step 4, as the patent
 *       states them. That pair is inconsistent: unconstrained, v_{n+1} =
 *       3/2 v_n - 1/2 v_{n-1} + dt g, which accelerates at 2g for any dt
 *       (tests/test_pbd.c measures it); it is kept to show that.
 *     The first step, and a step after a change of dt, are euler.
 *     Prescribed nodes are put at their positions and get w = 0 for the step.
 *  2. Projection, `iterations` Gauss-Seidel sweeps. Each tet's constraint
 *     is projected along its gradient, g_j = dU/dx_j with U = V psi(F) the
 *     tet's strain energy (F = D_s D_m^-1, P(F) from pbd_priv.h; g_j = V P
 *     D_m^-T column j for three nodes, minus their sum for the fourth):
 *       PBD  (patent): C = U, dp_j = -k s w_j g_j, s = C / sum_j w_j |g_j|^2;
 *       XPBD: C = sqrt(2U) with compliance 1 (so C^2 / 2 = U, the element's
 *             energy), dlambda = (-C - a lambda) / (sum_j w_j |g_j|^2 / C^2 + a),
 *             a = 1 / dt^2, lambda += dlambda, dp_j = w_j (g_j / C) dlambda.
 *     Tets are swept in the phases of the slab schedule (models/tet_slabs.c:
 *     slab interiors, even interfaces, odd interfaces, wide tets; a phase's
 *     tasks share no node, a task's tets go in a fixed order), forward and
 *     backward in turn; a task waits only for the tasks sharing a node with
 *     it (sweep), and the result does not depend on the thread count. After
 *     the tets of each sweep the ground constraint (p - q).n >= 0 (patent eq. 4) is
 *     projected for every free node, so the sweep ends with nothing below
 *     the ground, and friction acts on the nodes the ground touched
 *     (ground_sweep).
 *  3. Velocity: bdf2 and patent v = (3 x_{n+1} - 4 x_n + x_{n-1}) / (2 dt)
 *     (patent §[0171]); euler (and every first step) (x_{n+1} - x_n) / dt. A
 *     ground contact's normal velocity is the restitution times its
 *     approaching speed (friction is already in the positions; a node that
 *     sticks gets no tangential velocity). Prescribed nodes get the velocity that moved them,
 *     (x_fixed - x_n) / dt.
 *  4. PBD's constraint damping (see 0.) on the new positions and velocities.
 * The state is kept in the schedule's node order; the step reads the
 * forces and prescribed nodes through it and ends by copying x and v into
 * the mesh's order. Nothing is allocated here. */
#include <math.h>
#include <sched.h>
#include <string.h>

#include "pbd_priv.h"
#include "core/tb_threads.h"

/* An inverted or flat tet (det F <= 0): the energy and stress of Irving,
 * Teran & Fedkiw 2004 ("Invertible finite elements"), as Bender et al.
 * 2014 use them for position-based FEM: F = U S V^T with rotations U, V
 * and the smallest singular value negative, each singular value clamped to
 * at least 0.577, psi and P evaluated on the clamped diagonal and P rotated
 * back, P = U P(S^) V^T. The clamped state has energy, so the projection
 * pushes the tet back through flat towards its rest shape instead of
 * leaving it at StVK's zero-energy mirror image. */
static void inverted_stress(const pbd *s, const double F[9], double *psi, double P[9]) {
  tb_mat3 f, a, v;
  for (int r = 0; r < 3; r++)
    for (int c = 0; c < 3; c++) f.m[r][c] = F[3 * r + c];
  a = tb_m3_mul(tb_m3_transpose(f), f);
  double w[3], sg[3];
  tb_m3_sym_eigen(a, w, &v); /* ascending: column 0 is the smallest */
  if (tb_m3_det(v) < 0)
    for (int r = 0; r < 3; r++) v.m[r][0] = -v.m[r][0];
  tb_vec3 u[3], vc[3];
  for (int i = 0; i < 3; i++) {
    sg[i] = sqrt(fmax(w[i], 0));
    vc[i] = tb_v3(v.m[0][i], v.m[1][i], v.m[2][i]);
  }
  for (int i = 2; i >= 1; i--) { /* the two largest directions */
    tb_vec3 fv = tb_m3_mulv(f, vc[i]);
    u[i] = sg[i] > 1e-12 ? tb_scale(fv, 1 / sg[i]) : tb_v3(0, 0, 0);
  }
  if (!(sg[1] > 1e-12)) { /* F of rank <= 1: any frame around u2 */
    tb_vec3 e = fabs(u[2].x) < 0.9 ? tb_v3(1, 0, 0) : tb_v3(0, 1, 0);
    if (!(sg[2] > 1e-12)) u[2] = tb_v3(0, 0, 1);
    u[1] = tb_normalize(tb_cross(u[2], e));
  }
  u[0] = tb_cross(u[1], u[2]);                /* det U = +1 */
  sg[0] = tb_dot(u[0], tb_m3_mulv(f, vc[0])); /* negative when inverted */
  double D[9] = {0}, Pd[9];
  for (int i = 0; i < 3; i++) D[4 * i] = fmax(sg[i], 0.577);
  pbd_energy(s->set.energy, s->mu, s->lambda, D, psi, Pd); /* det D > 0: always defined */
  for (int r = 0; r < 3; r++) /* P = U diag(Pd) V^T (Pd is diagonal for a diagonal D) */
    for (int c = 0; c < 3; c++) {
      double sum = 0;
      for (int i = 0; i < 3; i++) sum += tb_comp(u[i], r) * Pd[4 * i] * tb_comp(vc[i], c);
      P[3 * r + c] = sum;
    }
}

/* The gradients g_j = dU/dx_j of tet t's strain energy U = V psi at the
 * positions p (g_j = V P D_m^-T column j, g_3 = -g_0 - g_1 - g_2); returns
 * U, or 0 when the energy is rounding noise (below a strain of about 1e-7
 * Neo-Hookean's terms cancel to O(eps), and noise over its gradient is no
 * direction). */
static inline double gradients(const pbd *s, const tb_vec3 *p, int t, tb_vec3 g[4]) {
  const int *n = s->tet[t];
  const double *D = s->dminv[t];
  double F[9], P[9], psi = 0;
  pbd_deformation(p, n, D, F);
  double det = F[0] * (F[4] * F[8] - F[5] * F[7]) - F[1] * (F[3] * F[8] - F[5] * F[6]) +
               F[2] * (F[3] * F[7] - F[4] * F[6]);
  if (det > 0)
    pbd_energy(s->set.energy, s->mu, s->lambda, F, &psi, P);
  else
    inverted_stress(s, F, &psi, P);
  if (!(psi > 1e-14 * (s->mu + s->lambda))) return 0;
  double V = s->vol[t];
  PBD_UNROLL
  for (int j = 0; j < 3; j++)
    g[j] = tb_v3(V * (P[0] * D[3 * j] + P[1] * D[3 * j + 1] + P[2] * D[3 * j + 2]),
                 V * (P[3] * D[3 * j] + P[4] * D[3 * j + 1] + P[5] * D[3 * j + 2]),
                 V * (P[6] * D[3 * j] + P[7] * D[3 * j + 1] + P[8] * D[3 * j + 2]));
  g[3] = tb_scale(tb_add(tb_add(g[0], g[1]), g[2]), -1);
  return V * psi;
}

/* Projects tet t (the schedule's order) on p; alpha: XPBD's compliance /
 * dt^2; gamma: XPBD's damping factor rayleigh_stiffness / dt. Returns 0
 * when all its nodes are prescribed (nothing to do), else 1. */
static inline int project(pbd *s, int t, double alpha, double gamma) {
  const int *n = s->tet[t];
  tb_vec3 *p = s->p;
  const double *w = s->w;
  double wj[4] = {w[n[0]], w[n[1]], w[n[2]], w[n[3]]};
  if (wj[0] + wj[1] + wj[2] + wj[3] == 0) return 0;
  tb_vec3 g[4];
  double U = gradients(s, p, t, g);
  if (U == 0) return 1;
  double sum = 0;
  PBD_UNROLL
  for (int j = 0; j < 4; j++) sum += wj[j] * tb_dot(g[j], g[j]);
  if (!(sum > 0)) return 1;
  double f;
  if (s->xpbd) {
    double gdx = 0; /* grad U . (p - x_n), the constraint's change over the step */
    if (gamma > 0) {
      PBD_UNROLL
      for (int j = 0; j < 4; j++) gdx += tb_dot(g[j], tb_sub(p[n[j]], s->x[n[j]]));
    }
    double C = sqrt(2 * U);
    double dl = (-C - alpha * s->lam[t] - gamma * gdx / C) / ((1 + gamma) * sum / (C * C) + alpha);
    s->lam[t] += dl;
    f = dl / C;
  } else {
    f = -s->set.k * U / sum;
  }
  PBD_UNROLL
  for (int j = 0; j < 4; j++) p[n[j]] = tb_madd(p[n[j]], f * wj[j], g[j]);
  return 1;
}

/* Step 5 (PBD): tet t's strain rate at the new positions p reduced by the
 * share c in the velocities v. */
static inline void damp_rate(pbd *s, int t, double c) {
  const int *n = s->tet[t];
  const double *w = s->w;
  double wj[4] = {w[n[0]], w[n[1]], w[n[2]], w[n[3]]};
  if (wj[0] + wj[1] + wj[2] + wj[3] == 0) return;
  tb_vec3 g[4], *v = s->v;
  if (gradients(s, s->p, t, g) == 0) return;
  double sum = 0, rate = 0;
  PBD_UNROLL
  for (int j = 0; j < 4; j++) sum += wj[j] * tb_dot(g[j], g[j]), rate += tb_dot(g[j], v[n[j]]);
  if (!(sum > 0)) return;
  double f = -c * rate / sum;
  PBD_UNROLL
  for (int j = 0; j < 4; j++) v[n[j]] = tb_madd(v[n[j]], f * wj[j], g[j]);
}

/* The threads' shares for this step (see struct pbd), one thread, at the
 * step's start: each phase's tasks cut into nth contiguous ranges of about
 * equal cost, a task going to the range its cost's midpoint falls in.
 * Contiguous, so that a thread keeps its slabs and the interfaces between
 * them in its cache from phase to phase and step to step (dealt out by
 * cost alone, a task that changed cores ran a third slower there). A
 * task's cost is its tets with a free node in the last step (a tet of
 * prescribed nodes costs nearly nothing): a count, not a time, which would
 * move with the caches. */
static void plan(pbd *s, int nth) {
  const int *phase = s->sl.phase;
  for (int ph = 0; ph < 4; ph++) {
    int a = phase[ph], b = phase[ph + 1], q = a;
    double total = 0, acc = 0;
    for (int r = a; r < b; r++) total += s->cost[r];
    s->share[ph][0] = a;
    for (int k = 1; k < nth; k++) {
      while (q < b && acc + 0.5 * s->cost[q] < total * k / nth) acc += s->cost[q++];
      s->share[ph][k] = q;
    }
    s->share[ph][nth] = b;
  }
}

/* Waits until task c has run `need` times in this step. */
static void wait_for(atomic_int *c, int need) {
  for (int spins = 0; atomic_load_explicit(c, memory_order_acquire) < need; spins++)
    if (spins > 1000) sched_yield(); /* the thread it waits for may need this core */
}

/* One sweep of project (damp_share < 0) or damp_rate (damp_share: its
 * share) over the tets, phase by phase, thread k of nth running its share
 * of each phase (none for k >= nth); every thread of the team calls it.
 * back: in reverse (symmetric Gauss-Seidel: forward and backward sweeps in
 * turn, so that no direction of the mesh is favoured). count: each task's
 * tets with a free node into cost, the next plan's.
 * No barrier ends a phase: occ[p] counts the runs of phase p so far in the
 * step (the same on every thread), and a task waits only for its
 * conflicts (the tasks of other phases sharing a node with it) to have run
 * as often as their phases have before this one: every node still sees its
 * tets in the same order, while a thread whose share of one phase ends
 * early goes on with the next. */
static void sweep(pbd *s, int k, int nth, int back, int count, int *occ, double alpha, double gamma,
                  double damp_share) {
  const int *task = s->sl.task, *phase = s->sl.phase, *cs = s->sl.conf_start, *conf = s->sl.conf;
  for (int f = 0; f < 4; f++) {
    int ph = back ? 3 - f : f;
    if (phase[ph] == phase[ph + 1]) continue;
    int lo = k < nth ? s->share[ph][k] : 0, hi = k < nth ? s->share[ph][k + 1] : 0;
    for (int r = lo; r < hi; r++) {
      int q = back ? lo + hi - 1 - r : r, free = 0;
      for (int c = cs[q]; c < cs[q + 1]; c++)
        wait_for(&s->done[conf[c]], occ[tb_tet_slabs_phase(&s->sl, conf[c])]);
      if (damp_share >= 0)
        for (int t = task[q]; t < task[q + 1]; t++) damp_rate(s, t, damp_share);
      else if (back)
        for (int t = task[q + 1] - 1; t >= task[q]; t--) free += project(s, t, alpha, gamma);
      else
        for (int t = task[q]; t < task[q + 1]; t++) free += project(s, t, alpha, gamma);
      if (count) s->cost[q] = free;
      atomic_store_explicit(&s->done[q], occ[ph] + 1, memory_order_release);
    }
    occ[ph]++;
  }
}

/* Step 0: velocities relative to the rigid motion damped by the share c. */
static void damp(pbd *s, double c) {
  double M = 0;
  tb_vec3 xc = tb_v3(0, 0, 0), vc = tb_v3(0, 0, 0), L = tb_v3(0, 0, 0);
  for (int i = 0; i < s->nv; i++) {
    M += s->mass[i];
    xc = tb_madd(xc, s->mass[i], s->x[i]), vc = tb_madd(vc, s->mass[i], s->v[i]);
  }
  xc = tb_scale(xc, 1 / M), vc = tb_scale(vc, 1 / M);
  tb_mat3 I = {{{0}}};
  for (int i = 0; i < s->nv; i++) {
    tb_vec3 r = tb_sub(s->x[i], xc);
    double m = s->mass[i], rr = tb_dot(r, r);
    L = tb_madd(L, m, tb_cross(r, s->v[i]));
    double rv[3] = {r.x, r.y, r.z};
    for (int a = 0; a < 3; a++)
      for (int b = 0; b < 3; b++) I.m[a][b] += m * ((a == b) * rr - rv[a] * rv[b]);
  }
  tb_mat3 Iinv;
  tb_vec3 w = tb_m3_inverse(I, &Iinv) ? tb_m3_mulv(Iinv, L) : tb_v3(0, 0, 0);
  for (int i = 0; i < s->nv; i++) {
    tb_vec3 rigid = tb_add(vc, tb_cross(w, tb_sub(s->x[i], xc)));
    s->v[i] = tb_madd(s->v[i], c, tb_sub(rigid, s->v[i]));
  }
}

/* After each sweep's tets (one thread; node order): the ground constraint
 * (p - q).n >= 0 (patent eq. 4) for every free node, its normal
 * corrections over the step summed in depth, then Coulomb friction
 * (models/ground.c) on the nodes the ground has touched in the step,
 * measured from the step's start x. Friction is solved with the tets, not
 * after them, so the final positions do not leave the tets strained by a
 * correction they never saw (applied once after the sweeps, it fed energy
 * into a body resting on the ground). fric[i] holds the tangential
 * correction friction has made so far in the step: each sweep asks friction
 * about p - fric (the motion without it), so its kinetic share is taken
 * once per step, not once per sweep. Returns the number of contacts; their
 * ids, summed depths, predicted normal velocities and kept tangential
 * shares are in cids, cdepth, cvn and keep. */
static int ground_sweep(pbd *s, const tb_ground *gr) {
  tb_vec3 *p = s->p;
  int nc = 0;
  for (int i = 0; i < s->nv; i++) {
    double d = tb_dot(tb_sub(p[i], gr->p), gr->n);
    if (d < 0 && s->w[i] > 0) p[i] = tb_madd(p[i], -d, gr->n), s->depth[i] -= d;
    if (s->depth[i] > 0) {
      s->cids[nc] = i, s->cp[nc] = tb_sub(p[i], s->fric[i]), s->cdepth[nc] = s->depth[i];
      s->cvn[nc++] = tb_dot(s->v[i], gr->n); /* the predicted normal velocity */
    }
  }
  tb_ground_friction(gr, nc, s->cids, s->cdepth, s->x, s->mass, s->cp, s->keep);
  for (int k = 0; k < nc; k++) {
    int i = s->cids[k];
    tb_vec3 free = tb_sub(p[i], s->fric[i]);
    s->fric[i] = tb_sub(s->cp[k], free), p[i] = s->cp[k];
  }
  return nc;
}

/* Step 3's contacts: restitution and friction's share of the velocity. */
static void contact_velocities(pbd *s, const tb_ground *gr, int nc) {
  for (int k = 0; k < nc; k++) {
    int i = s->cids[k];
    tb_vec3 n = gr->n, *v = s->v;
    double vn = tb_dot(v[i], n);
    tb_vec3 vt = s->keep[k] > 0 ? tb_madd(v[i], -vn, n) : tb_v3(0, 0, 0); /* stuck: at rest */
    vn = s->cvn[k] < 0 ? -gr->restitution * s->cvn[k] : fmax(vn, 0);
    v[i] = tb_madd(vt, vn, n);
  }
}

/* 5. A contact changed its node's normal velocity by an impulse: the
 * normal part of the history the next BDF2 step reads is made that of a
 * smooth motion through the new state (x_n = x - dt v, v_n = v along n);
 * else the backward difference turns the stop into a rebound (v = (3
 * x_{n+1} - 4 x_n + x_{n-1}) / (2 dt) = V / 2 up for a node that fell at
 * V and stopped). The tangential history is kept: a sliding node's is smooth. */
static void contact_history(pbd *s, const tb_ground *gr, int nc, double h) {
  for (int k = 0; k < nc; k++) {
    int i = s->cids[k];
    tb_vec3 n = gr->n;
    double xn = tb_dot(s->x[i], n) - h * tb_dot(s->v[i], n);
    s->xm1[i] = tb_madd(s->xm1[i], xn - tb_dot(s->xm1[i], n), n);
    s->vm1[i] = tb_madd(s->vm1[i], tb_dot(s->v[i], n) - tb_dot(s->vm1[i], n), n);
  }
}

int pbd_step(void *self, const tb_step *in, tb_error *err) {
  pbd *s = self;
  double h = in->dt;
  if (!(h > 0) || !isfinite(h)) return tb_error_set(err, "pbd", 0, "dt must be > 0 (got %g)", h);
  const tb_ground *gr = in->ground;
  const int nv = s->nv, iters = s->set.iterations;
  if (s->set.damping > 0) damp(s, 1 - exp(-s->set.damping * h));
  const int *old = s->sl.old, *nw = s->sl.nw, par = s->sl.nslabs > 1;
  memcpy(s->w, s->invm, sizeof(double) * (size_t)nv);
  for (int k = 0; k < in->nfixed; k++) s->w[nw[in->fixed[k]]] = 0;
  const double alpha = 1.0 / (h * h), gamma = s->set.rayleigh_stiffness / h;
  const int same = s->have_prev && s->last_dt == h; /* a second-order step can use the history */
  const int second = same && s->set.integrator == PBD_BDF2;
  const int bdf2 = same && s->set.integrator != PBD_EULER;
  const int damp_rates = !s->xpbd && gamma > 0;
  tb_vec3 *x = s->x, *p = s->p, *v = s->v;
  int nc = 0;  /* ground contacts of the last sweep */
  int nth = 1; /* the team's size, up to PBD_MAX_THREADS sharing the sweeps */
#pragma omp parallel if (par)
  {
    const int k = tb_thread_id();
#pragma omp single
    {
      nth = tb_threads_team() < PBD_MAX_THREADS ? tb_threads_team() : PBD_MAX_THREADS;
      plan(s, nth);
      for (int q = 0; q < s->sl.ntasks; q++)
        atomic_store_explicit(&s->done[q], 0, memory_order_relaxed);
    }
    /* 1. prediction */
#pragma omp for schedule(static)
    for (int i = 0; i < nv; i++) {
      s->depth[i] = 0, s->fric[i] = tb_v3(0, 0, 0);
      tb_vec3 vn = v[i];
      if (s->w[i] > 0) {
        tb_vec3 a = in->gravity;
        if (in->force) a = tb_madd(a, s->invm[i], in->force[old[i]]);
        if (second) {
          v[i] = tb_madd(tb_scale(tb_sub(tb_scale(vn, 4), s->vm1[i]), 1.0 / 3), 2.0 / 3 * h, a);
          p[i] =
              tb_madd(tb_scale(tb_sub(tb_scale(x[i], 4), s->xm1[i]), 1.0 / 3), 2.0 / 3 * h, v[i]);
        } else {
          v[i] = tb_madd(vn, h, a);
          p[i] = tb_madd(x[i], h, v[i]);
        }
      }
      s->vm1[i] = vn;
    }
    if (s->xpbd) {
#pragma omp for schedule(static)
      for (int t = 0; t < s->nt; t++) s->lam[t] = 0;
    }
#pragma omp single
    for (int f = 0; f < in->nfixed; f++) p[nw[in->fixed[f]]] = in->fixed_x[f];
    /* 2. projection */
    int occ[4] = {0}; /* the phases' runs in this step (see sweep) */
    for (int it = 0; it < iters; it++) {
      sweep(s, k, nth, it & 1, it == 0, occ, alpha, gamma, -1);
      if (gr) { /* every node: after all of the sweep's tasks */
#pragma omp barrier
#pragma omp single
        nc = ground_sweep(s, gr);
      }
    }
#pragma omp barrier
    /* 3. velocity */
#pragma omp for schedule(static)
    for (int i = 0; i < nv; i++) {
      if (s->w[i] == 0 || !bdf2)
        v[i] = tb_scale(tb_sub(p[i], x[i]), 1 / h);
      else
        v[i] = tb_scale(tb_add(tb_sub(tb_scale(p[i], 3), tb_scale(x[i], 4)), s->xm1[i]), 0.5 / h);
    }
#pragma omp single
    contact_velocities(s, gr, nc);
    /* 4. PBD's constraint damping */
    if (damp_rates) sweep(s, k, nth, 0, 0, occ, alpha, gamma, gamma / (1 + gamma));
#pragma omp for schedule(static)
    for (int i = 0; i < nv; i++) s->xm1[i] = x[i], x[i] = p[i];
#pragma omp single
    contact_history(s, gr, nc, h);
    /* the mesh's order */
#pragma omp for schedule(static)
    for (int m = 0; m < nv; m++) s->xo[m] = x[nw[m]], s->vo[m] = v[nw[m]];
  }
  s->have_prev = 1, s->last_dt = h;
  return 0;
}
