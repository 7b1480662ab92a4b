/* The scalpel's folded plane and its intersection tests. Source: patent
 * CN (doc. 12722810) "A real-time digital organ cutting method based on the
 * metaball model and a hybrid driving method", step 3 (1): the surface the
 * blade sweeps is discretised into a folded plane (折平面), "a series of
 * planes joined at their edges", and collision is folded plane vs metaball
 * and folded plane vs surface triangle; step 3 (5) (表面分裂, fig. 5): a
 * triangle meets the folded plane through one piece, across a fold, or with
 * the cut starting or ending inside it.
 *
 * Definition. The blade's edge moves along the polyline p_0 .. p_n (n >= 1);
 * the blade has a fixed depth vector D (its extent, not parallel to any path
 * segment). Piece k (0 <= k < n) is the closed parallelogram
 *     P_k = { p_k + s (p_{k+1} - p_k) + t D : s, t in [0, 1] },
 * so pieces k and k+1 share the edge from p_{k+1} to p_{k+1} + D: the fold
 * (crease) k|k+1, which belongs to piece k in every report. The outer
 * boundary is p_0's edge (START, s = 0 of piece 0), p_n's edge (END, s = 1 of
 * the last piece), the path itself (PATH, t = 0) and the depth edge (DEPTH,
 * t = 1). Piece k's unit normal is n_k = e_k x D / |e_k x D|, e_k =
 * p_{k+1} - p_k; "side +1" is the side n_k points to.
 *
 * Exactness. The corners q_i = p_i + D are stored rounded once; the set the
 * segment test decides on is the pair of triangles (p_k, p_{k+1}, q_{k+1}),
 * (p_k, q_{k+1}, q_k) per piece, decided exactly with the orientation
 * predicates of tb_predicates.h. When the sums p_i + D are exact (e.g. small
 * dyadic coordinates) that is exactly P_k; otherwise it is within rounding of
 * it. Distances, sides and triangle cuts are computed in doubles. */
#ifndef TB_FOLD_H
#define TB_FOLD_H

#include "core/tb_error.h"
#include "core/tb_math.h"

typedef struct tb_fold_piece {
  tb_vec3 e;              /* p_{k+1} - p_k */
  tb_vec3 n;              /* unit normal, e x D normalised */
  double ee, ed, dd, det; /* Gram matrix of (e, D) and its determinant */
} tb_fold_piece;

typedef struct tb_fold {
  int count;            /* path points, n + 1 >= 2 */
  int npieces;          /* n */
  tb_vec3 depth;        /* D */
  tb_vec3 *p;           /* path points p_0 .. p_n (owned copy) */
  tb_vec3 *q;           /* p_i + D, rounded once */
  tb_fold_piece *piece; /* npieces entries */
} tb_fold;

/* Copies the path and precomputes the pieces. Fails (returns -1, message
 * "tb_fold_init: ...") on: count < 2, a non-finite coordinate, D = 0, two
 * consecutive equal points, or D parallel to a segment (the sine of the angle
 * between e_k and D below 1e-9). On failure *f is empty (safe to free). */
int tb_fold_init(tb_fold *f, const tb_vec3 *p, int count, tb_vec3 depth, tb_error *err);
void tb_fold_free(tb_fold *f);

/* The nearest point of the folded plane to x. */
typedef struct tb_fold_near {
  int piece;     /* lowest index among the nearest pieces */
  double s, t;   /* its coordinates in that piece, in [0, 1] */
  tb_vec3 point; /* p_k + s e_k + t D */
  double dist;   /* |x - point| */
} tb_fold_near;
void tb_fold_nearest(const tb_fold *f, tb_vec3 x, tb_fold_near *out);

/* 1 when the closed ball (c, r) meets the folded plane (the distance from c
 * to some piece is <= r; tangency counts), else 0. out (may be NULL) gets the
 * nearest point either way. */
int tb_fold_sphere(const tb_fold *f, tb_vec3 c, double r, tb_fold_near *out);

/* Segment test, exact (see above). Touching rule: the closed segment against
 * the closed pieces; 1 when they share at least one point, so an endpoint on
 * a piece, a segment touching a piece's boundary, and a segment lying in a
 * piece all count as crossing (a neighbour link that touches the cut is cut).
 * hit (may be NULL) gets the first shared point along a -> b: u in [0, 1]
 * with point = a + u (b - a), the piece (lowest index on ties) and (s, t) in
 * it (computed in doubles, clamped to [0, 1]). A degenerate segment (a == b)
 * is the point a. */
typedef struct tb_fold_hit {
  int piece;
  double u, s, t;
  tb_vec3 point;
} tb_fold_hit;
int tb_fold_segment(const tb_fold *f, tb_vec3 a, tb_vec3 b, tb_fold_hit *hit);

/* Which side of the folded plane x is on: the sign of (x - y) . m, y the
 * nearest point (tb_fold_nearest), m the nearest piece's normal, or the sum
 * of the two normals when y lies on a crease (the angle-weighted pseudo-
 * normal, so points beyond a convex fold get a consistent side). +1, -1, or 0
 * on the plane (or its extension beyond the outer boundary). */
int tb_fold_side(const tb_fold *f, tb_vec3 x);

/* ---- triangle against folded plane (the patent's surface splitting) ---- */

/* Where a cut point lies on the triangle. Edge i is the side opposite
 * tri[i] (bary[i] == 0). */
enum { TB_FOLD_TRI_INTERIOR = 0, TB_FOLD_TRI_EDGE = 1, TB_FOLD_TRI_VERTEX = 2 };
/* Where a cut point lies on the folded plane: a bit set, 0 inside a piece. */
enum {
  TB_FOLD_CREASE = 1, /* on the fold between piece and piece + 1 */
  TB_FOLD_START = 2,  /* on p_0's edge */
  TB_FOLD_END = 4,    /* on p_n's edge */
  TB_FOLD_PATH = 8,   /* on the path (t = 0) */
  TB_FOLD_DEPTH = 16  /* on the depth edge (t = 1) */
};

typedef struct tb_fold_tpoint {
  tb_vec3 x;
  double bary[3]; /* x = sum bary[i] tri[i]; values within 1e-12 of 0 are 0 */
  int tri_loc;    /* TB_FOLD_TRI_* */
  int tri_index;  /* the edge or vertex index, -1 inside */
  int piece;      /* piece it lies on (the lower one on a crease) */
  double s, t;    /* coordinates in that piece */
  int fold_loc;   /* TB_FOLD_* bits */
  int polyline;   /* index of the polyline it belongs to */
} tb_fold_tpoint;

#define TB_FOLD_CUT_MAX 64
typedef struct tb_fold_cut {
  int n;          /* points listed */
  int npoly;      /* polylines: consecutive points with the same polyline index */
  int coplanar;   /* pieces whose plane contains the triangle (not listed) */
  int truncated;  /* 1 when more than TB_FOLD_CUT_MAX points were found */
  int degenerate; /* 1 when the triangle has zero area: nothing computed */
  tb_fold_tpoint pt[TB_FOLD_CUT_MAX];
} tb_fold_cut;

/* The intersection of the closed triangle with the folded plane, as
 * polylines of points on the triangle, in piece order. Each piece not
 * coplanar with the triangle meets its plane in a segment (or a point),
 * clipped to the triangle; consecutive pieces join at a crease point. The
 * patent's cases come out as: through one piece, two points on the
 * triangle's boundary (tri_loc EDGE or VERTEX, fold_loc 0); across a fold,
 * boundary point, CREASE point inside, boundary point; the cut starting or
 * ending inside, a boundary point and an INTERIOR point with START, END, PATH
 * or DEPTH set; no intersection, n = 0. A single touching point is a
 * polyline of one point. Degenerate cases: a crease lying in the triangle's
 * plane is listed once (by the lower non-coplanar piece) as a CREASE
 * segment; a piece coplanar with the triangle is counted in coplanar, its
 * overlap (a polygon) is not listed; a zero-area triangle sets degenerate.
 * Returns cut->n. */
int tb_fold_triangle(const tb_fold *f, const tb_vec3 tri[3], tb_fold_cut *cut);

#endif
