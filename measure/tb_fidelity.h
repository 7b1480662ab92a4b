/* Fidelity of the deformation models against the reference solution
 * (reference/tb_reference.h: static Neo-Hookean FEM on quadratic tets):
 * a scene's static problem posed to the reference once, on a mesh finer
 * than any model's; each model run on the scene until it settles and its
 * surface nodes compared with the reference displacement sampled at their
 * rest positions. Also the Pareto front of error against speed and the
 * points table `advise` reads (results/pareto/<scene>/points.csv). */
#ifndef TB_FIDELITY_H
#define TB_FIDELITY_H

#include "reference/tb_reference.h"
#include "scenes/tb_sim.h"

/* ---- metrics on arrays (no simulation) ---- */

/* Nodes of the boundary triangles, ascending, malloc'ed into *out; returns
 * the count (0 when the mesh has no triangles) or -1 (no memory). */
int tb_fid_surface_nodes(const tb_mesh *m, int **out);

/* Displacement error of nodes idx[0..n-1]: e_k = |(x - X)[idx[k]] - uref[k]|;
 * *rms = sqrt(mean e_k^2) / scale, *max = max e_k / scale. */
void tb_fid_disp_error(const tb_vec3 *X, const tb_vec3 *x, const int *idx, int n,
                       const tb_vec3 *uref, double scale, double *rms, double *max);

/* The Pareto front of points (cost, error): point k is on it when it is
 * valid and no valid point is at least as fast (speed >= speed_k) and at
 * least as accurate (error <= error_k) with one of the two strict. Writes
 * on[k] = 1/0; returns the number on the front. */
int tb_fid_pareto(const double *speed, const double *error, const char *valid, int n, char *on);

/* ---- the reference of a scene ---- */

typedef struct tb_fid_ref {
  char scene[32];
  tb_sim_def def; /* the scene settings it was solved with (nodes: the reference mesh's) */
  double t_eq;    /* the scene time whose loads were posed */
  tb_mesh mesh;   /* the reference's rest (linear) mesh */
  tb_ref_solution *sol;
  double umax;          /* largest displacement of a reference node */
  double volume_change; /* (V - V0) / V0 of the linear mesh's tets */
  int has_reaction;     /* the scene prescribes the positions of its driven set */
  tb_vec3 reaction;     /* then: the total reaction force on the driven set */
  double seconds;       /* wall time of the solve */
  double cpu_seconds;   /* CPU time of the solve (the process's when threads work) */
  int iterations, load_steps;
} tb_fid_ref;

/* Poses scene (beam, liver-stretch or liver-hang; others have no static problem here)
 * with settings def at time t_eq to the reference solver with the material
 * (E, nu, density) model fem reads from mset (NULL: its defaults): the
 * same loads, supports and prescribed positions the scene gives its models
 * (tb_sim_loads). */
int tb_fid_reference(const char *scene, const tb_sim_def *def, double t_eq, const tb_settings *mset,
                     tb_fid_ref *out, tb_error *err);
void tb_fid_ref_free(tb_fid_ref *r);

/* ---- a model run against the reference ---- */

typedef struct tb_fid_opts {
  double settle_speed; /* settled: every node moves slower than this (per simulated s) */
  double max_time;     /* simulated seconds of holding (and of recovery) before giving up */
  double window;       /* settle window, simulated s (0: max_time / 20); quasi-static: 3 steps */
  int recovery;        /* 1 (scenes that release): let go and measure what is left */
  int substeps;        /* the model's dt is def.dt / substeps (cost counted per def.dt) */
  tb_vec3 *keep_x;     /* not NULL: receives the nodes' positions at equilibrium (mesh nv) */
} tb_fid_opts;

/* A resolution of a scene: its mesh, surface nodes and the reference
 * displacement at their rest positions (shared by the models run on it). */
typedef struct tb_fid_mesh {
  tb_mesh mesh;
  int nsurf, *surf;
  tb_vec3 *uref; /* nsurf */
} tb_fid_mesh;
int tb_fid_mesh_make(const tb_fid_ref *ref, const tb_sim_def *def, tb_fid_mesh *out, tb_error *err);
void tb_fid_mesh_free(tb_fid_mesh *m);

typedef struct tb_fid_result {
  int stable;          /* 0: blew up or failed (state says why) */
  int settled;         /* 1: reached settle_speed within max_time */
  char state[192];     /* "settled", "not settled (...)", "unstable (reason)" */
  double ms_step;      /* median CPU ms of one sim step (at the model's dt) */
  double ms_step_wall; /* median wall ms of one sim step */
  long steps;          /* steps taken in all */
  double rms_err;      /* surface nodes at equilibrium, / ref umax */
  double max_err;      /* likewise, the largest */
  double volume_change;
  double reaction_err; /* |R - R_ref| / |R_ref| on the driven set; NAN when not prescribed */
  double settle_time;  /* simulated s from the full load to settled; NAN when not settled */
  double recovery_err; /* largest surface displacement left after release / umax; NAN if not run */
} tb_fid_result;

/* Runs model (with settings mset) on the scene of ref at resolution fm with scene
 * settings def (def->nodes is fm's resolution): loads as the scene gives
 * them, held until settled (liver-stretch: the pull is held past its
 * `release` until then), the errors measured; with o->recovery the driven
 * set is let go and the run continues until settled again. Returns 0 (the
 * result says stable or not) or -1 for a setup failure (err). */
int tb_fid_run(const tb_fid_ref *ref, const tb_fid_mesh *fm, const char *model,
               const tb_settings *mset, const tb_sim_def *def, const tb_fid_opts *o,
               tb_fid_result *out, tb_error *err);

/* ---- the settings the fidelity suites (pareto, calibration) use ---- */

typedef struct tb_fid_plan {
  int nres, res[4]; /* model resolutions: the scene's `nodes` key, coarse to fine */
  int ref_res;      /* the reference's, finer than any model's */
  tb_sim_def def;   /* scene settings: dt, load, drag, release (nodes: set per run) */
  double t_eq;      /* the scene time whose loads the reference gets */
  tb_fid_opts opts; /* settle_speed relative to the reference: times its umax per s */
  const char *load; /* the load in words, for notes */
  /* 1: gravity loads the scene; the models' masses come from the density
   * (lumped: on linear tets the reference's consistent body force) */
  int density_masses;
} tb_fid_plan;
/* Equal node masses of the body's mass at model's density in mset (sets
 * node_mass = density * volume / nodes): without gravity the static answer
 * does not depend on masses, and no sliver node's tiny mass limits the
 * explicit models' step. */
int tb_fid_equal_masses(const tb_mesh *m, const char *model, tb_settings *mset, tb_error *err);
/* The masses a plan gives model: equal masses (tb_fid_equal_masses), or for
 * a gravity-loaded scene (density_masses) node_mass = 0, so that every node
 * carries the weight of its share of the volume, as the reference's load. */
int tb_fid_masses(const tb_fid_plan *p, const tb_mesh *m, const char *model, tb_settings *mset,
                  tb_error *err);
/* level 0: smoke (tiny meshes), 1: quick, 2: full. Scenes: beam, liver-stretch, liver-hang. */
int tb_fid_plan_for(const char *scene, int level, uint64_t seed, tb_fid_plan *p, tb_error *err);

#endif
