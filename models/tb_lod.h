/* Levels of detail and the active surface of Bao et al. 2006 (SPEC §2.4,
 * §3.1-3.4): a closed base surface subdivided offline by the modified
 * butterfly into levels 0..nlevels-1, and online a surface made of faces
 * of different levels, refined where forces are large and coarsened where
 * they fall.
 *
 * The forest of quadtrees (the paper's §3.4) is linear: level l's face f
 * has parent f / 4 at level l - 1 and children 4f..4f+3 at level l + 1
 * (tb_butterfly's numbering), one tree per base triangle. The vertices are
 * nested: level l's are the first level_nv[l] of level l + 1's, at the
 * same rest positions, so one array of the finest level's vertices holds
 * every level's, and an index keeps its meaning when the resolution changes.
 *
 * Every face is off (a coarser ancestor is a leaf), a leaf (on the
 * surface) or split (its four children are on). Two rules keep the surface
 * closed without T-vertices:
 *  - balance: a leaf's edge neighbours of its own level are leaves or split
 *    faces whose children are leaves (levels across an edge differ by at
 *    most one);
 *  - closure: a leaf with split neighbours across two or three edges is
 *    split too (1-to-4); a leaf with one is drawn as two triangles joined at
 *    that edge's midpoint, the paper's 1-to-2 transition band. */
#ifndef TB_LOD_H
#define TB_LOD_H

#include "core/tb_error.h"
#include "core/tb_mesh.h"

enum { TB_LOD_OFF, TB_LOD_LEAF, TB_LOD_SPLIT };

typedef struct tb_lod {
  int nlevels;
  int nv;               /* vertices of the finest level (every level's) */
  tb_vec3 *rest;        /* nv rest positions */
  int *level_nv;        /* level l's vertices are 0..level_nv[l]-1 */
  int *level_nf;        /* level l's faces: base faces * 4^l */
  int *first;           /* level l's faces are first[l]..first[l]+level_nf[l]-1 in state */
  int **tri;            /* tri[l]: 3 level_nf[l] vertex indices */
  int **pair;           /* pair[l]: the opposite half-edge of each half-edge 3f+k */
  int **out;            /* out[l]: one half-edge of level l leaving each of its vertices */
  int **mid;            /* mid[l] (l < nlevels-1): level l+1's vertex on half-edge h's edge */
  int *ends;            /* 2 nv: the level edge a vertex was born on (-1 for level 0's) */
  unsigned char *state; /* per face of every level: TB_LOD_* */
  /* The active surface (tb_lod_surface): ntri triangles over the nv
   * vertices, each with its leaf (first[l] + f); active[v] is 1 for the
   * vertices they use. */
  int ntri;
  int *out_tri, *out_leaf;
  unsigned char *active;
} tb_lod;

/* Levels 0..nlevels-1 (1 <= nlevels <= 6) from a closed 2-manifold
 * surface (ntet == 0); level 0 is base itself, every face a leaf. */
int tb_lod_create(tb_lod *lod, const tb_mesh *base, int nlevels, tb_error *err);
void tb_lod_free(tb_lod *lod);

/* Level of face id (an index into state) and its index in that level. */
int tb_lod_level(const tb_lod *lod, int id, int *f);

/* Splits leaf f of level l (1-to-4), with whatever balance and closure
 * need around it; returns the number of faces split (0 when f is not a
 * leaf or is on the finest level). */
int tb_lod_refine(tb_lod *lod, int l, int f);
/* Makes split face f of level l a leaf again when its children are
 * leaves and the rules allow it; returns 1 when done, 0 when not (a face
 * inside a split region cannot go alone: it would hang on three edges). */
int tb_lod_coarsen(tb_lod *lod, int l, int f);
/* Back to the base surface (every level-0 face a leaf). A region is
 * coarsened by a reset and refining again what is still wanted. */
void tb_lod_reset(tb_lod *lod);

/* The paper's §3.3 for every node at once: from the base, the faces of
 * level l around each vertex v with depth[v] > l are split, level by level
 * (depth[v] in 0..nlevels-1 for the active vertices, 0 for the others),
 * then the surface is rebuilt. */
void tb_lod_apply(tb_lod *lod, const unsigned char *depth);

/* Rebuilds the active surface (out_tri, out_leaf, ntri, active). */
void tb_lod_surface(tb_lod *lod);

#endif
