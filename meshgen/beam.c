/* Cantilever beams: a box split into nx*ny*nz cubes, each cube into six
 * tetrahedra around a main diagonal (Kuhn's subdivision). TB_SPLIT_KUHN
 * uses the diagonal from (0,0,0) to (1,1,1) in every cube, which makes the
 * mesh lopsided: a vertical tip load also bends it sideways.
 * TB_SPLIT_SYMMETRIC mirrors the cubes of the upper half of each axis
 * (2i >= n) across their cell's mid-plane, so the mesh is mirror-symmetric
 * about the box's mid-planes when the counts are even. Either way a cube's
 * face diagonal depends only on the mirror flags of the two axes in that
 * face, which neighbours share, so the faces match and the mesh conforms. */
#include <stdlib.h>
#include <string.h>

#include "tb_meshgen.h"

int tb_beam(double lx, double ly, double lz, int nx, int ny, int nz, tb_mesh *out, tb_error *err) {
  return tb_beam_with_split(lx, ly, lz, nx, ny, nz, TB_SPLIT_KUHN, out, err);
}

int tb_beam_with_split(double lx, double ly, double lz, int nx, int ny, int nz, tb_beam_split split,
                       tb_mesh *out, tb_error *err) {
  memset(out, 0, sizeof *out);
  if (!(lx > 0 && ly > 0 && lz > 0) || !isfinite(lx + ly + lz))
    return tb_error_set(err, "beam", 0, "box sides must be positive and finite");
  if (nx < 1 || ny < 1 || nz < 1 || (double)nx * ny * nz > 2e6)
    return tb_error_set(err, "beam", 0, "cells %d x %d x %d: each must be >= 1, at most 2e6 in all",
                        nx, ny, nz);
  if (split != TB_SPLIT_KUHN && split != TB_SPLIT_SYMMETRIC)
    return tb_error_set(err, "beam", 0, "unknown split %d", (int)split);
  if (split == TB_SPLIT_SYMMETRIC && (ny % 2 || nz % 2))
    return tb_error_set(err, "beam", 0,
                        "split=symmetric needs even ny and nz (cells across the beam), not %d x %d",
                        ny, nz);
  int sx = nx + 1, sy = ny + 1, sz = nz + 1;
  out->nv = sx * sy * sz;
  out->ntet = 6 * nx * ny * nz;
  out->x = malloc(sizeof(tb_vec3) * (size_t)out->nv);
  out->tet = malloc(sizeof(int) * 4 * (size_t)out->ntet);
  if (!out->x || !out->tet) {
    tb_mesh_free(out);
    return tb_error_set(err, "beam", 0, "out of memory");
  }
  for (int k = 0; k < sz; k++)
    for (int j = 0; j < sy; j++)
      for (int i = 0; i < sx; i++)
        out->x[(k * sy + j) * sx + i] = tb_v3(lx * i / nx, ly * j / ny, lz * k / nz);
  /* the six orderings of the axes: walk from corner 000 to 111 */
  static const int perm[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
  int t = 0;
  for (int k = 0; k < nz; k++)
    for (int j = 0; j < ny; j++)
      for (int i = 0; i < nx; i++)
        for (int p = 0; p < 6; p++) {
          /* the walk over local corner bits l, each axis's bit inverted
           * where the cube is mirrored along that axis */
          int base[3] = {i, j, k}, n[3] = {nx, ny, nz}, flip[3], l[3] = {0, 0, 0};
          int *tet = out->tet + 4 * t++;
          for (int a = 0; a < 3; a++) flip[a] = split == TB_SPLIT_SYMMETRIC && 2 * base[a] >= n[a];
          for (int s = 0; s <= 3; s++) {
            if (s > 0) l[perm[p][s - 1]] = 1;
            int c[3];
            for (int a = 0; a < 3; a++) c[a] = base[a] + (l[a] ^ flip[a]);
            tet[s] = (c[2] * sy + c[1]) * sx + c[0];
          }
          const tb_vec3 *x = out->x;
          if (tb_tet_volume(x[tet[0]], x[tet[1]], x[tet[2]], x[tet[3]]) < 0) {
            int tmp = tet[2];
            tet[2] = tet[3], tet[3] = tmp;
          }
        }
  out->ntri = tb_mesh_tet_boundary(out, &out->tri);
  if (out->ntri < 0) {
    tb_mesh_free(out);
    return tb_error_set(err, "beam", 0, "out of memory");
  }
  return 0;
}
