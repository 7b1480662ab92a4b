/* A peer for the FEM models: Bullet's deformable world (3.24, double
 * precision through pkg-config bullet-float64): btDeformableMultiBodyDynamicsWorld
 * with btDeformableBodySolver, i.e. backward Euler linearised once (one
 * Newton iteration), its conjugate-gradient solve and Dirichlet nodes as
 * projections, with one of Bullet's hyperelastic forces on the tets of a
 * tet mesh, behind a C API. models/bullet_fem_peer.cpp says what Bullet
 * does with them. */
#ifndef TB_DEFORMABLE_H
#define TB_DEFORMABLE_H

#include "core/tb_error.h"
#include "core/tb_mesh.h"

/* Bullet's element forces. */
typedef enum {
  TB_DEFORMABLE_NEOHOOKEAN = 0, /* btDeformableNeoHookeanForce */
  TB_DEFORMABLE_LINEAR = 1,     /* btDeformableLinearElasticityForce */
  TB_DEFORMABLE_COROTATED = 2   /* btDeformableCorotatedForce (no force differential) */
} tb_deformable_force;

typedef struct tb_deformable_def {
  int force;           /* tb_deformable_force */
  double E, nu;        /* Young's modulus > 0, Poisson ratio in (-1, 0.5) */
  double damping;      /* neohookean: its damping (damping stresses damping * mu, lambda);
                          linear: damping_beta (the same, stiffness proportional);
                          corotated: Bullet's force has none, must be 0 */
  double damping_mass; /* linear: damping_alpha (force -alpha m v); others: must be 0 */
  int implicit;        /* 1: implicit (setImplicit(true)); 0: Bullet's explicit scheme */
} tb_deformable_def;

/* Lamé parameters: mu = E / (2 (1 + nu)), lambda = E nu / ((1 + nu)(1 - 2 nu)). */
void tb_deformable_lame(double E, double nu, double *mu, double *lambda);

typedef struct tb_deformable tb_deformable;

/* mass: nv lumped node masses (> 0; copied). NULL (err set) on a mesh
 * without tets, a tet of non-positive volume, a bad setting or no memory. */
tb_deformable *tb_deformable_create(const tb_mesh *mesh, const double *mass,
                                    const tb_deformable_def *def, tb_error *err);
/* One world step of exactly dt under gravity g, external node forces force
 * (nv, or NULL) and prescribed nodes fixed[0 .. nfixed) (ascending) that end
 * the step at fixed_x (which may alias tb_deformable_positions' array). */
int tb_deformable_step(tb_deformable *b, double dt, tb_vec3 g, const tb_vec3 *force, int nfixed,
                       const int *fixed, const tb_vec3 *fixed_x, tb_error *err);
/* The nodes' positions and velocities now (nv each, mesh order), kept by the adapter. */
const tb_vec3 *tb_deformable_positions(const tb_deformable *b);
const tb_vec3 *tb_deformable_velocities(const tb_deformable *b);
/* Overwrites positions and/or velocities (either may be NULL) of ids[0 .. n). */
void tb_deformable_correct(tb_deformable *b, int n, const int *ids, const tb_vec3 *x,
                           const tb_vec3 *v);
/* Bullet's elastic energy of the force at the current positions, or NAN
 * where the force has none (corotated). */
double tb_deformable_elastic_energy(tb_deformable *b);
void tb_deformable_destroy(tb_deformable *b);

#endif
