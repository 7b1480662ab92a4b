/* Cutting a closed triangle surface with the scalpel's folded plane: the
 * metaball patent's step 3 (5), surface splitting (表面分裂, fig. 5) and crack
 * generation (裂隙生成, fig. 6). Pure geometry: the
 * caller re-skins the vertices listed in reskin.
 *
 * What comes out. The input is a closed, oriented (outward), 2-manifold
 * triangle surface and a tb_fold. Triangles the folded plane crosses are
 * split along the cut polylines (tb_fold_triangle) by a 2D constrained
 * Delaunay triangulation of the triangle (CGAL) with the polylines as
 * constraints. The part of the folded plane inside the organ becomes two
 * crack surfaces, one facing each side, triangulated per piece in its (s, t)
 * coordinates (CGAL CDT with the cut polylines, the creases and the fold's
 * boundary edges as constraints, plus Steiner points: a grid at about the
 * mean edge length and the caller's extra points, projected), regions
 * outside the organ removed. Along the cut every vertex gets a copy for each
 * side; where the cut ends inside the surface (its tips) and along the fold
 * edges inside the organ the two sides share vertices (the slit closes
 * there). So a cut through the whole organ gives two closed 2-manifolds, a
 * cut that stops inside gives one (a slit); the result is always checked to
 * be a closed, consistently oriented 2-manifold, or an error comes back.
 *
 * Layout of the result. Vertices: the old nv first, same indices, same
 * positions bit for bit; then new ones. Triangles: a triangle not split keeps
 * its index (its corners may be renamed to a vertex's copy on its side); a
 * split triangle's slot holds its first piece, the other pieces follow the
 * old triangles, then the crack triangles (the + side's, then the − side's).
 *
 * Sides. side[v] = +1 or -1 for a vertex on the cut or crack that belongs to
 * that side of the fold (the side its normal n_k points to is +1), 0 for a
 * vertex both sides share (tips, fold edges inside the organ) and for every
 * vertex off the cut. An old vertex on the cut keeps its index for the +
 * side; its − copy is new, with origin = the old index. */
#ifndef TB_CUT_SURFACE_H
#define TB_CUT_SURFACE_H

#include "tb_fold.h"
#include "core/tb_error.h"
#include "core/tb_math.h"

typedef struct tb_cut_def {
  double snap;          /* cut points closer than snap x mean edge length to an old vertex
                         * become that vertex; 0: 1e-6 */
  double spacing;       /* crack Steiner grid spacing; 0: the mean edge length; < 0: no grid */
  const tb_vec3 *extra; /* optional crack points (e.g. meshless boundary points): each */
  int nextra;           /* projected onto its nearest piece, kept when inside the organ
                         * and farther than spacing / 2 from the other crack points */
} tb_cut_def;
tb_cut_def tb_cut_default_def(void);

typedef struct tb_cut_result {
  int nv;        /* vertices: the old ones first */
  tb_vec3 *x;    /* nv positions */
  int *origin;   /* nv: the old vertex a copy duplicates, v itself for an old vertex, -1
                  * for a vertex created on an edge, inside a triangle or on the crack */
  int *side;     /* nv: +1 / -1 / 0 (see above) */
  int ntri;      /* triangles */
  int *tri;      /* 3 ntri, outward */
  int *tri_from; /* ntri: the old triangle it comes from, -1 for a crack triangle */
  int nreskin;   /* vertices to re-skin: new ones and old ones whose 1-ring changed */
  int *reskin;   /* ascending */
  int cut;       /* 1 when the surface changed; 0 when the fold misses it or only touches */
  int split_tris, crack_tris; /* old triangles split; crack triangles (both sides) */
  int components_before, components_after;
  int perturbed; /* 0, or the attempt (1..3) that needed a deterministic shift of the fold */
} tb_cut_result;

/* Cuts the surface (nv points x, ntri triangles tri) with the fold. def may
 * be NULL (defaults). Errors ("tb_cut_surface: reason"): the input is not a
 * closed, oriented 2-manifold with positive volume (or has non-finite
 * points); a triangle lies in the plane of a piece it overlaps; a
 * configuration that stays inconsistent after three deterministic shifts of
 * the fold. On error *out is empty (safe to free). Same input, same output,
 * bit for bit. */
int tb_cut_surface(int nv, const tb_vec3 *x, int ntri, const int *tri, const tb_fold *fold,
                   const tb_cut_def *def, tb_cut_result *out, tb_error *err);
void tb_cut_result_free(tb_cut_result *r);

/* 1 when the triangles form a closed, consistently oriented 2-manifold: every
 * edge in exactly two triangles, in opposite directions; every used vertex's
 * link a single cycle; no degenerate triangle or index out of range. Unused
 * vertices are allowed. */
int tb_cut_is_closed_manifold(int nv, int ntri, const int *tri);
/* Connected components of the triangles (joined through shared vertices). */
int tb_cut_components(int nv, int ntri, const int *tri);
/* The piece (component) of each triangle, numbered in the order of their
 * first triangles, into of_tri (ntri); returns the count, or -1 out of
 * memory. */
int tb_cut_piece_of(int nv, int ntri, const int *tri, int *of_tri);
/* Which piece of a closed surface (triangles tri on points x, pieces
 * of_tri numbered 0 .. npieces - 1) holds each of the nq points q, by exact
 * ray parity per piece: out[k] is the lowest piece holding q[k], -1 when
 * none does, -2 when q[k] lies on the surface. 0, or -1 out of memory. */
int tb_cut_locate(const tb_vec3 *x, int ntri, const int *tri, const int *of_tri, int npieces,
                  int nq, const tb_vec3 *q, int *out);
/* Enclosed signed volume (divergence theorem). */
double tb_cut_volume(const tb_vec3 *x, int ntri, const int *tri);

/* CGAL's 2D constrained Delaunay triangulation (cutting/cut_cdt.cpp):
 * np points (xy pairs), nseg constraints (index pairs). Triangles are
 * counter-clockwise, as input indices (smallest first, sorted); region[t]
 * numbers the sets of triangles joined across unconstrained edges. Returns
 * 0, -1 on bad input or memory, -2 when constraints cross (a new point would
 * be needed), -3 on duplicate points; on failure *out is empty. */
typedef struct tb_cdt2 {
  int ntri;
  int *tri;    /* 3 ntri */
  int *region; /* ntri */
  int nregion;
} tb_cdt2;
int tb_cdt2_build(const double *xy, int np, const int *seg, int nseg, tb_cdt2 *out);
void tb_cdt2_free(tb_cdt2 *c);

#endif
