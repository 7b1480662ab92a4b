/* The liver's volume mesh: its marching-cubes surface tetrahedralised by
 * TetGen with the boundary kept ("Y") and quality-bounded ("q1.4"). The
 * maximum tet volume ("a") is searched by bisection so that the relative
 * errors of the vertex and tet counts against the targets (thesis §2.5:
 * 1206 vertices, 4230 tets) balance: V/V* + T/T* = 2. Both must end within
 * 10%. With tets < 0 only the vertex count is targeted. (The thesis's QTetraMesher also remeshed
 * the boundary; with the surface kept, vertices and tets cannot both be matched exactly.)
 * With tet_verts 0 only the tet count is targeted (the 2022 patent's livers
 * of 596 ... 12829 tets): the same bisection on T/T* - 1, stopped once
 * within a quarter of the tolerance, the closest mesh kept; it must end
 * within TB_LIVER_TET_TOL (2%). The tet count falls in steps as the bound
 * grows (TetGen is deterministic, not strictly monotone), so the closest
 * mesh met on the way is kept. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "tb_meshgen.h"

/* Tets only (tet_verts 0): within TB_LIVER_TET_TOL of def->tets. */
static int tets_only(const tb_liver_def *def, const tb_mesh *surf, double volume, tb_mesh *tets,
                     tb_error *err) {
  double tt = def->tets;
  /* a bound of volume / (4 T*) forces at least 4 T* tets; the whole volume, none */
  double lo = log(volume / (4.0 * tt)), hi = log(volume);
  tb_mesh best;
  double best_b;
  if (tb_tetgen_search(surf, "pq1.4Y", lo, hi, 0, tt, 40, 1e-4, 0.25 * TB_LIVER_TET_TOL, &best,
                       &best_b, err))
    return -1;
  if (fabs(best_b) <= TB_LIVER_TET_TOL) {
    *tets = best;
    return 0;
  }
  int nt = best.ntet;
  tb_mesh_free(&best);
  return tb_error_set(err, "liver", 0,
                      "TetGen gives no mesh within %g%% of %d tets from a surface of %d vertices "
                      "(closest: %d)",
                      100 * TB_LIVER_TET_TOL, def->tets, surf->nv, nt);
}

int tb_liver_tets(const tb_liver_def *def, const tb_mesh *surf, tb_mesh *tets, tb_error *err) {
  double tv = def->tet_verts, tt = def->tets > 0 ? def->tets : def->tet_verts * 4230.0 / 1206.0;
  if (def->tets < 0) tt = -1; /* vertices only */
  double volume = tb_mesh_volume(surf);
  memset(tets, 0, sizeof *tets);
  if (def->tet_verts == 0) {
    if (def->tets <= 0 || !(volume > 0))
      return tb_error_set(err, "liver", 0,
                          "with tet_verts 0 (tets only) tets must be > 0, not %d (volume %g)",
                          def->tets, volume);
    return tets_only(def, surf, volume, tets, err);
  }
  if (def->tet_verts < surf->nv || !(volume > 0))
    return tb_error_set(err, "liver", 0,
                        "tet_verts %d must be at least the surface's %d vertices (volume %g)",
                        def->tet_verts, surf->nv, volume);
  double lo = log(volume / (20.0 * tv)), hi = log(volume); /* log of the volume bound */
  tb_mesh best;
  double best_b;
  if (tb_tetgen_search(surf, "pq1.4Y", lo, hi, tv, tt, 30, 1e-3, -1, &best, &best_b, err))
    return -1;
  if (fabs(best.nv / tv - 1) <= 0.1 && (tt < 0 || fabs(best.ntet / tt - 1) <= 0.1)) {
    *tets = best;
    return 0;
  }
  int nv = best.nv, nt = best.ntet;
  tb_mesh_free(&best);
  return tb_error_set(
      err, "liver", 0,
      "TetGen gives no mesh within 10%% of %g vertices and %g tets (closest: %d, %d)", tv,
      tt > 0 ? tt : NAN, nv, nt);
}

int tb_liver_of_tets(int tets, uint64_t seed, tb_mesh *out, tb_error *err) {
  tb_liver_def d = tb_liver_default_def();
  d.surface_verts = 0, d.tet_verts = 0, d.tets = tets, d.seed = seed;
  tb_mesh surf;
  if (tb_liver_surface(&d, &surf, err)) return -1;
  int rc = tb_liver_tets(&d, &surf, out, err);
  tb_mesh_free(&surf);
  return rc ? -1 : 0;
}
