/* The collider table behind `collide` and the collision suites (see
 * tb_collider.h). Ours keeps B's build-time hierarchy and moves its rest
 * volumes into a working copy at each pose by the thesis's rotated-AABB
 * update (tb_bvh_transform maps box0/sph0, so poses never compound); the
 * references get B's world-space vertices (FCL's collide() would deep-copy
 * and rebuild both models on a non-identity transform). */
#include <stdlib.h>
#include <string.h>

#include "tb_collider.h"
#include "reference/tb_refbvh.h"

static const char *const methods[] = {"sphere",
                                      "aabb",
                                      "composite",
                                      "fcl-aabb",
                                      "fcl-obbrss",
                                      "bullet-gimpact",
                                      "bullet-gimpact-exact",
                                      "brute"};
static const tb_ref_kind ref_kinds[] = {TB_REF_FCL_AABB, TB_REF_FCL_OBBRSS, TB_REF_BULLET_GIMPACT,
                                        TB_REF_BULLET_GIMPACT_EXACT};

struct tb_collider {
  int family; /* 0 ours, 1 reference, 2 brute */
  tb_ref_kind ref;
  const tb_mesh *a, *b;
  tb_vec3 *xa; /* A's current vertices (deformations) */
  tb_vec3 *xb; /* B's world-space vertices at the current pose */
  tb_bvh_def def_a;
  tb_bvh ha, hb; /* ours: A's hierarchy, B's build-time hierarchy */
  tb_aabb *box;  /* ours: B's volumes at the current pose */
  tb_sphere *sph;
  tb_ref_bvh *ra, *rb; /* references */
  tb_tritri_fn test;
};

const char *const *tb_collider_methods(int *count) {
  *count = (int)(sizeof methods / sizeof methods[0]);
  return methods;
}

int tb_collider_is_ours(const char *m) {
  return !strcmp(m, "sphere") || !strcmp(m, "aabb") || !strcmp(m, "composite");
}

int tb_collision_mesh(const tb_mesh *m, tb_mesh *out, tb_error *err) {
  if (tb_mesh_copy(out, m)) return tb_error_set(err, "mesh", 0, "out of memory");
  if (!out->ntri && out->ntet) {
    out->ntri = tb_mesh_tet_faces(m, &out->tri);
    if (out->ntri < 0) {
      tb_mesh_free(out);
      return tb_error_set(err, "mesh", 0, "out of memory");
    }
  }
  free(out->tet);
  out->tet = NULL, out->ntet = 0;
  if (!out->ntri) {
    tb_mesh_free(out);
    return tb_error_set(err, "mesh", 0, "no triangles to collide");
  }
  return 0;
}

void tb_collider_free(tb_collider *c) {
  if (!c) return;
  tb_bvh_free(&c->ha), tb_bvh_free(&c->hb);
  tb_ref_bvh_free(c->ra), tb_ref_bvh_free(c->rb);
  free(c->xa), free(c->xb), free(c->box), free(c->sph);
  free(c);
}

tb_collider *tb_collider_new(const char *method, const tb_mesh *a, const tb_mesh *b,
                             const tb_bvh_def *def_a, const tb_bvh_def *def_b, tb_tritri_fn test,
                             tb_error *err) {
  tb_collider *c = calloc(1, sizeof *c);
  if (!c) return tb_error_set(err, "collide", 0, "out of memory"), NULL;
  c->a = a, c->b = b, c->test = test ? test : tb_tritri_exact;
  c->xa = malloc(sizeof(tb_vec3) * (size_t)a->nv);
  c->xb = malloc(sizeof(tb_vec3) * (size_t)b->nv);
  if (!c->xa || !c->xb) goto oom;
  memcpy(c->xa, a->x, sizeof(tb_vec3) * (size_t)a->nv);
  memcpy(c->xb, b->x, sizeof(tb_vec3) * (size_t)b->nv);
  int n;
  tb_collider_methods(&n);
  int k = 0;
  while (k < n && strcmp(methods[k], method)) k++;
  if (k == n) {
    tb_collider_free(c);
    tb_error_set(err, "collide", 0, "unknown method '%s'", method);
    return NULL;
  }
  if (tb_collider_is_ours(method)) {
    c->family = 0;
    c->def_a = def_a ? *def_a : tb_bvh_kind_def(method);
    tb_bvh_def db = def_b ? *def_b : tb_bvh_kind_def(method);
    if (tb_bvh_build(&c->ha, c->xa, a->tri, a->ntri, &c->def_a, err) ||
        tb_bvh_build(&c->hb, b->x, b->tri, b->ntri, &db, err)) {
      tb_collider_free(c);
      return NULL;
    }
    c->box = malloc(sizeof(tb_aabb) * (size_t)c->hb.nnodes);
    c->sph = malloc(sizeof(tb_sphere) * (size_t)c->hb.nnodes);
    if (!c->box || !c->sph) goto oom;
    memcpy(c->box, c->hb.box, sizeof(tb_aabb) * (size_t)c->hb.nnodes);
    memcpy(c->sph, c->hb.sph, sizeof(tb_sphere) * (size_t)c->hb.nnodes);
  } else if (!strcmp(method, "brute")) {
    c->family = 2;
  } else {
    c->family = 1;
    c->ref = ref_kinds[k - 3];
    c->ra = tb_ref_bvh_build(c->ref, c->xa, a->nv, a->tri, a->ntri, err);
    c->rb = c->ra ? tb_ref_bvh_build(c->ref, c->xb, b->nv, b->tri, b->ntri, err) : NULL;
    if (!c->rb) {
      tb_collider_free(c);
      return NULL;
    }
  }
  return c;
oom:
  tb_collider_free(c);
  tb_error_set(err, "collide", 0, "out of memory");
  return NULL;
}

int tb_collider_pose(tb_collider *c, tb_mat3 R, tb_vec3 t, tb_error *err) {
  for (int i = 0; i < c->b->nv; i++) c->xb[i] = tb_add(tb_m3_mulv(R, c->b->x[i]), t);
  if (c->family == 0) { /* B's rest volumes (box0, sph0) moved into the view's own arrays */
    tb_bvh v = c->hb;
    v.box = c->box, v.sph = c->sph;
    tb_bvh_transform(&v, R, t);
  } else if (c->family == 1) {
    tb_ref_bvh_free(c->rb);
    c->rb = tb_ref_bvh_build(c->ref, c->xb, c->b->nv, c->b->tri, c->b->ntri, err);
    if (!c->rb) return -1;
  }
  return 0;
}

int tb_collider_deform(tb_collider *c, const tb_vec3 *x, double delta, tb_error *err) {
  memcpy(c->xa, x, sizeof(tb_vec3) * (size_t)c->a->nv);
  if (c->family == 0) {
    if (delta >= 0) {
      tb_bvh_refit(&c->ha, c->xa, delta);
    } else {
      tb_bvh_free(&c->ha);
      if (tb_bvh_build(&c->ha, c->xa, c->a->tri, c->a->ntri, &c->def_a, err)) return -1;
    }
  } else if (c->family == 1) {
    return tb_ref_bvh_update(c->ra, c->xa, err);
  }
  return 0;
}

int tb_collider_query(tb_collider *c, tb_pairlist *out, tb_collide_stats *st, tb_error *err) {
  out->n = 0;
  tb_collide_stats local = {0, 0};
  if (!st) st = &local;
  st->bv_tests = st->tri_tests = 0;
  int rc;
  if (c->family == 0) {
    tb_bvh v = c->hb;
    v.box = c->box, v.sph = c->sph;
    rc = tb_bvh_collide(&c->ha, c->xa, &v, c->xb, c->test, out, st);
  } else if (c->family == 2) {
    rc = tb_collide_brute(c->xa, c->a->tri, c->a->ntri, c->xb, c->b->tri, c->b->ntri, c->test, out,
                          st);
  } else {
    return tb_ref_bvh_collide(c->ra, c->rb, out, err) ? -1 : (tb_pairlist_sort_unique(out), 0);
  }
  if (rc) return tb_error_set(err, "collide", 0, "out of memory");
  tb_pairlist_sort_unique(out);
  return 0;
}

int tb_pairlist_difference(const tb_pairlist *a, const tb_pairlist *b) {
  int d = 0, i = 0, j = 0;
  while (i < a->n || j < b->n) {
    long ka = i < a->n ? (long)a->ij[2 * i] << 32 | a->ij[2 * i + 1] : -1;
    long kb = j < b->n ? (long)b->ij[2 * j] << 32 | b->ij[2 * j + 1] : -1;
    if (ka == kb)
      i++, j++;
    else if (kb < 0 || (ka >= 0 && ka < kb))
      i++, d++;
    else
      j++, d++;
  }
  return d;
}
