/* The metaball model's state (models/metaball_model.c), shared with its
 * cutting (models/metaball_model_cut.c). */
#ifndef TB_METABALL_MODEL_PRIV_H
#define TB_METABALL_MODEL_PRIV_H

#include "metaball_priv.h"
#include "tb_model.h"
#include "cutting/tb_fold.h"

typedef struct mb_settings {
  double density, node_mass, stretch, unit, damping, sigma, overlap;
  int iterations, spheres, samples, seed;
  int cut_points;                         /* points per converted sphere */
  double cut_E;                           /* the point set's Young's modulus */
  char spheres_file[TB_SETTING_TEXT_MAX]; /* SOFA .sph spheres instead of the packing ("": pack) */
} mb_settings;

typedef struct mb_model {
  mb_settings set;
  tb_metaball *mb;
  int nv, ns;
  tb_vec3 *x, *v; /* the points (nodes) and their velocities */
  tb_vec3 *skin0; /* the skin at a step's start */
  double *mass;
  tb_vec3 *fs;           /* per-sphere forces of a step */
  tb_vec3 *cstart;       /* sphere centres at a step's start */
  tb_vec3 *hold, *hold0; /* a held sphere's prescribed points' centroid, now and at rest */
  tb_mat3 *apq;          /* their covariance, for the fit's rotation */
  int *nhold, *held;     /* how many prescribed points hold it; the held spheres */
  double *push, *keep;   /* ground: per-sphere push and friction's kept share */
  int *cids;             /* ground contact spheres */
  tb_vec3 *cp;           /* their pushed positions */
  double *cdepth;
  int dominant_ok;
  int *dominant;          /* per point: the sphere it holds when prescribed */
  unsigned char *presc;   /* per point: prescribed this step (0 between steps) */
  int ntri, *tri;         /* the current surface over the points */
  unsigned long version;  /* changes with every cut that changes the surface */
  int cutting, have_fold; /* a cut is running; its folded plane exists (2+ path points) */
  tb_fold fold;           /* the blade's folded plane so far */
  tb_metaball_skin_report last_skin; /* what the last cut's end did to the spheres and skin */
} mb_model;

/* Point masses as shares of the alive spheres' masses, and each point's
 * dominant sphere (models/metaball_model.c's head). */
int mb_share_masses(mb_model *s, tb_error *err);
/* Every per-point array for nv points and per-sphere array for ns
 * spheres, entries past s->nv and s->ns zeroed (the caller sets them
 * after); 0 or -1 out of memory. */
int mb_grow(mb_model *s, int nv, int ns);
/* The model's cut event (tb_model_class.cut). */
int mb_cut(void *self, const tb_cut_event *ev, tb_cut_stats *st, tb_error *err);

#endif
