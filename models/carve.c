/* Element-removal cutting of tet models (SOFA's carving, as in its
 * TopologicalChangeManager: the elements a tool touches are removed and
 * the surface is rebuilt from those left), the comparison the metaball
 * patent's table 2 makes against its own hybrid cut.
 *
 * Which tets go. At each MOVE the blade has swept the folded plane from its
 * position at the last MOVE through the path's new points to its position
 * now, with its depth vector (cutting/tb_fold.h). A tet goes when that
 * sheet meets it at the current positions: a face of the tet meets the
 * sheet (tb_fold_triangle, or a face in a piece's plane whose edge touches
 * the piece, tb_fold_segment), or the sheet lies inside the tet (its first
 * point does). Candidates by bounding box.
 *
 * What is left. The surface is the boundary of the tets left (faces of one
 * tet, oriented outward by their rest volume, core/mesh.c); a node left
 * without tets is debris: on no surface, it keeps its mass and moves as a
 * free particle. Volume is lost by construction: the removed tets' share. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "carve_priv.h"
#include "cutting/tb_fold.h"

int tb_carve_init(tb_carve *c, const tb_mesh *mesh, const char *model, tb_error *err) {
  memset(c, 0, sizeof *c);
  c->nv = mesh->nv;
  c->X = malloc(sizeof(tb_vec3) * (size_t)mesh->nv);
  c->mass = calloc((size_t)mesh->nv, sizeof(double));
  c->scratch = malloc(sizeof(int) * 4 * (size_t)mesh->ntet + 1);
  c->alive = malloc((size_t)mesh->ntet + 1);
  if (!c->X || !c->mass || !c->scratch || !c->alive) {
    tb_carve_free(c);
    return tb_error_set(err, model, 0, "out of memory");
  }
  memcpy(c->X, mesh->x, sizeof(tb_vec3) * (size_t)mesh->nv);
  memset(c->alive, 1, (size_t)mesh->ntet);
  c->ntri = tb_mesh_tet_boundary(mesh, &c->tri);
  if (c->ntri < 0) {
    tb_carve_free(c);
    return tb_error_set(err, model, 0, "out of memory");
  }
  return 0;
}

void tb_carve_free(tb_carve *c) {
  free(c->X), free(c->tri), free(c->scratch), free(c->mass), free(c->alive);
  memset(c, 0, sizeof *c);
}

/* The sheet swept since the last MOVE: the blade's last position, the
 * path's points added since, its position now; consecutive points closer
 * than a 1e-12 share of the path's extent merged. Returns the count. */
static int swept(const tb_carve *c, const tb_cut_event *ev, tb_vec3 *q) {
  int n = 0, from = c->have_last ? c->last_n - 1 : 0;
  double scale = 0;
  for (int k = 1; k < ev->npath; k++) scale = fmax(scale, tb_dist(ev->path[k], ev->path[0]));
  double tiny = 1e-12 * fmax(scale, tb_len(ev->depth));
  if (c->have_last) q[n++] = c->last;
  if (from < 0) from = 0;
  for (int k = from; k < ev->npath; k++)
    if (n == 0 || tb_dist(ev->path[k], q[n - 1]) > tiny) q[n++] = ev->path[k];
  return n;
}

/* Does the sheet f meet the closed tet with corners v? */
static int touches(const tb_fold *f, const tb_vec3 v[4]) {
  static const int face[4][3] = {{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}};
  for (int j = 0; j < 4; j++) {
    tb_vec3 tri[3] = {v[face[j][0]], v[face[j][1]], v[face[j][2]]};
    tb_fold_cut cut;
    if (tb_fold_triangle(f, tri, &cut) > 0) return 1;
    if (cut.coplanar)
      for (int k = 0; k < 3; k++)
        if (tb_fold_segment(f, tri[k], tri[(k + 1) % 3], NULL)) return 1;
  }
  /* the sheet inside the tet: its first point on the inner side of every face */
  tb_vec3 p = f->p[0];
  double s = tb_tet_volume(v[0], v[1], v[2], v[3]);
  for (int j = 0; j < 4; j++) {
    tb_vec3 w[4] = {v[0], v[1], v[2], v[3]};
    w[j] = p;
    if (tb_tet_volume(w[0], w[1], w[2], w[3]) * s < 0) return 0;
  }
  return s != 0;
}

int tb_carve_event(tb_carve *c, const tb_cut_event *ev, const tb_vec3 *x, const int *tet, int nt,
                   const unsigned char *alive, unsigned char *hit, tb_error *err) {
  if (ev->kind == TB_CUT_BEGIN) {
    c->have_last = 0, c->removed = 0;
    return 0;
  }
  if (ev->kind == TB_CUT_END) return 0;
  tb_vec3 *q = malloc(sizeof(tb_vec3) * ((size_t)ev->npath + 1));
  if (!q) return tb_error_set(err, "carve", 0, "out of memory");
  int n = swept(c, ev, q), nhit = 0;
  c->have_last = 1, c->last = ev->path[ev->npath - 1], c->last_n = ev->npath;
  tb_fold f;
  tb_error ferr;
  /* one point: the blade has not moved; a sheet along the depth: it only
   * pushed in (tb_fold_init refuses both); nothing swept */
  if (n < 2 || tb_fold_init(&f, q, n, ev->depth, &ferr)) {
    free(q);
    return 0;
  }
  tb_vec3 lo = q[0], hi = q[0];
  for (int k = 0; k < n; k++) {
    tb_vec3 d = tb_add(q[k], ev->depth);
    lo = tb_vmin(tb_vmin(lo, q[k]), d), hi = tb_vmax(tb_vmax(hi, q[k]), d);
  }
  for (int t = 0; t < nt; t++) {
    if (alive && !alive[t]) continue;
    const int *e = tet + 4 * t;
    tb_vec3 v[4] = {x[e[0]], x[e[1]], x[e[2]], x[e[3]]};
    tb_vec3 a = tb_vmin(tb_vmin(v[0], v[1]), tb_vmin(v[2], v[3]));
    tb_vec3 b = tb_vmax(tb_vmax(v[0], v[1]), tb_vmax(v[2], v[3]));
    if (a.x > hi.x || a.y > hi.y || a.z > hi.z || b.x < lo.x || b.y < lo.y || b.z < lo.z) continue;
    if (touches(&f, v)) hit[t] = 1, nhit++;
  }
  tb_fold_free(&f);
  free(q);
  return nhit;
}

int tb_carve_update(tb_carve *c, const int *tet, int nt, const unsigned char *alive, int removed,
                    double density, double node_mass, tb_error *err) {
  int n = 0;
  for (int t = 0; t < nt; t++)
    if (!alive || alive[t]) memcpy(c->scratch + 4 * n++, tet + 4 * t, 4 * sizeof(int));
  if (!(node_mass > 0)) { /* node_mass: every node keeps it; else lumped anew where tets are left */
    for (int k = 0; k < 4 * n; k++) c->mass[c->scratch[k]] = 0;
    for (int t = 0; t < n; t++) {
      const int *e = c->scratch + 4 * t;
      double v = tb_tet_volume(c->X[e[0]], c->X[e[1]], c->X[e[2]], c->X[e[3]]);
      for (int k = 0; k < 4; k++) c->mass[e[k]] += density * v / 4.0;
    }
  }
  tb_mesh view = {.nv = c->nv, .x = c->X, .ntet = n, .tet = c->scratch};
  int *tri = NULL, ntri = tb_mesh_tet_boundary(&view, &tri);
  if (ntri < 0) return tb_error_set(err, "carve", 0, "out of memory");
  free(c->tri);
  c->tri = tri, c->ntri = ntri, c->version++, c->removed += removed;
  return 0;
}

tb_surface tb_carve_surface(const tb_carve *c, const tb_vec3 *x) {
  return (tb_surface){c->nv, c->ntri, x, c->tri, c->version, NULL};
}

void tb_carve_stats(const tb_carve *c, tb_cut_stats *st) {
  memset(st, 0, sizeof *st);
  st->removed = c->removed;
  tb_mesh view = {.nv = c->nv, .x = c->X, .ntri = c->ntri, .tri = c->tri};
  st->components = tb_mesh_topology(&view).components;
}
