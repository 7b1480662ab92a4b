/* Private to the position-based models (pbd.c builds them, pbd_solve.c
 * steps them): the state, and the per-tet strain energies with their first
 * Piola-Kirchhoff stresses, inlined into the projection. */
#ifndef TB_PBD_PRIV_H
#define TB_PBD_PRIV_H

#include <stdatomic.h>

#include "carve_priv.h"
#include "tb_model.h"

enum { PBD_STVK, PBD_NEOHOOKEAN };
enum { PBD_BDF2, PBD_PATENT, PBD_EULER }; /* the integrator setting */

/* The settings of pbd-stvk and xpbd-stvk (xpbd ignores k). */
typedef struct pbd_settings {
  double density, node_mass, E, nu, k, damping, rayleigh_stiffness;
  int iterations, energy, integrator;
} pbd_settings;

/* Threads that share a sweep at most (more wait at its barriers). */
#define PBD_MAX_THREADS 256

typedef struct pbd {
  int xpbd; /* 1: XPBD (compliance, accumulated lambda); 0: the patent's PBD */
  pbd_settings set;
  double mu, lambda; /* Lame parameters from E, nu */
  int nv, nt;
  /* the sweeps' schedule (models/tet_slabs.c): the nodes numbered slab by
   * slab (every per-node array below is in that order, internal node n is
   * mesh node old[n]), the tets by task, the tasks by phase */
  tb_tet_slabs sl;
  /* the threads' shares: in each phase p, thread k runs the tasks
   * share[p][k] .. share[p][k+1], a contiguous range of about equal cost
   * (pbd_solve.c, plan): cost[q], task q's tets with a free node, counted
   * by each step's first sweep for the next step's plan (its tet count
   * before the first). Which thread runs a task never changes the result
   * (a phase's tasks share no node). */
  int share[4][PBD_MAX_THREADS + 1];
  double *cost;
  /* per task: how often it has run in this step (the threads' sweeps wait
   * on their conflicts' counts instead of on each other at every phase) */
  atomic_int *done;
  /* hot, per node: current, previous and predicted positions, current and
   * previous velocity, mass, inverse mass (w) and the w the step uses (0 for
   * prescribed nodes) */
  tb_vec3 *x, *xm1, *p, *v, *vm1;
  double *mass, *invm, *w;
  tb_vec3 *xo, *vo; /* x and v in the mesh's node order, after every step */
  /* per node, the ground contact of the step: normal correction, and the
   * contact list (ids, positions, keep) friction works on */
  double *depth;
  int *cids;          /* contact k's node */
  tb_vec3 *cp;        /* its position */
  double *cdepth;     /* its summed normal correction */
  double *cvn, *keep; /* its predicted normal velocity; the tangential share friction kept */
  tb_vec3 *fric;      /* per node: friction's tangential correction so far in the step */
  /* hot, per tet in the schedule's order: nodes (internal), rest volume,
   * D_m^-1 (row-major), XPBD's lambda */
  int (*tet)[4];
  double *vol;
  double (*dminv)[9];
  double *lam;
  int *tmesh; /* 4 nt: the tets' mesh node ids, for the carving's masses and surface */
  /* cutting: the tets removed so far, the surface left (carve.c) */
  tb_carve carve;
  unsigned char *hit; /* per tet: touched by the blade at this MOVE */
  int *orig;          /* per tet: its index in the rest mesh */
  /* BDF2 needs the previous step (and its dt) */
  int have_prev;
  double last_dt;
} pbd;

/* The projection's inner function: inlined into it (GCC, Clang). */
#if defined(__GNUC__)
#define PBD_INLINE static inline __attribute__((always_inline))
#else
#define PBD_INLINE static inline
#endif

/* The kernels' small fixed loops unrolled completely: GCC's -O2 keeps loops of 9 or
 * 27 steps as loops, and the projection ran 1.7x slower (suite pbd: 0.21 against
 * 0.12 us per element-step at 12765 tets, the same positions bit for bit). */
#if defined(__GNUC__)
#define PBD_UNROLL _Pragma("GCC unroll 9")
#else
#define PBD_UNROLL
#endif

/* F = D_s D_m^-1 (row-major) of the tet with nodes n at positions x, D its
 * D_m^-1 (row-major); D_s's columns are x_j - x_3 (the patent's eq. 11). */
PBD_INLINE void pbd_deformation(const tb_vec3 *x, const int n[4], const double D[9], double F[9]) {
  double ds[9];
  PBD_UNROLL
  for (int j = 0; j < 3; j++) {
    tb_vec3 e = tb_sub(x[n[j]], x[n[3]]);
    ds[j] = e.x, ds[3 + j] = e.y, ds[6 + j] = e.z;
  }
  PBD_UNROLL
  for (int r = 0; r < 3; r++) {
    PBD_UNROLL
    for (int c = 0; c < 3; c++)
      F[3 * r + c] = ds[3 * r] * D[c] + ds[3 * r + 1] * D[3 + c] + ds[3 * r + 2] * D[6 + c];
  }
}

/* Energy density psi(F) and P = d psi / dF for F (row-major); returns 0 for
 * a Neo-Hookean tet with det F <= 0, where it is undefined. */
PBD_INLINE int pbd_energy(int kind, double mu, double lambda, const double F[9], double *psi,
                          double P[9]) {
  if (kind == PBD_STVK) {
    /* E = (F^T F - I) / 2, psi = mu E:E + lambda/2 tr(E)^2, P = F (2 mu E + lambda tr(E) I) */
    double E[9];
    PBD_UNROLL
    for (int r = 0; r < 3; r++) {
      PBD_UNROLL
      for (int c = r; c < 3; c++) {
        double s = F[r] * F[c] + F[3 + r] * F[3 + c] + F[6 + r] * F[6 + c];
        E[3 * r + c] = E[3 * c + r] = 0.5 * (s - (r == c));
      }
    }
    double tr = E[0] + E[4] + E[8], ee = 0;
    PBD_UNROLL
    for (int k = 0; k < 9; k++) ee += E[k] * E[k];
    *psi = mu * ee + 0.5 * lambda * tr * tr;
    double S[9];
    PBD_UNROLL
    for (int k = 0; k < 9; k++) S[k] = 2 * mu * E[k];
    S[0] += lambda * tr, S[4] += lambda * tr, S[8] += lambda * tr;
    PBD_UNROLL
    for (int r = 0; r < 3; r++) {
      PBD_UNROLL
      for (int c = 0; c < 3; c++)
        P[3 * r + c] = F[3 * r] * S[c] + F[3 * r + 1] * S[3 + c] + F[3 * r + 2] * S[6 + c];
    }
    return 1;
  }
  /* compressible Neo-Hookean (Bonet & Wood): psi = mu/2 (I1 - 3) - mu ln J
   * + lambda/2 (ln J)^2, P = mu (F - F^-T) + lambda ln J F^-T */
  double C[9] = {F[4] * F[8] - F[5] * F[7], F[5] * F[6] - F[3] * F[8], F[3] * F[7] - F[4] * F[6],
                 F[2] * F[7] - F[1] * F[8], F[0] * F[8] - F[2] * F[6], F[1] * F[6] - F[0] * F[7],
                 F[1] * F[5] - F[2] * F[4], F[2] * F[3] - F[0] * F[5], F[0] * F[4] - F[1] * F[3]};
  double J = F[0] * C[0] + F[1] * C[1] + F[2] * C[2]; /* C: cofactor matrix, F^-T = C / J */
  if (!(J > 0)) return 0;
  double lj = log(J), i1 = 0;
  PBD_UNROLL
  for (int k = 0; k < 9; k++) i1 += F[k] * F[k];
  *psi = 0.5 * mu * (i1 - 3) - mu * lj + 0.5 * lambda * lj * lj;
  double a = (lambda * lj - mu) / J;
  PBD_UNROLL
  for (int k = 0; k < 9; k++) P[k] = mu * F[k] + a * C[k];
  return 1;
}

/* The step (pbd_solve.c). */
int pbd_step(void *self, const tb_step *in, tb_error *err);

#endif
