/* Private to the surface cutter (cutting/cut_surface.c, cut_topology.c,
 * cut_crack.c): the cut's state and the helpers its steps share. */
#ifndef TB_CUT_PRIV_H
#define TB_CUT_PRIV_H

#include <stddef.h>

#include "tb_cut_surface.h"

#define NAME "tb_cut_surface"
#define MAX_ATTEMPTS 4
#define CREASE_MAX 64 /* at most CREASE_MAX - 1 points on a crease inside the organ */

enum { LAB_S = 0, LAB_CP = 1, LAB_CM = 2 }; /* surface, + crack, - crack */
enum { OK = 0, RETRY = 1, NOMEM = -1 };     /* an attempt's outcome */
enum { SIDE_L, SIDE_R, SIDE_B, SIDE_T };    /* s = 0, s = 1, t = 0, t = 1 */

/* Grows *a to room for need elements of size bytes (doubling); 0 or -1. */
int cut_grow(void **a, int *cap, int need, size_t size);
#define GROW(arr, n, cap) cut_grow((void **)&(arr), &(cap), (n), sizeof *(arr))

/* Outgoing directed edges per vertex (CSR): for vertex a, out[start[a] .. start[a+1]) are
 * the triangles t with a corner k at a, stored as 3 t + k; the edge runs a -> tri[3t+(k+1)%3]. */
typedef struct vstar {
  int *start, *out;
} vstar;
int cut_vstar_build(vstar *vs, int nv, int ntri, const int *tri);
void cut_vstar_free(vstar *vs);
/* The corner 3 t + k whose edge runs a -> b, the first in triangle order; -1 when none. */
int cut_find_edge(const vstar *vs, const int *tri, int a, int b);
/* Union-find over p (p[i] = i at the start): the root of i; joins a and b. */
int cut_uf_find(int *p, int i);
void cut_uf_join(int *p, int a, int b);
/* The ray from p along +z, +x or +y (r = 0, 1, 2: projected on (x, y), (z, x), (y, z))
 * against triangle ABC, with exact signs: 1 it crosses the triangle's inside, 0 it
 * misses, -1 it grazes an edge or a corner, -2 p lies on the triangle. */
int cut_ray(tb_vec3 A, tb_vec3 B, tb_vec3 C, tb_vec3 p, int r);
/* 1 inside the closed surface, 0 outside, -1 undecided (exact ray parity). */
int cut_inside_organ(const tb_vec3 *x, int ntri, const int *tri, tb_vec3 p);

/* ---- the cut's state ---- */

typedef struct vrec {
  tb_vec3 x;
  int cut;   /* on the cut (an old vertex snapped to, or a new cut vertex) */
  int piece; /* for a cut vertex: its piece (the lower one on a crease), s, t, TB_FOLD_* bits */
  double s, t;
  int loc;
  int active;       /* on a cut segment */
  int origin, side; /* as in tb_cut_result */
} vrec;

typedef struct rawpt { /* one point of one triangle's cut */
  int tri, poly, id;
  int edge;    /* undirected edge id for an edge point, else -1 */
  int where;   /* -1 interior, 0..2 on edge i (opposite corner i), 3 + k at corner k */
  double u, v; /* its place in the triangle's barycentric plane */
  tb_fold_tpoint p;
} rawpt;

typedef struct seg {
  int a, b, piece, tri;
} seg;

typedef struct cutter {
  int nv, ntri;
  const tb_vec3 *x;
  const int *tri;
  int *pair; /* 3 ntri: the opposite half-edge */
  double h, snapd, spacing;
  const tb_vec3 *extra;
  int nextra;
  const tb_fold *f;
  /* per attempt */
  vrec *v;
  int nvr, capv;
  rawpt *rp;
  int nrp, caprp;
  seg *sg;
  int nsg, capsg;
  int *otri, *ofrom, *olab; /* assembled triangles */
  int nout, capout, capfrom, caplab;
  int *split;     /* ntri: old triangle split */
  int *corner_id; /* 2 count: the vertex of p_i and q_i, or -1 */
  int *crease_id; /* CREASE_MAX count: the vertex of point j on the crease at p_i, or -1 */
  int nsplit, ncrack;
  const char *why; /* what made the last attempt inconsistent */
} cutter;

/* An attempt found the cut inconsistent (why: for the error message). */
#define RETRY_BECAUSE(c, reason) ((c)->why = (reason), RETRY)

/* A new vertex at x (its record zeroed); its index, or -1. */
int cut_new_vertex(cutter *c, tb_vec3 x);
/* Appends the output triangle (a, b, d) from old triangle `from` with label lab. */
int cut_emit(cutter *c, int a, int b, int d, int from, int lab);
/* The crack of piece k (step 3), its triangles appended to *crack. */
int cut_crack_piece(cutter *c, int k, int **crack, int *ncrack, int *capcrack);

#endif
