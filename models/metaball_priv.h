/* The metaball model's state (models/metaball.c), shared with the files
 * that change it (the cut). Hot data are flat arrays per sphere and per
 * skin vertex; a step allocates nothing. */
#ifndef TB_METABALL_PRIV_H
#define TB_METABALL_PRIV_H

#include "tb_metaball.h"

struct tb_metaball {
  tb_metaball_settings set;
  int n;
  tb_vec3 *c0, *c, *p, *v; /* rest, current and predicted centres, velocities */
  double *r, *m, *w;       /* radii, masses, 1 / mass (0 when fixed or removed) */
  unsigned char *alive, *fixed;
  int nl, *link;         /* alive links: 2 nl sphere pairs */
  double *len0;          /* their rest lengths */
  int *cstart, *cmember; /* unit constraint i: members cmember[cstart[i] .. cstart[i+1]) */
  tb_vec3 *cm0;          /* its rest centre of mass over the alive members */
  tb_mat3 *rot;          /* its rotation at the last step (the sphere's) */
  int nv;                /* the skin */
  tb_vec3 *x0, *x;
  int (*bind)[3];
  double (*bw)[3];
  int nfallback;
};

#endif
