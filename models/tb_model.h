/* Deformation models behind one interface. A model is one file defining a
 * tb_model_class (a small table of functions) and one entry in the table of
 * models/model.c; scenes and suites never switch on a model's name.
 *
 * Every model works on the nodes of a tet mesh (shape matching treats them
 * as particles and may ignore the tets), with lumped node masses from the
 * density and the tet volumes. A step advances the state by dt under
 * gravity, external node forces and prescribed (Dirichlet) node positions:
 * a prescribed node ends the step exactly at its position, with the
 * velocity that moved it there. */
#ifndef TB_MODEL_H
#define TB_MODEL_H

#include "tb_error.h"
#include "tb_mesh.h"

/* Shape-matching variants (Müller et al. 2005; thesis §3.4.4). */
enum { TB_SM_RIGID = 0, TB_SM_LINEAR = 1, TB_SM_QUADRATIC = 2 };
/* Shape-matching clusters: overlapping spheres of a radius around centres
 * chosen by farthest-point sampling (thesis: "region radius 1"), or one
 * cluster per node made of the node and its tet neighbours. */
enum { TB_CLUSTER_REGIONS = 0, TB_CLUSTER_TETS = 1 };

/* Settings of every model; tb_model_default_def() gives the thesis's values
 * (§3.5). A model reads only the fields it needs (its class lists them). */
typedef struct tb_model_def {
  double density;   /* mass per volume; node mass = density * (sum of its tets' volumes) / 4 */
  double node_mass; /* > 0: every node gets this mass instead (thesis MSM: unit masses) */
  /* material (fem, fem-corot; msm when calibrated) */
  double E, nu; /* Young's modulus, Poisson ratio: 3000, 0.3 */
  /* msm: Kelvin springs on the tet edges (eq. 3-2) */
  double ks, kd;  /* 180, 5 */
  int calibrated; /* 1: spring stiffness from E and nu (Van Gelder 1998), kd unchanged */
  /* fem, fem-corot: implicit (backward) Euler with Rayleigh damping C = a M + b K */
  double rayleigh_mass, rayleigh_stiffness; /* a = 0, b = 0.02 */
  int consistent_mass;                      /* 1: consistent mass matrix instead of lumped */
  int quasistatic; /* 1: each step solves the static equilibrium (velocities 0) */
  /* sm: shape matching, eq. 3-41 */
  int sm_mode;       /* TB_SM_*: quadratic */
  double alpha;      /* stiffness in [0, 1]: 0.72 */
  double beta;       /* linear/quadratic blend in [0, 1]: 0.63 */
  int clusters;      /* number of regions (TB_CLUSTER_REGIONS): 50; 1 = the whole body */
  double radius;     /* region radius: 1 (nodes outside every region join the nearest) */
  int cluster_mode;  /* TB_CLUSTER_* */
  double sm_damping; /* velocity damping per step in [0, 1): 0 */
} tb_model_def;

tb_model_def tb_model_default_def(void);
/* Sets one field from "key=value" text (the keys are the field names above;
 * sm_mode takes rigid|linear|quadratic, cluster_mode regions|tets). Unknown
 * keys and bad values are errors naming the key. */
int tb_model_def_set(tb_model_def *def, const char *key_eq_value, tb_error *err);
/* Range checks shared by all models (E > 0, -1 < nu < 0.5, 0 <= alpha <= 1, ...). */
int tb_model_def_check(const tb_model_def *def, tb_error *err);

/* What one step receives. */
typedef struct tb_step {
  double dt;
  tb_vec3 gravity;      /* acceleration applied to every node */
  const tb_vec3 *force; /* nv external node forces, or NULL */
  int nfixed;
  const int *fixed;       /* prescribed nodes, strictly ascending */
  const tb_vec3 *fixed_x; /* their positions at the end of the step */
} tb_step;

typedef struct tb_model_class {
  const char *name;
  const char *summary;
  const char *keys; /* the tb_model_def fields it reads, space separated */
  /* Builds the model from a tet mesh (copied; mesh may be freed after). */
  void *(*create)(const tb_mesh *mesh, const tb_model_def *def, tb_error *err);
  /* Advances one step; a failure (e.g. a matrix that is not positive
   * definite) returns non-zero with err filled in. */
  int (*step)(void *self, const tb_step *in, tb_error *err);
  const tb_vec3 *(*positions)(const void *self);
  const tb_vec3 *(*velocities)(const void *self);
  /* Elastic potential + kinetic energy, or NAN where a model has no energy. */
  double (*energy)(const void *self);
  void (*destroy)(void *self);
} tb_model_class;

/* The table of models (models/model.c). */
extern const tb_model_class *const tb_model_classes[];
extern const int tb_model_count;
const tb_model_class *tb_model_find(const char *name);

/* A model instance: its class, the data, and the rest mesh. */
typedef struct tb_model {
  const tb_model_class *cls;
  void *self;
  int nv;
} tb_model;

/* Creates model `name` (see tb_model_find) after tb_model_def_check. */
int tb_model_create(tb_model *m, const char *name, const tb_mesh *mesh, const tb_model_def *def,
                    tb_error *err);
int tb_model_step(tb_model *m, const tb_step *in, tb_error *err);
const tb_vec3 *tb_model_positions(const tb_model *m);
const tb_vec3 *tb_model_velocities(const tb_model *m);
double tb_model_energy(const tb_model *m);
void tb_model_destroy(tb_model *m);

/* ---- helpers the models share (models/model_util.c) ---- */
/* Lumped node masses (density or node_mass as in tb_model_def) into mass[nv];
 * tets with non-positive volume are an error naming the tet. */
int tb_lumped_masses(const tb_mesh *mesh, const tb_model_def *def, double *mass, tb_error *err);
/* Rotation R closest to A (polar decomposition A = R S, det R = +1, also for
 * singular or inverted A: the smallest singular direction is flipped). */
tb_mat3 tb_m3_polar(tb_mat3 a);
/* Eigen-decomposition of a symmetric matrix: a = V diag(w) V^T, w ascending,
 * V's columns the eigenvectors (Jacobi rotations). */
void tb_m3_sym_eigen(tb_mat3 a, double w[3], tb_mat3 *v);
/* Inverse; returns 0 when |det| <= tiny * (scale)^3. */
int tb_m3_inverse(tb_mat3 a, tb_mat3 *inv);

/* ---- blow-up detection (every suite and the CLI check each run) ---- */
typedef struct tb_health {
  int ok;
  char reason[96]; /* "NaN or inf", "inverted elements (n)", "velocity beyond bound" ... */
} tb_health;
/* Checks positions for NaN/inf, velocities against vmax (<= 0: no bound)
 * and, when inversion is non-zero, tets for inversion (signed volume <= 0
 * in x while positive at rest). */
tb_health tb_model_health(const tb_mesh *rest, const tb_vec3 *x, const tb_vec3 *v, double vmax,
                          int inversion);

#endif
