/* The liver-and-instrument collision scene (thesis §4.5, fig. 4.21). */
#include <math.h>
#include <stdlib.h>

#include "tb_collision_scene.h"
#include "meshgen/tb_meshgen.h"
#include "scenes/tb_collider.h"

int tb_collision_scene_make(uint64_t seed, tb_mesh *liver, tb_mesh *instrument, tb_error *err) {
  tb_liver_def d = tb_liver_default_def();
  d.seed = seed;
  tb_mesh surf, tets;
  if (tb_liver_surface(&d, &surf, err)) return -1;
  int rc = tb_liver_tets(&d, &surf, &tets, err);
  tb_mesh_free(&surf);
  if (rc) return -1;
  int *faces = NULL, nf = tb_mesh_tet_faces(&tets, &faces);
  free(tets.tri), free(tets.tet);
  *liver = tets;
  liver->tri = faces, liver->ntri = nf;
  liver->tet = NULL, liver->ntet = 0;
  if (nf < 0) {
    tb_mesh_free(liver);
    return tb_error_set(err, "scene", 0, "out of memory");
  }
  tb_instrument_def id = tb_instrument_default_def();
  if (tb_instrument(&id, instrument, err)) {
    tb_mesh_free(liver);
    return -1;
  }
  return 0;
}

void tb_collision_scene_pose(double s, tb_mat3 *R, tb_vec3 *t) {
  *R = tb_m3_rotation(tb_v3(0, 1, 0), M_PI / 2 + 0.15); /* shaft toward +x, tilted */
  *t = tb_v3(7.0 - 3.5 * s, 0.2, 0.3 + 0.1 * s);
}

void tb_collision_scene_deform(const tb_vec3 *x0, int n, double t, double amp, tb_vec3 *out) {
  for (int i = 0; i < n; i++) {
    tb_vec3 p = x0[i];
    double a = sin(0.6 * p.x + 1.7 * t), b = cos(0.9 * p.y - 1.3 * t), c = sin(1.1 * p.z + 0.8 * t);
    out[i] = tb_add(p, tb_scale(tb_v3(0.3 * b * c, 0.4 * a * c, a * b), amp));
  }
}

const int tb_collision_scene_thesis_pairs[TB_COLLISION_SCENE_ROWS] = {0,   32,  97,  279,
                                                                      534, 733, 925, 1106};

int tb_collision_scene_row_poses(tb_collider *c, int npose, const int *target, int n, double *s,
                                 int *pairs, tb_error *err) {
  int *count = malloc(sizeof(int) * (size_t)(npose > 0 ? npose : 1));
  tb_pairlist pl = {0, 0, NULL};
  int rc = count && npose >= 2 ? 0 : tb_error_set(err, "scene", 0, "out of memory (or npose < 2)");
  for (int k = 0; !rc && k < npose; k++) {
    tb_mat3 R;
    tb_vec3 t;
    tb_collision_scene_pose((double)k / (npose - 1), &R, &t);
    rc = tb_collider_pose(c, R, t, err) || tb_collider_query(c, &pl, NULL, err);
    count[k] = pl.n;
  }
  for (int r = 0; !rc && r < n; r++) {
    int best = 0;
    for (int k = 1; k < npose; k++)
      if (abs(count[k] - target[r]) < abs(count[best] - target[r])) best = k;
    s[r] = (double)best / (npose - 1), pairs[r] = count[best];
  }
  tb_pairlist_free(&pl);
  free(count);
  return rc ? -1 : 0;
}
