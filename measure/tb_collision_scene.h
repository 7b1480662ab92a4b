/* The collision scene of thesis §4.5: the liver's collision model (every
 * face of its tet mesh) fixed, the instrument moving along a scripted path
 * into it; and the smooth time-varying displacement that deforms the liver
 * in the refit suite. */
#ifndef TB_COLLISION_SCENE_H
#define TB_COLLISION_SCENE_H

#include <stdint.h>

#include "core/tb_error.h"
#include "core/tb_mesh.h"

/* liver: the collision triangles over the tet-mesh vertices; instrument:
 * the grasper (tip at the origin, shaft along +z). */
int tb_collision_scene_make(uint64_t seed, tb_mesh *liver, tb_mesh *instrument, tb_error *err);
/* The path, s in [0, 1]: the grasper lying nearly along x, its jaws ahead,
 * the tip moving from x = 7 (clear of the liver) to x = 3.5 (deep inside). */
void tb_collision_scene_pose(double s, tb_mat3 *R, tb_vec3 *t);
/* Thesis table 4.2's rows: intersecting triangle pairs 0 ... 1106. */
#define TB_COLLISION_SCENE_ROWS 8
extern const int tb_collision_scene_thesis_pairs[TB_COLLISION_SCENE_ROWS];
/* The path positions, among npose evenly spaced samples of [0, 1], whose
 * intersecting-pair counts (c: the liver fixed, the instrument posed by
 * tb_collision_scene_pose) are nearest each of the n targets (the first of equals):
 * s[r] and its count pairs[r]. */
typedef struct tb_collider tb_collider;
int tb_collision_scene_row_poses(tb_collider *c, int npose, const int *target, int n, double *s,
                                 int *pairs, tb_error *err);
/* The liver's rest positions x0 displaced at time t (smooth, amplitude amp). */
void tb_collision_scene_deform(const tb_vec3 *x0, int n, double t, double amp, tb_vec3 *out);

#endif
