/* Half-edge surfaces (Bao 2006, §3.4 and its figure 5): each triangle edge is two opposite
 * half-edges; h.v (start vertex), h.r (pair), h.n / h.p (next / previous in the face) give
 * constant-time access to the points, edges and triangles around any element. Our layout is
 * flat arrays: next, prev and face are arithmetic on the half-edge index, only the start vertex,
 * the pair and one outgoing half-edge per vertex are stored. */
#ifndef TB_HALFEDGE_H
#define TB_HALFEDGE_H

#include "tb_error.h"

/* A closed, oriented, 2-manifold triangle surface as half-edges. Face f owns half-edges
 * 3f, 3f+1, 3f+2: half-edge 3f+k starts at tri[3f+k] and ends at tri[3f+(k+1)%3], so
 * next, prev and face are arithmetic. */
typedef struct tb_halfedge {
  int nv, nf;
  int *vert; /* 3 nf: the vertex half-edge h starts at (the paper's h.v) */
  int *pair; /* 3 nf: the opposite half-edge (h.r); always >= 0 on a closed surface */
  int *out;  /* nv: one half-edge starting at each vertex */
} tb_halfedge;
static inline int tb_he_face(int h) { return h / 3; }
static inline int tb_he_next(int h) { return h - h % 3 + (h + 1) % 3; }
static inline int tb_he_prev(int h) { return h - h % 3 + (h + 2) % 3; }
/* Builds from nf triangles over nv vertices. Errors (returns non-zero, err filled,
 * message starting with `name`): a boundary edge (open surface), an edge used by more than two
 * triangles or twice in the same direction (non-manifold / misoriented), a vertex whose fan
 * is not one cycle (non-manifold vertex), a degenerate triangle, an unused vertex, an index
 * out of range; the message says which edge/vertex/triangle. Pairs are found by sorting the
 * edge keys (O(n log n)); out[v] is the smallest half-edge starting at v. On failure *he is
 * left empty. */
int tb_halfedge_build(tb_halfedge *he, int nv, int nf, const int *tri, const char *name,
                      tb_error *err);
void tb_halfedge_free(tb_halfedge *he);
/* Number of edges at v. */
int tb_halfedge_valence(const tb_halfedge *he, int v);
/* The 1-ring of v in counter-clockwise order (seen from outside), starting at the end of
 * out[v]; at most max written, returns the valence. */
int tb_halfedge_ring(const tb_halfedge *he, int v, int *ring, int max);

/* The half-edge after h counter-clockwise around its start vertex (seen from outside): the
 * pair of h's previous half-edge. */
static inline int tb_he_rotate(const tb_halfedge *he, int h) { return he->pair[tb_he_prev(h)]; }

#endif
