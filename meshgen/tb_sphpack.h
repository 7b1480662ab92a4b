/* Spheres filling a closed surface, for a metaball organ model (the metaball
 * hybrid-cutting patent fills the organ with overlapping spheres found
 * offline by a Voronoi analysis of its OBJ surface).
 *
 * tb_sphere_pack: samples the surface (its vertices, then area-weighted
 * points), finds each sample's inner Voronoi pole (CGAL's 3D Delaunay,
 * meshgen/sphpack_poles.cpp), which lies near the medial axis; the poles
 * inside the surface are the candidate centres, each with the exact distance
 * to the surface as its radius (so every sphere touches the surface and lies
 * inside it). Then, largest first, a candidate is taken unless its centre is
 * closer than alpha * R to a chosen sphere (centre C, radius R); passes with
 * alpha = 1, 0.75, 0.5, 0.35, 0.25, 0.15, 0.1, 0.05, 0 over the candidates
 * not yet taken stop at the target count. Candidates smaller than 5% of
 * the largest (at sharp rims and thin spots: nearly massless spheres) come
 * only in a second round of the same passes, when the first falls short. So the spheres overlap but
 * no two centres sit deep in each other while bigger gaps remain. Fewer spheres than asked come
 * back only when there are fewer distinct candidates (raise samples). Same surface and settings,
 * same spheres, bit for bit.
 *
 * tb_sphere_coverage: the share of the enclosed volume inside some sphere (a
 * grid of points, inside by ray parity along z) and the share of surface
 * vertices within skinning reach (some sphere with r <= d <= 2 r, d the
 * vertex's distance to the centre: the patent's skinning rule). */
#ifndef TB_SPHPACK_H
#define TB_SPHPACK_H

#include <stdint.h>

#include "collision/tb_bvh.h"
#include "core/tb_error.h"
#include "core/tb_mesh.h"
#include "core/tb_spheres.h"

/* ---- a closed surface for distance and inside queries ---- */
typedef struct tb_closed_surface {
  const tb_vec3 *x; /* the mesh's, not owned */
  const int *tri;
  int ntri;
  tb_bvh bvh; /* AABB hierarchy for the distance */
} tb_closed_surface;

/* Checks that m's triangles form a closed, oriented 2-manifold (errors are
 * "NAME: reason") and builds the hierarchy. */
int tb_closed_surface_init(tb_closed_surface *s, const tb_mesh *m, const char *name, tb_error *err);
void tb_closed_surface_free(tb_closed_surface *s);
/* Exact (up to rounding) distance from p to the nearest triangle. */
double tb_closed_surface_distance(const tb_closed_surface *s, tb_vec3 p);
/* 1 when p is inside: odd number of crossings of the ray from p along +z
 * (a point-in-triangle test in the xy plane with a tie rule that gives a
 * ray through a shared edge or vertex to exactly one of the triangles). */
int tb_closed_surface_inside(const tb_closed_surface *s, tb_vec3 p);
/* The heights, ascending, where the vertical line through (px, py) crosses
 * the surface (same rule), into z (room for ntri); returns how many. */
int tb_closed_surface_column(const tb_closed_surface *s, double px, double py, double *z);

/* ---- the packing ---- */
typedef struct tb_sphpack_def {
  int count;     /* target number of spheres (>= 1) */
  int samples;   /* surface samples; 0: max(used vertices, 20 * count, 4000) */
  uint64_t seed; /* for the area-weighted sample points */
} tb_sphpack_def;
tb_sphpack_def tb_sphpack_default_def(int count);

typedef struct tb_sphpack_stats {
  int samples;    /* points triangulated */
  int poles;      /* samples with an inner pole */
  int candidates; /* distinct poles inside the surface */
  double alpha;   /* separation factor of the last pass used */
} tb_sphpack_stats;

/* Fills out (largest sphere first); stats may be NULL. Errors: "NAME: reason". */
int tb_sphere_pack(const tb_mesh *surf, const char *name, const tb_sphpack_def *def,
                   tb_spheres *out, tb_sphpack_stats *stats, tb_error *err);

/* CGAL (meshgen/sphpack_poles.cpp): for each of np samples p with outward
 * normals n, its inner pole and pole radius |pole - p| (radius -1 when it
 * has none: no finite Voronoi vertex on the inner side, or a duplicate
 * sample). Returns 0, or -1 on non-finite input or a CGAL failure. */
int tb_voronoi_poles(const tb_vec3 *p, const tb_vec3 *n, int np, tb_vec3 *pole, double *pole_r);

/* ---- coverage ---- */
typedef struct tb_sphere_coverage {
  int grid_inside;       /* grid points inside the surface */
  int grid_covered;      /* ... of which inside some sphere */
  double volume;         /* grid_covered / grid_inside */
  int verts;             /* surface vertices (used by a triangle) */
  int reached;           /* ... with some sphere at r <= d <= 2 r (r from 1 - 1e-9) */
  double reach;          /* reached / verts */
  double sphere_volume;  /* sum of the sphere volumes / enclosed volume */
  int centres_outside;   /* centres not inside the surface */
  double max_protrusion; /* max over spheres of r - distance(centre, surface) */
} tb_sphere_coverage;

/* grid: points along the longest bounding-box side (>= 4), cell centres
 * nudged off the symmetry planes. Errors: "NAME: reason". */
int tb_sphere_coverage_of(const tb_mesh *surf, const char *name, const tb_spheres *s, int grid,
                          tb_sphere_coverage *cov, tb_error *err);

#endif
