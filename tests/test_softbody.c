/* Bullet's btSoftBody behind models/tb_softbody.h (the pbd suite's
 * peer): a block of tets dropped onto the static ground falls, lands and
 * stays above the ground plane within a small tolerance; its mass is the
 * density times the volume; bad settings are refused. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "tb_test.h"
#include "meshgen/tb_meshgen.h"
#include "models/tb_softbody.h"

/* A 2 x 2 x 1 block of 4 x 4 x 2 cubes (192 tets), bottom at height h. */
static int block(double h, tb_mesh *m) {
  tb_error err;
  if (tb_beam(2, 2, 1, 4, 4, 2, m, &err)) return -1;
  for (int i = 0; i < m->nv; i++) m->x[i].z += h;
  return 0;
}

static double lowest(const tb_vec3 *x, int n) {
  double z = INFINITY;
  for (int i = 0; i < n; i++) z = fmin(z, x[i].z);
  return z;
}

static void softbody_drop(void) {
  tb_mesh m;
  TB_CHECK(block(0.5, &m) == 0);
  tb_softbody_def d = tb_softbody_default_def();
  d.density = 2, d.stiffness = 0.4, d.iterations = 5, d.friction = 0.5, d.margin = 0.01;
  d.gravity = tb_v3(0, 0, -9.81), d.has_ground = 1;
  tb_error err;
  tb_softbody *b = tb_softbody_create(&m, &d, &err);
  TB_CHECK_MSG(b != NULL, "%s", err.msg);
  if (!b) {
    tb_mesh_free(&m);
    return;
  }
  TB_CHECK(tb_softbody_nodes(b) == m.nv);
  int *e = NULL;
  TB_CHECK(tb_softbody_links(b) == tb_mesh_edges(&m, &e));
  free(e);
  TB_CHECK_NEAR(tb_softbody_total_mass(b), 2 * tb_mesh_volume(&m), 1e-9);
  tb_vec3 *x = malloc(sizeof(tb_vec3) * (size_t)m.nv);
  double deepest = 0, first = 0;
  for (int k = 0; k < 300; k++) { /* 1.5 s: a fall of 0.5 takes 0.32 s */
    TB_CHECK(tb_softbody_step(b, 0.005, &err) == 0);
    tb_softbody_positions(b, x);
    deepest = fmax(deepest, -lowest(x, m.nv));
    if (k == 9) first = lowest(x, m.nv);
  }
  /* it fell freely for 10 steps: symplectic Euler, g dt^2 n (n + 1) / 2 */
  TB_CHECK_MSG(fabs(0.5 - first - 9.81 * 0.005 * 0.005 * 55) < 1e-6, "fell %.9g in 0.05 s",
               0.5 - first);
  double end = lowest(x, m.nv), size = sqrt(9.0);
  TB_CHECK_MSG(deepest <= 0.01 * size, "a node %g below the ground", deepest);
  TB_CHECK_MSG(end > -0.01 * size && end < d.margin + 0.01 * size, "lowest node at %g at 1.5 s",
               end);
  free(x);
  tb_softbody_destroy(b);
  d.stiffness = 0;
  TB_CHECK(tb_softbody_create(&m, &d, &err) == NULL && strstr(err.msg, "stiffness"));
  tb_mesh_free(&m);
}

const tb_test_case tb_tests_softbody[] = {
    {"softbody_drop", softbody_drop},
    {0, 0},
};
