/* The stability map of msm-vvs (Bao 2006 §4; suites/suite_stability_vvs.c,
 * part 3 of `figure stability`): the `sphere-press` scene (the paper's
 * sphere of 252 points, unit node masses, k'_s 1.5, k'_d 0.5, dt 0.01) run
 * over spring stiffness ks x damping kd with the paper's quasi-static
 * update (at the scene's alpha) or symplectic Euler, each run judged by the
 * simulation driver's detector; beside it the linear prediction the model's
 * file documents (models/msm_vvs.c). tests/test_stability.c checks points of
 * the map and the boundary through these functions. */
#ifndef TB_STAB_VVS_H
#define TB_STAB_VVS_H

#include <stdint.h>

#include "core/tb_error.h"
#include "core/tb_mesh.h"

enum { TB_VVS_QUASISTATIC, TB_VVS_EULER }; /* msm-vvs's integrator setting */

/* One run of the map. */
typedef struct tb_vvs_run {
  int integrator;
  double ks, kd;            /* surface springs, node damping */
  double dt;                /* 0.01, the paper's */
  double duration, release; /* simulated s; the press acts until release */
} tb_vvs_run;

/* Quasi-static, the paper's ks 3 and kd 0.5, dt 0.01, 3 s with the press
 * let go at 1.5 s (the quick map's run). */
void tb_vvs_run_init(tb_vvs_run *r);

/* Its outcome: code 0 stable, else the detector's (the stability maps'
 * codes: 1 NaN or inf, 2 energy growth, 3 inverted, 4 velocity, 5 failed
 * step), the simulated time reached and the detector's words. */
typedef struct tb_vvs_cell {
  int code;
  double t;
  char reason[200];
} tb_vvs_cell;

/* Runs r on the scene's sphere (mesh NULL: built) or a copy of mesh.
 * Returns 0 (c says how it went), -1 when the scene cannot be built. */
int tb_vvs_run_cell(const tb_vvs_run *r, const tb_mesh *mesh, tb_vvs_cell *c, tb_error *err);

/* What the linear prediction needs: lambda, the largest eigenvalue of the
 * surface springs' rest stiffness per unit ks over the node mass (free
 * points, power iteration), and the scene's alpha, m, k'_s, k'_d. */
typedef struct tb_vvs_linear {
  double lambda, alpha, mass, ks_v, kd_v;
} tb_vvs_linear;
int tb_vvs_linear_init(tb_vvs_linear *p, const tb_mesh *mesh, uint64_t seed, tb_error *err);

/* Stable, linearised, iff a + 2 b < L with K = ks lambda + k'_s and
 * c = kd + k'_d: quasi-static a = alpha dt^2 K / m, b = alpha c dt / m,
 * L = 2 (msm_vvs.c's bound); symplectic Euler a = dt^2 K / m, b = c dt / m,
 * L = 4. The largest stable ks at kd and kd at ks (<= 0: none). */
double tb_vvs_ks_limit(const tb_vvs_linear *p, int integrator, double dt, double kd);
double tb_vvs_kd_limit(const tb_vvs_linear *p, int integrator, double dt, double ks);

/* The measured boundary along a line of r (r's ks and kd are the start):
 * along_kd 0 varies ks, 1 varies kd. From the start, doubles until a run is
 * unstable (or past cap), then bisects bisect times (geometric for ks,
 * arithmetic for kd) into [*lo, *hi]: *lo the largest stable value found
 * (0: none), *hi the smallest unstable one (INFINITY: none up to cap).
 * *runs counts the runs. -1 on a setup error. */
int tb_vvs_edge(const tb_vvs_run *r, const tb_mesh *mesh, int along_kd, double cap, int bisect,
                double *lo, double *hi, int *runs, tb_error *err);

#endif
