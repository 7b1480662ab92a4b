/* The metaball model's state (models/metaball.c), shared with the files
 * that change it (the cut). Hot data are flat arrays per sphere and per
 * skin vertex; a step allocates nothing. */
#ifndef TB_METABALL_PRIV_H
#define TB_METABALL_PRIV_H

#include "tb_metaball.h"
#include "cutting/tb_fold.h"

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
  struct tb_metaball_cut *cut; /* the cut's state (models/metaball_cut.c), NULL when none */
  /* Flat data for the step (models/metaball.c), kept with the links, the
   * unit constraints and the binding: */
  double *em;       /* per member entry k (cmember order): its mass, 0 once removed */
  tb_vec3 *eq;      /* its rest offset c0_j - cm0_i */
  tb_vec3 *smq;     /* per unit constraint: sum_k em_k eq_k (0 but for rounding) */
  double *wf;       /* per sphere, set each step: 1 / mass, 0 when fixed or removed */
  tb_vec3 (*xo)[3]; /* per skin vertex and binding q: x0 - c0 of its sphere */
  /* Contacts across cracks (models/metaball_pieces.c): sphere pairs kept at
   * least their distance at the cut's end apart (the step projects them). */
  int ncontact, contact_cap;
  int *contact;  /* 2 ncontact spheres */
  double *cdist; /* ncontact least distances */
  /* ... and the crack's faces on the skin: twin vertices (one point of the
   * crack, a copy on each side) kept on their sides of each other. */
  int ntwin, twin_cap;
  int *twin;      /* 2 ntwin vertices: on the + side, on the - side */
  int *tsph;      /* the sphere whose rotation carries the twin's normal */
  tb_vec3 *tn;    /* the crack's normal (to the + side) in that sphere's rest frame */
  double *treach; /* beyond this tangential offset the two no longer face each other */
  tb_vec3 *tpush; /* per sphere: the push of a step's contact (scratch, m->n) */
};

/* The cut's state (models/metaball_cut.c, metaball_repack.c). */
typedef struct tb_metaball_cut {
  tb_metaball_cut_settings set;
  int cutting, has_fold;
  tb_fold fold;     /* the last folded plane given (kept after the cut for the skin) */
  tb_vec3 flo, fhi; /* its bounding box */
  double spacing;   /* the shared grid's spacing, or the smallest per-sphere one */
  double rfloor;    /* per_sphere: radii below it sampled as if this radius (coarse) */
  double density;
  double omega;      /* a bound of the point set's largest free frequency (rad/s) */
  int last_substeps; /* meshless steps in the last frame */
  tb_vec3 glo;       /* the shared grid's origin */
  int np, pcap;
  tb_vec3 *X, *x, *held; /* points: rest, current (at the last advance), held position */
  double *vol;
  int *gen, *driver;                 /* the sphere each came from; the sphere driving it */
  int nrem, rcap, *removed, *pstart; /* removed sphere k: points pstart[k] .. pstart[k+1] */
  double rsum;                       /* sum of the removed radii */
  struct tb_meshless *ml;
  int nd, *ids; /* driven points, and the per-frame buffers (dcap points) */
  int dcap;
  tb_vec3 *fx0, *fx1, *fx, *fpts, *fsph, *fel;
  double *ks; /* per sphere: the stiffness of its coupling to the points */
  /* per-piece boxes of the fold, the first piece the
   * cut test looks at, and scratch for the stability bound */
  tb_vec3 *plo, *phi;
  int piece_from;
  int nfrom;        /* the first new piece of the last fold given, and ... */
  tb_vec3 nlo, nhi; /* ... the box of the pieces from it on */
  unsigned char *isdriven;
  double *row;
  tb_vec3 *vbuf;
} tb_metaball_cutstate;

/* The cut test handed to the point set (ctx: the cut state). */
int tb_metaball_cut_crosses(void *ctx, tb_vec3 a, tb_vec3 b);
/* Frees the points and the per-frame buffers (keeps the fold). */
void tb_metaball_cut_free_points(tb_metaball_cutstate *c);

/* Appends k alive, free spheres (rest centres c0, current centres c,
 * rotations rot and velocities v, NULL: identity and zero; radii r), with
 * no links; their unit constraints hold only themselves until
 * tb_metaball_set_links. Returns 0, or -1 out of memory. */
int tb_metaball_add(tb_metaball *m, int k, const tb_vec3 *c0, const tb_vec3 *c, const tb_mat3 *rot,
                    const double *r, const tb_vec3 *v);
/* Replaces the links by nl pairs (rest lengths from the rest centres) and
 * rebuilds the unit constraints from them. Returns 0, or -1 out of memory. */
int tb_metaball_set_links(tb_metaball *m, int nl, const int *pairs);
/* Recomputes vertex v's rest offsets xo from x0 and its binding; call it
 * after changing x0[v] or bind[v] (the skin's m->xo must hold m->nv). */
void tb_metaball_bind_offsets(tb_metaball *m, int v);
/* The rotation of the polar decomposition of a, iterated from r: r turns
 * about sum_k r_k x a_k / |sum_k r_k . a_k| (columns; Müller, Bender,
 * Chentanez & Macklin 2016) at most `turns` times, until a turn is below
 * tol radians (models/metaball.c's head says why warm starts). */
tb_mat3 tb_metaball_turns(tb_mat3 a, tb_mat3 r, int turns, double tol);
/* Frees the cut's state (models/metaball_cut.c); tb_metaball_destroy calls it. */
void tb_metaball_cut_release(tb_metaball *m);

#endif
