/* Reference mesh-mesh collision from FCL and Bullet behind one C API:
 * FCL BVHModel<AABB> and BVHModel<OBBRSS> (collide with a large
 * num_max_contacts, pairs deduplicated) and Bullet GImpact
 * (btGImpactQuantizedBvh::find_collision candidates, then Bullet's triangle
 * test -- or our exact test on the same candidates). Models are prebuilt
 * from world-space vertices and collided with identity transforms, so FCL's
 * collide() does not deep-copy and rebuild on a non-identity transform. */
#ifndef TB_REFBVH_H
#define TB_REFBVH_H

#include "collision/tb_bvh.h"
#include "core/tb_error.h"
#include "core/tb_math.h"

typedef enum tb_ref_kind {
  TB_REF_FCL_AABB,
  TB_REF_FCL_OBBRSS,
  TB_REF_BULLET_GIMPACT,      /* Bullet's candidates and triangle test */
  TB_REF_BULLET_GIMPACT_EXACT /* Bullet's candidates, our exact triangle test */
} tb_ref_kind;

typedef struct tb_ref_bvh tb_ref_bvh;

tb_ref_bvh *tb_ref_bvh_build(tb_ref_kind kind, const tb_vec3 *x, int nv, const int *tri, int ntri,
                             tb_error *err);
/* New vertex positions (same topology): FCL refit (updateSubModel +
 * endUpdateModel(refit)), Bullet's updateBound after postUpdate. */
int tb_ref_bvh_update(tb_ref_bvh *m, const tb_vec3 *x, tb_error *err);
/* Every intersecting triangle pair of a and b (same kind), appended to out
 * (unsorted, may hold duplicates: call tb_pairlist_sort_unique). */
int tb_ref_bvh_collide(tb_ref_bvh *a, tb_ref_bvh *b, tb_pairlist *out, tb_error *err);
void tb_ref_bvh_free(tb_ref_bvh *m);

#endif
