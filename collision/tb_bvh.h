/* Bounding volume hierarchies over triangle meshes (thesis §4.3): Sphere,
 * AABB and the composite Sphere-AABB hierarchy (top layers Sphere, middle
 * layers Sphere+AABB with the sphere circumscribing the box, bottom layers
 * AABB; test rules of fig. 4.4, by default confirmed box against box,
 * see box_check), built top-down; all intersecting triangle
 * pairs between two meshes; rigid motion by the rotated-AABB update and
 * refit after deformation with the thesis's threshold delta. Nodes live in
 * flat arrays (hot: boxes, spheres, children; cold: build bookkeeping). */
#ifndef TB_BVH_H
#define TB_BVH_H

#include "tb_tritri.h"
#include "core/tb_error.h"
#include "core/tb_math.h"

/* ---- bounding volumes ---- */
typedef struct tb_aabb {
  tb_vec3 lo, hi;
} tb_aabb;
typedef struct tb_sphere {
  tb_vec3 c;
  double r;
} tb_sphere;

int tb_sphere_sphere(tb_sphere a, tb_sphere b);
int tb_sphere_aabb(tb_sphere s, tb_aabb b); /* closest point on the box */
int tb_aabb_aabb(tb_aabb a, tb_aabb b);
/* The sphere circumscribing a box: centre the box centre, radius half the
 * diagonal (thesis §4.3.3), rounded outward so it contains the box, and at
 * least TB_SPHERE_MIN_R so that squared radii never underflow (bv.c). */
#define TB_SPHERE_MIN_R 0x1p-500
tb_sphere tb_aabb_sphere(tb_aabb b);

/* ---- building ---- */
typedef enum tb_split_axis {
  TB_SPLIT_LONGEST,   /* longest extent of the triangle centroids */
  TB_SPLIT_VARIANCE,  /* largest variance of the centroids */
  TB_SPLIT_MIN_VOLUME /* smallest sum of the children's volumes */
} tb_split_axis;
typedef enum tb_split_point { TB_SPLIT_MEAN, TB_SPLIT_MEDIAN } tb_split_point;

/* Layer kinds: a node at depth d is Sphere when d < sphere_layers, Sphere+AABB
 * when d < sphere_layers + both_layers, else AABB. All-Sphere: sphere_layers
 * >= the depth; all-AABB: 0, 0. */
typedef struct tb_bvh_def {
  tb_split_axis axis;
  tb_split_point point;
  int max_depth;     /* stop: depth limit (root depth 0) */
  int min_leaf;      /* stop: no child gets fewer triangles than this... */
  int max_leaf;      /* ...and a node with at most max_leaf triangles is a leaf */
  int sphere_layers; /* composite layer depths */
  int both_layers;
  /* 1: a node pair whose fig.-4.4 test uses a sphere and passes is also
   * tested box against box (every node keeps its box up to date whatever
   * its kind), so the loose sphere levels only ever reject earlier, never
   * let a pair through that the boxes separate; 0: the thesis's rule
   * alone. Either way the pair sets are exact (both volumes hold the
   * node's triangles); see bvh_query.c. Only "composite" turns it on. */
  int box_check;
} tb_bvh_def;
/* AABB, longest, median, leaves <= 10, min_leaf 1, max_depth 40. */
tb_bvh_def tb_bvh_default_def(void);
/* The default with the layers of "sphere", "aabb" or "composite" (3/3,
 * with box_check);
 * any other name gives a zeroed def, which tb_bvh_build refuses. */
tb_bvh_def tb_bvh_kind_def(const char *kind);

enum { TB_BV_SPHERE = 1, TB_BV_AABB = 2 }; /* bits of tb_bvh.kind[] */

typedef struct tb_bvh {
  int nnodes, ntri, depth;
  /* hot, per node */
  tb_aabb *box;
  tb_sphere *sph;
  int *child;         /* first child (the second is child+1), -1 for a leaf */
  int *first, *count; /* range in tri_index (every node, children split it) */
  unsigned char *kind;
  int box_check; /* from the definition */
  /* rest volumes: those of the positions the hierarchy was built or last
   * refit for; tb_bvh_transform maps them, never the moved ones */
  tb_aabb *box0;
  tb_sphere *sph0;
  /* one past the last descendant: node k's descendants are the nodes
   * child[k] .. sub_end[k] - 1 (the build allocates depth first) */
  int *sub_end;
  /* per triangle */
  int *tri_index; /* triangle numbers in leaf order */
  const int *tri; /* the mesh's triangles (3 per), not owned */
} tb_bvh;

/* Refuses (-1, err) a triangle with a vertex that is not finite or lies
 * beyond TB_COORD_MAX (1e90, core/tb_mesh.h): within it, every square and
 * sum of squares of the volume arithmetic stays finite, and the volumes hold
 * their triangles down to subnormal coordinates (bv.c). */
int tb_bvh_build(tb_bvh *b, const tb_vec3 *x, const int *tri, int ntri, const tb_bvh_def *def,
                 tb_error *err);
void tb_bvh_free(tb_bvh *b);

/* ---- motion and deformation ---- */
/* Rigid motion x' = R x + t of the mesh, (R, t) taken from the rest
 * positions (build or last refit), so calls replace each other instead of
 * composing and boxes never grow without bound (thesis §4.3.3 part 3):
 * boxes by the rotated-AABB update (centre R c + t, half extents |R| h),
 * spheres move with their centres (radius kept); both widened by a few ulps
 * of the coordinates so they contain x' however the caller rounds it.
 * A volume moved beyond +-1e150 meets everything (see bvh_update.c). */
void tb_bvh_transform(tb_bvh *b, tb_mat3 R, tb_vec3 t);
/* Bottom-up refit from the (deformed) vertices x: leaf boxes rebuilt, a box
 * replaced only when ||Min'-Min||_2 + ||Max'-Max||_2 > delta (delta = 0:
 * exact boxes); a kept box is grown to contain the new one (so it stays
 * within delta of the exact box and queries stay exact). The refit volumes
 * become the rest volumes. Returns the number of nodes whose volume
 * changed, -1 (nothing changed) for a vertex that is not finite or lies
 * beyond TB_COORD_MAX (core/tb_mesh.h). Large hierarchies are refit on the
 * threads of tb_threads.h (whole subtrees per task): the same volumes for
 * any thread count. */
int tb_bvh_refit(tb_bvh *b, const tb_vec3 *x, double delta);

/* ---- queries ---- */
typedef struct tb_pairlist {
  int n, cap;
  int *ij; /* 2 per pair: triangle of A, triangle of B */
} tb_pairlist;
void tb_pairlist_free(tb_pairlist *p);
/* Appends (i, j); returns 0 or -1 out of memory (p unchanged). */
int tb_pairlist_push(tb_pairlist *p, int i, int j);
/* Sorts by (i, j) and removes duplicates. */
void tb_pairlist_sort_unique(tb_pairlist *p);

typedef struct tb_collide_stats {
  long bv_tests;  /* volume-volume tests */
  long tri_tests; /* triangle-triangle tests */
} tb_collide_stats;

/* Every intersecting pair (i of A, j of B): A's vertices xa, B's xb (world
 * space, the positions the hierarchies were built/refit/transformed for).
 * The pairs are appended to out unsorted, each once, in the same order for
 * any thread count (tb_threads.h; queries that reach deep run on threads,
 * see bvh_query.c); returns 0 or -1 out of memory. tri_tests counts
 * calls of test (pairs whose triangle boxes overlap, after each leaf's
 * triangles were checked against the other leaf's box). */
int tb_bvh_collide(const tb_bvh *a, const tb_vec3 *xa, const tb_bvh *b, const tb_vec3 *xb,
                   tb_tritri_fn test, tb_pairlist *out, tb_collide_stats *stats);
/* The surface's self-intersecting triangle pairs (i < j, sorted): pairs
 * that cross other than in a vertex or an edge they share, decided by the
 * exact test; coplanar pairs (touching sheets) are not counted
 * (collision/self.c says how). Returns 0, or -1 with err (a coordinate the
 * hierarchy refuses, no memory). */
int tb_collide_self(const tb_vec3 *x, const int *tri, int ntri, tb_pairlist *out, tb_error *err);
/* Brute force over all ntri_a * ntri_b pairs; for a test the method table
 * marks exact, pairs with disjoint triangle boxes are skipped (such a test
 * says 0 for them), any other test is called on every pair. */
int tb_collide_brute(const tb_vec3 *xa, const int *ta, int na, const tb_vec3 *xb, const int *tb,
                     int nb, tb_tritri_fn test, tb_pairlist *out, tb_collide_stats *stats);

#endif
