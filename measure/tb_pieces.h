/* What a cut leaves, checked: the pieces of a triangle surface (connected
 * through shared vertices), whether each is a closed, oriented 2-manifold,
 * their volumes, the surface's self-intersections, and whether a sphere
 * model's sphere graph falls apart into the same pieces (measure/pieces.c). */
#ifndef TB_PIECES_H
#define TB_PIECES_H

#include "core/tb_error.h"
#include "core/tb_math.h"
#include "models/tb_model.h"

typedef struct tb_pieces {
  int n;             /* pieces: connected components of the triangles */
  int closed;        /* 1: every piece a closed, consistently oriented 2-manifold */
  int self_pairs;    /* crossing triangle pairs within one piece (collision/tb_bvh.h) */
  int overlap_pairs; /* crossing triangle pairs of two pieces: pieces inside each other */
  double deepest;    /* the deepest crossing of those pairs, in the surface's mean edges: of
                        the two triangles, how far the lesser side of one pokes through the
                        other's plane, the smaller of the two ways round; 0 when none */
  double *volume;    /* n: each piece's enclosed volume */
  int *of_vertex;    /* nv: a vertex's piece, -1 for one no triangle uses */
  int *of_tri;       /* ntri: a triangle's piece */
  int nv, ntri;
} tb_pieces;

/* Measures the surface (nv points x, ntri triangles tri); self_pairs and
 * overlap_pairs only when self is 1 (else -1). Returns 0, or -1 with err. */
int tb_pieces_measure(int nv, const tb_vec3 *x, int ntri, const int *tri, int self, tb_pieces *p,
                      tb_error *err);
/* Volumes of the same pieces at other positions x (p's triangles). */
void tb_pieces_volumes(const tb_pieces *p, const tb_vec3 *x, const int *tri, double *volume);
void tb_pieces_free(tb_pieces *p);

/* The sphere graph against the pieces: components of the alive spheres
 * through their links (*components); each component's piece is the one
 * most of the points bound to it lie on; the points bound to a component of
 * another piece (*crossing). Returns 1 when the graph's components are the
 * pieces: as many, one each, no point bound across. */
int tb_pieces_spheres(const tb_pieces *p, const tb_model_spheres *sp, int *components,
                      int *crossing);

#endif
