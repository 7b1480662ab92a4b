/* Metaballs: an organ filled with overlapping spheres driven by
 * position-based dynamics, and a surface skinned to them (the metaball
 * patent, SPEC §2.6, step 2: stretch, unit and energy constraints, fixed
 * spheres; Gaussian binding of each surface vertex to at most three
 * spheres). The cutting that turns spheres into a point set and back
 * works on this through tb_metaball_remove and the per-sphere forces. */
#ifndef TB_METABALL_H
#define TB_METABALL_H

#include "tb_error.h"
#include "tb_mesh.h"

typedef struct tb_metaball_settings {
  double density; /* mass per volume: a sphere's mass is density 4/3 pi r^3 */
  double stretch; /* stiffness in [0, 1] of the links between overlapping spheres */
  double unit;    /* stiffness in [0, 1] of the unit (shape-matching) constraints */
  double damping; /* per second: velocities decay as exp(-damping t) */
  double sigma;   /* the binding's Gaussian exp(-k^2 / (2 sigma^2)) of k = d / r */
  double overlap; /* spheres are linked when |c_i - c_j| < overlap (r_i + r_j) */
  int iterations; /* Gauss-Seidel sweeps per step */
} tb_metaball_settings;

/* The defaults: density 1, stretch 1, unit 0.5, damping 1, sigma 1,
 * overlap 1, 10 iterations. */
void tb_metaball_settings_default(tb_metaball_settings *s);

typedef struct tb_metaball tb_metaball;

/* Spheres (centres c, radii r > 0) at rest, and the closed surface skinned
 * to them (its vertices at rest; copied). */
tb_metaball *tb_metaball_create(int n, const tb_vec3 *c, const double *r, const tb_mesh *surface,
                                const tb_metaball_settings *set, tb_error *err);
void tb_metaball_destroy(tb_metaball *m);

/* Holds sphere i where it is (fixed != 0) or lets it go. */
void tb_metaball_fix(tb_metaball *m, int i, int fixed);
/* Removes sphere i logically (the patent's cut): its links and its place
 * in every unit constraint go, indices stay; it no longer moves. */
void tb_metaball_remove(tb_metaball *m, int i);
/* Moves every sphere (and its velocity) by a rigid motion x -> R x + t,
 * without stepping: for tests and placement. */
void tb_metaball_transform(tb_metaball *m, const double R[9], tb_vec3 t);

/* One step: gravity and per-sphere forces (NULL: none), prediction, the
 * sweeps, velocities, damping, then the skin. */
void tb_metaball_step(tb_metaball *m, double dt, tb_vec3 gravity, const tb_vec3 *force);

int tb_metaball_count(const tb_metaball *m);
const tb_vec3 *tb_metaball_centres(const tb_metaball *m);
const tb_vec3 *tb_metaball_velocities(const tb_metaball *m);
const double *tb_metaball_radii(const tb_metaball *m);
/* Links between overlapping spheres still alive: 2 n sphere pairs. */
int tb_metaball_links(const tb_metaball *m, const int **pairs);
/* The skinned surface vertices (the surface's nv), and how many vertices
 * found no sphere with d / r in [1, 2] and fell back to the nearest. */
const tb_vec3 *tb_metaball_skin(const tb_metaball *m);
int tb_metaball_fallbacks(const tb_metaball *m);
/* Vertex v's binding: up to 3 spheres and weights (summing to 1);
 * returns how many. */
int tb_metaball_binding(const tb_metaball *m, int v, int sphere[3], double weight[3]);

#endif
