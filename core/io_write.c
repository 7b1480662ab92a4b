/* Mesh writers: OBJ and OFF (triangles; a tet mesh without triangles is
 * written as its boundary; only the vertices the triangles use, renumbered
 * in their original order), TetGen .node/.ele/.face (1-based, TetGen's
 * default) and VTK legacy ASCII ("VTK File Formats", Kitware: an
 * UNSTRUCTURED_GRID of VTK_TETRA cells, type 10, or POLYDATA polygons over
 * the vertices they use) and Gmsh's MSH 2.2 ASCII (Gmsh reference manual
 * §9.1: nodes, then triangles, type 2, and tets, type 4, each with the two
 * tags physical 1 and elementary 1).
 * Doubles are printed with %.17g so a write-read round trip is exact. */
#include <errno.h>
#include <stdlib.h>
#include <string.h>

#include "io_internal.h"

/* Refuses meshes a reader could not read back: bad indices, non-finite x. */
static int check(const char *path, const tb_mesh *m, tb_error *err) {
  if (m->nv < 0 || m->ntri < 0 || m->ntet < 0 || (m->nv && !m->x) || (m->ntri && !m->tri) ||
      (m->ntet && !m->tet))
    return tb_error_set(err, path, 0, "cannot write: inconsistent mesh counts");
  for (int i = 0; i < m->nv; i++)
    if (!tb_isfinite3(m->x[i]))
      return tb_error_set(err, path, 0, "cannot write: vertex %d is not finite", i);
  int tet, v;
  long e;
  if (tb_mesh_bad_index(m, &tet, &e, &v))
    return tb_error_set(err, path, 0, "cannot write: %s %ld uses vertex %d of %d",
                        tet ? "tet" : "triangle", e, v, m->nv);
  return 0;
}

static FILE *open_out(const char *path, tb_error *err) {
  FILE *f = fopen(path, "wb");
  if (!f) tb_error_set(err, path, 0, "cannot open for writing: %s", strerror(errno));
  return f;
}

static int close_out(FILE *f, const char *path, tb_error *err) {
  int bad = ferror(f), e = errno;
  if (fclose(f) != 0 || bad)
    return tb_error_set(err, path, 0, "write failed: %s", strerror(bad ? e : errno));
  return 0;
}

/* Each point (each with map[i] >= 0 when map is not NULL) as LEAD x y z,
 * or "i x y z" (1-based) when lead is NULL. */
static void put_points(FILE *f, const tb_mesh *m, const int *map, const char *lead) {
  for (int i = 0; i < m->nv; i++) {
    if (map && map[i] < 0) continue;
    if (lead)
      fputs(lead, f);
    else
      fprintf(f, "%d ", i + 1);
    fprintf(f, "%.17g %.17g %.17g\n", m->x[i].x, m->x[i].y, m->x[i].z);
  }
}

/* Each k-index cell as LEAD i0+base ..., or "n i0+base ..." when lead is
 * NULL; indices through map when it is not NULL. */
static void put_cells(FILE *f, const int *idx, const int *map, int n, int k, const char *lead,
                      int base) {
  for (int i = 0; i < n; i++) {
    if (lead)
      fputs(lead, f);
    else
      fprintf(f, "%d", i + 1);
    for (int j = 0; j < k; j++)
      fprintf(f, " %d", (map ? map[idx[k * i + j]] : idx[k * i + j]) + base);
    fputc('\n', f);
  }
}

/* The triangles to write: the mesh's own, or its tets' boundary (*owned). */
static int surface(const char *path, const tb_mesh *m, const int **tri, int **owned,
                   tb_error *err) {
  *owned = NULL;
  *tri = m->tri;
  if (m->ntri > 0 || m->ntet == 0) return m->ntri;
  int n = tb_mesh_tet_boundary(m, owned);
  if (n < 0) return tb_error_set(err, path, 0, "out of memory");
  *tri = *owned;
  return n;
}

/* The vertices n triangles use, renumbered in their order: *map (malloc'ed,
 * nv entries, -1 for unused vertices); returns how many are used, or -1.
 * Without triangles every vertex is kept (a point cloud stays one). */
static int compact(const char *path, const tb_mesh *m, const int *tri, int n, int **map,
                   tb_error *err) {
  *map = malloc(sizeof(int) * (size_t)(m->nv > 0 ? m->nv : 1));
  if (!*map) return tb_error_set(err, path, 0, "out of memory");
  for (int i = 0; i < m->nv; i++) (*map)[i] = n > 0 ? -1 : 0;
  for (long i = 0; i < 3L * n; i++) (*map)[tri[i]] = 0;
  int used = 0;
  for (int i = 0; i < m->nv; i++)
    if ((*map)[i] == 0) (*map)[i] = used++;
  return used;
}

static int write_surface(const char *path, const tb_mesh *m, int off, tb_error *err) {
  const int *tri;
  int *owned, *map = NULL, n, nv = -1;
  if (check(path, m, err) || (n = surface(path, m, &tri, &owned, err)) < 0) return -1;
  FILE *f = (nv = compact(path, m, tri, n, &map, err)) < 0 ? NULL : open_out(path, err);
  if (f) {
    if (off)
      fprintf(f, "OFF\n%d %d 0\n", nv, n);
    else
      fprintf(f, "# %d vertices, %d triangles\n", nv, n);
    put_points(f, m, map, off ? "" : "v ");
    put_cells(f, tri, map, n, 3, off ? "3" : "f", off ? 0 : 1);
  }
  free(owned);
  free(map);
  return f ? close_out(f, path, err) : -1;
}

int tb_write_obj(const char *path, const tb_mesh *m, tb_error *err) {
  return write_surface(path, m, 0, err);
}
int tb_write_off(const char *path, const tb_mesh *m, tb_error *err) {
  return write_surface(path, m, 1, err);
}

/* ASCII STL: each triangle with its unit normal (right-handed order), the
 * vertices %.17g as everywhere (a reader gets the same doubles back). */
int tb_write_stl(const char *path, const tb_mesh *m, tb_error *err) {
  const int *tri;
  int *owned, n;
  if (check(path, m, err) || (n = surface(path, m, &tri, &owned, err)) < 0) return -1;
  FILE *f = open_out(path, err);
  if (f) {
    fputs("solid tissuebench\n", f);
    for (int t = 0; t < n; t++) {
      tb_vec3 a = m->x[tri[3 * t]], b = m->x[tri[3 * t + 1]], c = m->x[tri[3 * t + 2]];
      tb_vec3 nrm = tb_cross(tb_sub(b, a), tb_sub(c, a));
      double l = tb_len(nrm);
      if (l > 0) nrm = tb_scale(nrm, 1 / l);
      fprintf(f, "facet normal %.17g %.17g %.17g\nouter loop\n", nrm.x, nrm.y, nrm.z);
      for (int k = 0; k < 3; k++) {
        tb_vec3 p = m->x[tri[3 * t + k]];
        fprintf(f, "vertex %.17g %.17g %.17g\n", p.x, p.y, p.z);
      }
      fputs("endloop\nendfacet\n", f);
    }
    fputs("endsolid tissuebench\n", f);
  }
  free(owned);
  return f ? close_out(f, path, err) : -1;
}

/* base.node, base.ele and base.face (the mesh's triangles, maybe none). */
int tb_write_tetgen(const char *path, const tb_mesh *m, tb_error *err) {
  static const char *const ext[] = {".node", ".ele", ".face"};
  if (check(path, m, err)) return -1;
  const char *dot = strrchr(path, '.');
  size_t len = dot ? (size_t)(dot - path) : strlen(path);
  char *name = malloc(len + 6);
  if (!name) return tb_error_set(err, path, 0, "out of memory");
  memcpy(name, path, len);
  int rc = 0;
  for (int k = 0; k < 3 && rc == 0; k++) {
    strcpy(name + len, ext[k]);
    FILE *f = open_out(name, err);
    if (!f) {
      rc = -1;
      break;
    }
    if (k == 0) {
      fprintf(f, "%d 3 0 0\n", m->nv);
      put_points(f, m, NULL, NULL);
    } else if (k == 1) {
      fprintf(f, "%d 4 0\n", m->ntet);
      put_cells(f, m->tet, NULL, m->ntet, 4, NULL, 1);
    } else {
      fprintf(f, "%d 0\n", m->ntri);
      put_cells(f, m->tri, NULL, m->ntri, 3, NULL, 1);
    }
    rc = close_out(f, name, err);
  }
  free(name);
  return rc;
}

int tb_write_vtk(const char *path, const tb_mesh *m, tb_error *err) {
  if (check(path, m, err)) return -1;
  int tets = m->ntet > 0, *map = NULL, nv = m->nv;
  if (!tets && (nv = compact(path, m, m->tri, m->ntri, &map, err)) < 0) return -1;
  FILE *f = open_out(path, err);
  if (!f) {
    free(map);
    return -1;
  }
  fprintf(f, "# vtk DataFile Version 3.0\ntissuebench mesh\nASCII\nDATASET %s\nPOINTS %d double\n",
          tets ? "UNSTRUCTURED_GRID" : "POLYDATA", nv);
  put_points(f, m, map, "");
  if (tets) {
    fprintf(f, "CELLS %d %ld\n", m->ntet, 5L * m->ntet);
    put_cells(f, m->tet, NULL, m->ntet, 4, "4", 0);
    fprintf(f, "CELL_TYPES %d\n", m->ntet);
    for (int i = 0; i < m->ntet; i++) fputs("10\n", f);
  } else if (m->ntri > 0) {
    fprintf(f, "POLYGONS %d %ld\n", m->ntri, 4L * m->ntri);
    put_cells(f, m->tri, map, m->ntri, 3, "3", 0);
  }
  free(map);
  return close_out(f, path, err);
}

int tb_write_msh(const char *path, const tb_mesh *m, tb_error *err) {
  if (check(path, m, err)) return -1;
  FILE *f = open_out(path, err);
  if (!f) return -1;
  fprintf(f, "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n%d\n", m->nv);
  put_points(f, m, NULL, NULL);
  fprintf(f, "$EndNodes\n$Elements\n%ld\n", (long)m->ntri + m->ntet);
  for (int i = 0; i < m->ntri; i++)
    fprintf(f, "%d 2 2 1 1 %d %d %d\n", i + 1, m->tri[3 * i] + 1, m->tri[3 * i + 1] + 1,
            m->tri[3 * i + 2] + 1);
  for (int i = 0; i < m->ntet; i++) {
    const int *t = m->tet + 4 * i;
    fprintf(f, "%d 4 2 1 1 %d %d %d %d\n", m->ntri + i + 1, t[0] + 1, t[1] + 1, t[2] + 1, t[3] + 1);
  }
  fputs("$EndElements\n", f);
  return close_out(f, path, err);
}
