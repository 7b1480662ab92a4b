/* One mesh-mesh collision method behind one interface, for `collide` and the
 * collision suites: ours (sphere, aabb, composite hierarchies with a chosen
 * triangle test), the references (fcl-aabb, fcl-obbrss, bullet-gimpact,
 * bullet-gimpact-exact) and brute force. A is fixed (or deformed), B moves
 * rigidly: x_B = R x_B,local + t. */
#ifndef TB_COLLIDER_H
#define TB_COLLIDER_H

#include "collision/tb_bvh.h"
#include "core/tb_error.h"
#include "core/tb_mesh.h"

typedef struct tb_collider tb_collider;

/* Method names, in table order. */
const char *const *tb_collider_methods(int *count);
int tb_collider_is_ours(const char *method);

/* def_a/def_b: hierarchy settings for ours (NULL: tb_bvh_kind_def(method));
 * test: triangle test for ours and brute (NULL: exact). The meshes must
 * outlive the collider. */
tb_collider *tb_collider_new(const char *method, const tb_mesh *a, const tb_mesh *b,
                             const tb_bvh_def *def_a, const tb_bvh_def *def_b, tb_tritri_fn test,
                             tb_error *err);
/* Puts B at pose (R, t): ours by the rotated-AABB update of B's build-time
 * hierarchy; references rebuild B's model from world-space vertices. Not
 * part of the timed query. */
int tb_collider_pose(tb_collider *c, tb_mat3 R, tb_vec3 t, tb_error *err);
/* A deformed to positions x (same topology): ours refit with delta (delta <
 * 0: rebuild from scratch); references update (FCL refit, Bullet update). */
int tb_collider_deform(tb_collider *c, const tb_vec3 *x, double delta, tb_error *err);
/* Every intersecting pair, sorted and unique, replacing out's contents. */
int tb_collider_query(tb_collider *c, tb_pairlist *out, tb_collide_stats *st, tb_error *err);
void tb_collider_free(tb_collider *c);

/* Pairs in exactly one of two sorted, unique lists. */
int tb_pairlist_difference(const tb_pairlist *a, const tb_pairlist *b);

/* A mesh's collision triangles: its triangles, or all faces of its tets
 * when it has none (the thesis's liver model). Returns a new mesh. */
int tb_collision_mesh(const tb_mesh *m, tb_mesh *out, tb_error *err);

#endif
