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
  int *piece; /* per sphere: its piece of the surface at the last cut's end (-1, or NULL
               * before a cut: one body) */
  int ncontact, contact_cap;
  int *contact;     /* 2 ncontact spheres a, b */
  double *cdist;    /* their least separation along ... */
  tb_vec3 *cnormal; /* ... the crack's normal from a to b, in the rest frame (a's R turns it) */
  struct tb_metaball_zone *zone; /* the skin's contact across cracks (metaball_contact.c) */
  /* After a skin with given rest positions: the positions it replaced less
   * the skin, added to the skin and fading out linearly to none over
   * TB_METABALL_BLEND seconds (blend_left of them still to go) */
  tb_vec3 *blend;
  double blend_left;
};
#define TB_METABALL_BLEND 0.1
/* Skin vertices from which the per-vertex loops take threads: each vertex
 * costs tens of ns, and below this a parallel region cost more than it
 * saved (on 2 cores, 2650 vertices: 0.69x one thread). */
#define TB_METABALL_PARALLEL_MIN 50000

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
  long long *apart; /* sorted keys a n + b (a < b) of the sphere pairs across earlier cracks */
  int napart;
  double *row;
  tb_vec3 *vbuf;
} tb_metaball_cutstate;

/* 1 when spheres a and b lie in two pieces or across an earlier crack (a
 * contact pair): their points never link, nor does one take the other's
 * grid points (models/metaball_cut.c). */
int tb_metaball_apart(const tb_metaball *m, int a, int b);
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
/* The skin from the spheres (models/metaball.c). */
void tb_metaball_reskin(tb_metaball *m);
/* The skin's contact after cuts (models/metaball_contact.c). At a cut's
 * end (d: the new surface, its vertices' crack sides; f: the fold;
 * of_vertex: each vertex's piece of npiece, or NULL): the crack's twins, the
 * cut's zone (the vertices and triangles near the crack by their side) and
 * the surface by pieces. 0, or -1 out of memory. */
struct tb_metaball_skin_def;
int tb_metaball_zone_add(tb_metaball *m, const struct tb_metaball_skin_def *d, const tb_fold *f,
                         const int *of_vertex, int npiece, int *nvert, int *ntri);
/* In a step, after the skin: what meets across a crack or between pieces
 * pushes its spheres apart; the skin again. Allocates nothing. */
void tb_metaball_zone_contact(tb_metaball *m, double dt);
void tb_metaball_zone_free(tb_metaball *m);
/* Frees the cut's state (models/metaball_cut.c); tb_metaball_destroy calls it. */
void tb_metaball_cut_release(tb_metaball *m);

#endif
