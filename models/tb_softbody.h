/* A peer for the position-based models: Bullet's classic soft body
 * (btSoftBody, libBulletSoftBody-float64 3.24: double precision through
 * pkg-config bullet-float64) behind a C API, in a btSoftRigidDynamicsWorld
 * with gravity and a static ground. Built from a tet mesh: one node per
 * mesh node, one link (Bullet's distance constraint, its position solver)
 * per tet edge; node masses from the density and a quarter of each tet's
 * volume (total mass = density x volume). models/bullet_softbody_peer.cpp says
 * what Bullet does with them. */
#ifndef TB_SOFTBODY_H
#define TB_SOFTBODY_H

#include "core/tb_error.h"
#include "core/tb_mesh.h"

typedef struct tb_softbody_def {
  double density;   /* node masses: density x a quarter of each tet's volume */
  double stiffness; /* the links' linear stiffness, Material::m_kLST in (0, 1] */
  int iterations;   /* position solver iterations, Config::piterations (>= 1) */
  double friction;  /* Config::kDF in [0, 1] (the ground's own friction is 1) */
  double damping;   /* Config::kDP in [0, 1] */
  double hardness;  /* contact hardness against the static ground, Config::kKHR in (0, 1]:
                       the share of a contact's depth corrected per iteration */
  double margin;    /* collision margin: a node nearer the ground is a contact, pushed back to it */
  tb_vec3 gravity;  /* acceleration */
  int has_ground;   /* 1: a static ground through ground_p with normal ground_n */
  tb_vec3 ground_p, ground_n;
  const double *mass; /* nv node masses (> 0) instead of the density's, or NULL */
} tb_softbody_def;

/* Bullet's defaults for the rest: stiffness 1, 1 iteration, friction 0.2,
 * damping 0, hardness 0.1, margin 0.25; density 1, no gravity, no ground. */
tb_softbody_def tb_softbody_default_def(void);

typedef struct tb_softbody tb_softbody;

/* NULL (err set) on a mesh without tets, a bad setting or no memory. */
tb_softbody *tb_softbody_create(const tb_mesh *mesh, const tb_softbody_def *def, tb_error *err);
/* Adds the static ground through p with normal n (when the body has none
 * yet), the links' contact friction kDF set to friction in [0, 1]. */
int tb_softbody_set_ground(tb_softbody *b, tb_vec3 p, tb_vec3 n, double friction, tb_error *err);
int tb_softbody_has_ground(const tb_softbody *b);
/* One world step of dt (stepSimulation(dt, 0): exactly one step of dt). */
int tb_softbody_step(tb_softbody *b, double dt, tb_error *err);
/* One step of dt as tb_softbody_step, with gravity g (world and body),
 * external node forces force (nv, or NULL: btSoftBody::addForce) and
 * prescribed nodes fixed[0 .. nfixed) (ascending) ending the step at
 * fixed_x with velocity (fixed_x - x) / dt: zero mass (Bullet's fixed
 * nodes) while prescribed, that velocity before the step, the position set
 * after it. */
int tb_softbody_step_nodes(tb_softbody *b, double dt, tb_vec3 g, const tb_vec3 *force, int nfixed,
                           const int *fixed, const tb_vec3 *fixed_x, tb_error *err);
/* The nodes' velocities now (nv entries). */
void tb_softbody_velocities(const tb_softbody *b, tb_vec3 *v);
/* Overwrites positions and/or velocities (either may be NULL) of ids[0 .. n). */
void tb_softbody_correct(tb_softbody *b, int n, const int *ids, const tb_vec3 *x, const tb_vec3 *v);
/* The nodes' positions now, in the mesh's node order (nv entries). */
void tb_softbody_positions(const tb_softbody *b, tb_vec3 *x);
int tb_softbody_nodes(const tb_softbody *b);
int tb_softbody_links(const tb_softbody *b);
double tb_softbody_total_mass(const tb_softbody *b);
void tb_softbody_destroy(tb_softbody *b);

#endif
