/* Private to msm-vvs (msm_vvs.c: the model; vvs_refine.c: its dynamic
 * local refinement): the settings, the state, and what the two share. */
#ifndef TB_VVS_PRIV_H
#define TB_VVS_PRIV_H

#include "tb_lod.h"
#include "tb_model.h"

enum { VVS_QUASISTATIC, VVS_EULER };
/* follow[i]: >= 0 the surface point a tet mesh's interior node follows;
 * VVS_SIM a simulated point; VVS_OFF a point of a finer level that is not
 * on the surface now (local refinement) */
enum { VVS_SIM = -1, VVS_OFF = -2 };

typedef struct vvs_settings {
  double density, node_mass, ks, kd, ks_v, kd_v, alpha, refine_force, coarsen_share;
  int integrator, volume_springs, levels, refine_every;
} vvs_settings;

typedef struct vvs {
  vvs_settings set;
  int nv;                          /* points: the mesh's nodes, then the finer levels' */
  int nbase;                       /* the mesh's nodes */
  tb_vec3 *x, *v, *x0, *f;         /* positions, velocities, rest positions, forces */
  double *mass, *invm, *ksv, *kdv; /* per point: mass, 1/mass, k'_s, k'_d */
  double *d;                       /* per point: damping d_i */
  int *follow;                     /* per point: VVS_SIM, VVS_OFF or the point followed */
  int nsim, *sim;                  /* the simulated points, ascending */
  int ntri, *tri;                  /* the simulated surface */
  unsigned long version;           /* changes with the surface */
  int ns, *ij;                     /* springs: 2*ns point pairs, i < j */
  double *len0, *k;                /* rest lengths, stiffnesses */
  int cap_tri;                     /* capacity of tri, and of the springs (3 cap_tri) */
  /* local refinement (levels > 1): the levels, each point's depth (the
   * level its faces are split to) and its share of the surface's area
   * against a base point's */
  tb_lod *lod;
  unsigned char *depth;
  double *share, mass_base;
  double *stress; /* per point: sum of its springs' |k (l - R)| at the last check */
  double *kdiag;  /* per point: its springs' k summed with k'_s */
  double *qinv;   /* per point: the quasi-static step's 1 / mass, for the step qh */
  double *barea;  /* per base point: its rest area share (a third of its triangles') */
  tb_vec3 *u;     /* per point: the displacement field a point coming on is placed by */
  tb_vec3 *bload; /* per base point: the external traction, force / barea */
  double qh;
  int steps;
  int refinements; /* surface rebuilds so far */
} vvs;

/* The per point arrays for nv points, the triangles' and springs' for up
 * to cap_tri triangles. */
int vvs_alloc(vvs *s, int nv, int cap_tri, tb_error *err);

/* The springs of tri[0 .. 3 ntri) (one per distinct edge, rest length from
 * x0, stiffness ks) and the simulated list; follow[] must already mark
 * the simulated points VVS_SIM. closed: the triangles form a closed,
 * oriented 2-manifold, where every edge runs a -> b with a < b in exactly
 * one triangle, so no sorting is needed (local refinement's surfaces);
 * otherwise edges are sorted and merged. Allocates nothing (capacity
 * cap_tri). */
void vvs_build_springs(vvs *s, int ntri, const int *tri, int closed);

/* Local refinement (vvs_refine.c). Init: the levels over the mesh (a
 * closed surface), the arrays for every level's points. Step: after the
 * forces, the points whose force per area share passes refine_force deepen
 * their faces a level, those below coarsen_share of it go back one;
 * returns 1 when the surface changed (points, springs, masses rebuilt). */
int vvs_refine_init(vvs *s, const tb_mesh *mesh, tb_error *err);
int vvs_refine_step(vvs *s);
/* Masses, damping and virtual springs from the area shares of the surface
 * (local refinement keeps the total mass and the stiffness per area). */
void vvs_refine_params(vvs *s);
/* The quasi-static step's masses for the step h = alpha dt^2 (qinv, qh). */
void vvs_refine_steps(vvs *s, double h);
/* The external forces given on the base points (nbase) as loads on every
 * point of the current surface, into s->f (vvs_refine.c). */
void vvs_refine_loads(vvs *s, const tb_vec3 *force);

#endif
