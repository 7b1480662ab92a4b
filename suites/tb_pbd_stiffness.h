/* The effective stiffness of the position-based models (suites/suite_pbd_stiffness.c,
 * `figure pbd-stiffness`): the static sag of the `beam` scene's cantilever
 * (10 x 1 x 1, held at x = 0) under gravity alone, a model run from rest
 * until the sag of its tip face stops changing, beside the static sag of
 * the same material on the same mesh from the reference solver
 * (reference/tb_reference.h). PBD's sag depends on k, the iterations and
 * dt (its projection does not see E); XPBD's tends to the reference as the
 * iterations grow (Macklin et al. 2016). tests/test_pbd_stiffness.c checks
 * both claims through these functions. */
#ifndef TB_PBD_STIFFNESS_H
#define TB_PBD_STIFFNESS_H

#include "core/tb_error.h"
#include "core/tb_mesh.h"

/* One run: the beam under gravity with one model's settings. */
typedef struct tb_sag_def {
  const char *model; /* pbd-stvk, xpbd-stvk (or any model with E and nu) */
  int cells;         /* the beam's cells along x */
  double gravity;    /* along -z; the tip load is off */
  double drag;       /* the scene's ambient drag (per s), about critical for the first mode */
  double dt;
  int iterations;  /* <= 0: the model's default */
  double k;        /* pbd-stvk's k; NAN: the default */
  double E, nu;    /* the material, also the reference's */
  double rayleigh; /* constraint damping b (rayleigh_stiffness); 0: off. It damps strain rates
                      and leaves the rest state (PBD's exactly, XPBD's once converged) */
  double max_time; /* simulated s before giving up ("not settled") */
  double window;   /* settled: over this many simulated s ... */
  double tol;      /* ... the tip sag varied by at most tol x the sag */
} tb_sag_def;

/* The suite's settings: pbd-stvk, 10 cells, gravity 0.02 (the continuum's
 * static tip sag about 0.1, 1% of L), drag 1.5, dt 0.01, default iterations
 * and k, E 3000, nu 0.3 (the reference's and fem's), constraint damping
 * off, 60 s, window 1 s, tol 1e-4. */
void tb_sag_def_init(tb_sag_def *d);

typedef struct tb_sag_result {
  int stable;         /* 0: blew up (state says why) */
  int settled;        /* the sag stopped changing within max_time */
  double sag;         /* tip sag: minus the mean z displacement of the tip face's nodes,
                         averaged over the last two steps (a node may jitter step to step);
                         not settled: the mean over the last window */
  double spread;      /* (largest - smallest) / mean sag over the last window */
  double settle_time; /* simulated s until the settled window began (NAN: not settled) */
  long steps;
  double ms_step;      /* median CPU ms of a step */
  double ms_step_wall; /* median wall ms of a step */
  char state[192];
} tb_sag_result;

/* Runs d (mesh: the beam at d->cells, or NULL to build it). Returns 0 (the
 * result says whether stable and settled) or -1 on a setup error (err). */
int tb_sag_run(const tb_sag_def *d, const tb_mesh *mesh, tb_sag_result *r, tb_error *err);

/* The static tip sag of d's beam, material and gravity by the reference
 * solver: quadratic = 0, St. Venant-Kirchhoff on the linear tets themselves
 * (the discrete problem the models solve: its equilibrium is the steady
 * state of backward Euler on that mesh); quadratic = 1, compressible
 * Neo-Hookean on quadratic tets (the continuum, free of the linear tets'
 * locking). Returns the sag, or NAN with err. */
double tb_sag_reference(const tb_sag_def *d, int quadratic, tb_error *err);

#endif
