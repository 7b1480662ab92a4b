/* fem-corot's cut: the tets the blade touches are removed (carve.c). A
 * removed tet keeps its place in every per-tet array and the patterns, with
 * volume 0, so its forces, its R K_e R^T and its Laplacian vanish; the
 * masses are lumped again from the tets left, and the next step refactors.
 * A piece cut free falls under gravity: the mass keeps alpha M + beta K
 * positive definite (quasistatic=1 has no mass: a free piece is singular
 * and the step says so). */
#include <string.h>

#include "fem_priv.h"

int tb_fem_cut(void *self, const tb_cut_event *ev, tb_cut_stats *st, tb_error *err) {
  tb_fem *f = self;
  if (ev->kind == TB_CUT_BEGIN && f->consistent)
    return tb_error_set(err, f->name, 0,
                        "cutting needs lumped masses (consistent_mass=0): removing a tet from a "
                        "consistent mass matrix is not built");
  int nhit = tb_carve_event(&f->carve, ev, f->x, f->tet, f->ntet, f->carve.alive, f->hit, err);
  if (nhit < 0) return -1;
  if (ev->kind == TB_CUT_END && st) tb_carve_stats(&f->carve, st);
  if (nhit == 0) return 0;
  for (int t = 0; t < f->ntet; t++)
    if (f->hit[t]) {
      f->carve.alive[t] = 0, f->hit[t] = 0, f->vol[t] = 0;
      memset(f->ke + 144 * (size_t)t, 0, 144 * sizeof(double));
    }
  tb_fem_laplacian(f);
  if (tb_carve_update(&f->carve, f->tet, f->ntet, f->carve.alive, nhit, f->density, f->node_mass,
                      err))
    return -1;
  for (int n = 0; n < f->nv; n++) f->mass[n] = f->carve.mass[n], f->mb[f->diag[n]] = f->mass[n];
  f->factored = 0;
  return 0;
}

const unsigned char *tb_fem_tets_alive(const void *self) {
  return ((const tb_fem *)self)->carve.alive;
}

tb_surface tb_fem_surface(const void *self) {
  const tb_fem *f = self;
  return tb_carve_surface(&f->carve, f->x);
}
