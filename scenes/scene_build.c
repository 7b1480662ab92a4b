/* What a scene description turns into on a mesh: the mesh itself (a file,
 * or a generator with settings), node selections, and rigid motions along
 * keyframes. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "sim_priv.h"
#include "core/tb_mesh_io.h"
#include "meshgen/tb_generators.h"
#include "meshgen/tb_meshgen.h"

/* ---- meshes ---- */

/* The liver for a target number of tet-mesh vertices (thesis: 1206); the
 * surface takes a larger share of a coarse mesh's nodes. */
static int liver_nodes(int nodes, uint64_t seed, const char *path, int line, tb_mesh *out,
                       tb_error *err) {
  tb_liver_def ld = tb_liver_default_def();
  /* the surface gets 725/1206 of the nodes on a coarse mesh, and needs at least 100 */
  int least = (int)ceil(100.0 * ld.tet_verts / ld.surface_verts);
  if (nodes < least || nodes > 100000)
    return tb_error_set(err, path, line,
                        "nodes = %d: the liver needs %d..100000 (its surface takes %d/%d of them "
                        "and needs at least 100)",
                        nodes, least, ld.surface_verts, ld.tet_verts);
  double r = (double)nodes / ld.tet_verts;
  ld.surface_verts = (int)lround(ld.surface_verts * (r < 1 ? r : pow(r, 2.0 / 3.0)));
  ld.tets = nodes == ld.tet_verts ? 0 : -1; /* the thesis's 4230 tets, else any */
  ld.tet_verts = nodes;
  if (seed) ld.seed = seed;
  tb_mesh surf;
  tb_error e2;
  if (tb_liver_surface(&ld, &surf, &e2) || tb_liver_tets(&ld, &surf, out, &e2)) {
    if (surf.nv) tb_mesh_free(&surf);
    return tb_error_set(err, path, line, "the liver with nodes = %d: %s", nodes, e2.msg);
  }
  tb_mesh_free(&surf);
  return 0;
}

static int build(const tb_mesh_source *src, const char *scene_path, const double *param,
                 uint64_t seed, tb_mesh *out, tb_error *err);

/* Places a mesh: x' = R(axis, angle) (scale x) + translate, then with
 * `bottom` moved so its bounding box's bottom centre (smallest z) is there. */
static int place(const tb_mesh_source *src, const char *scene_path, const double *param, tb_mesh *m,
                 tb_error *err) {
  double s = tb_expr_eval(src->scale, param);
  tb_vec3 t = tb_expr_vec(src->translate, param);
  if (!(s > 0)) return tb_error_set(err, scene_path, src->line, "scale must be > 0 (got %g)", s);
  tb_mat3 R;
  if (tb_expr_rotation(src->axis, src->angle, param, &R) < 0)
    return tb_error_set(err, scene_path, src->line, "rotate: the axis must not be zero");
  for (int i = 0; i < m->nv; i++) m->x[i] = tb_add(tb_m3_mulv(R, tb_scale(m->x[i], s)), t);
  if (src->has_bottom && m->nv > 0) { /* bounding box's bottom centre to `bottom` */
    tb_vec3 lo = m->x[0], hi = m->x[0];
    for (int i = 1; i < m->nv; i++) lo = tb_vmin(lo, m->x[i]), hi = tb_vmax(hi, m->x[i]);
    tb_vec3 b = tb_expr_vec(src->bottom, param);
    tb_vec3 d = tb_sub(b, tb_v3(0.5 * (lo.x + hi.x), 0.5 * (lo.y + hi.y), lo.z));
    for (int i = 0; i < m->nv; i++) m->x[i] = tb_add(m->x[i], d);
  }
  return 0;
}

int tb_sim_build_mesh(const tb_mesh_source *src, const char *scene_path, const double *param,
                      uint64_t seed, tb_mesh *out, tb_error *err) {
  if (build(src, scene_path, param, seed, out, err)) return -1;
  if (place(src, scene_path, param, out, err)) return tb_mesh_free(out), -1;
  return 0;
}

static int build(const tb_mesh_source *src, const char *scene_path, const double *param,
                 uint64_t seed, tb_mesh *out, tb_error *err) {
  memset(out, 0, sizeof *out);
  if (src->path[0]) return tb_mesh_read(src->path, out, err);
  if (src->prefer[0]) { /* turned into the scene's frame by prefer_rotate */
    tb_mat3 R;
    int turned = tb_expr_rotation(src->prefer_axis, src->prefer_angle, param, &R);
    if (turned < 0)
      return tb_error_set(err, scene_path, src->line, "prefer_rotate: the axis must not be zero");
    if (tb_mesh_read(src->prefer, out, err)) return -1;
    if (turned)
      for (int i = 0; i < out->nv; i++) out->x[i] = tb_m3_mulv(R, out->x[i]);
    return 0;
  }
  const tb_generator *g = tb_generator_find(src->generator);
  if (!g) return tb_error_set(err, scene_path, src->line, "unknown generator '%s'", src->generator);
  double p[TB_GEN_MAX_PARAMS];
  tb_generator_defaults(g, p);
  int cells = 0, nodes = 0;
  for (int i = 0; i < src->nset; i++) {
    double v = tb_expr_eval(src->setval[i], param);
    if (!strcmp(src->setkey[i], "nodes") || !strcmp(src->setkey[i], "cells")) {
      if (!(v >= 1 && v <= 1e6) || v != floor(v))
        return tb_error_set(err, scene_path, src->line, "%s must be a whole number >= 1 (got %g)",
                            src->setkey[i], v);
      *(src->setkey[i][0] == 'n' ? &nodes : &cells) = (int)v;
      continue;
    }
    for (int k = 0; k < TB_GEN_MAX_PARAMS && g->params[k].key; k++) {
      if (strcmp(g->params[k].key, src->setkey[i])) continue;
      if (g->params[k].integer && v != floor(v))
        return tb_error_set(err, scene_path, src->line, "%s must be a whole number (got %g)",
                            src->setkey[i], v);
      p[k] = v;
    }
  }
  if (!strcmp(g->name, "liver") && (nodes || seed)) {
    if (!nodes) nodes = (int)p[1];
    return liver_nodes(nodes, seed, scene_path, src->line, out, err);
  }
  if (!strcmp(g->name, "beam") && cells) {
    /* cells along x; the cross-section gets cells about as long (at least one a side) */
    if (cells > 400)
      return tb_error_set(err, scene_path, src->line, "cells must be 1..400 (got %d)", cells);
    p[3] = cells;
    p[4] = fmax(1, floor(cells * p[1] / p[0]));
    p[5] = fmax(1, floor(cells * p[2] / p[0]));
    if (p[6] == TB_SPLIT_SYMMETRIC) /* mirror symmetry needs even counts across */
      p[4] = 2 * ceil(p[4] / 2), p[5] = 2 * ceil(p[5] / 2);
  }
  tb_gen_result r;
  tb_error e2;
  if (tb_generator_run(g, p, &r, &e2))
    return tb_error_set(err, scene_path, src->line, "generate = %s: %s", g->name, e2.msg);
  if (r.volume.nv) {
    *out = r.volume;
    memset(&r.volume, 0, sizeof r.volume);
  } else {
    *out = r.surface;
    memset(&r.surface, 0, sizeof r.surface);
  }
  tb_gen_result_free(&r);
  return 0;
}

/* ---- selections ---- */

/* The surface node farthest along dir (the first of equals, in triangle order). */
static int extreme_surface_node(const tb_mesh *m, tb_vec3 dir) {
  int best = m->tri[0];
  for (int k = 0; k < 3 * m->ntri; k++)
    if (tb_dot(m->x[m->tri[k]], dir) > tb_dot(m->x[best], dir)) best = m->tri[k];
  return best;
}

static int picks(const tb_sim *s, const tb_selector *q, tb_vec3 lo, tb_vec3 hi, tb_vec3 patch,
                 double radius, tb_vec3 x) {
  const double *P = s->priv->param;
  double v[6];
  for (int k = 0; k < 6; k++) v[k] = tb_expr_eval(q->v[k], P);
  switch (q->kind) {
    case TB_SEL_BOX:
      return x.x >= v[0] && x.y >= v[1] && x.z >= v[2] && x.x <= v[3] && x.y <= v[4] && x.z <= v[5];
    case TB_SEL_FRACTION:
      for (int a = 0; a < 3; a++) {
        double c = tb_comp(x, a), l = tb_comp(lo, a), e = tb_comp(hi, a) - l;
        if (v[a] > 0 && c < l + v[a] * e) return 0;
        if (v[3 + a] < 1 && c > l + v[3 + a] * e) return 0;
      }
      return 1;
    case TB_SEL_PLANE:
      return tb_dot(tb_sub(x, tb_v3(v[0], v[1], v[2])), tb_v3(v[3], v[4], v[5])) <= 0;
    case TB_SEL_SPHERE:
      return tb_dist(x, tb_v3(v[0], v[1], v[2])) <= v[3];
    case TB_SEL_PATCH:
      return tb_dist(x, patch) < radius;
  }
  return 0;
}

int tb_sim_select_point(const tb_sim *s, const tb_selection *sel, tb_vec3 x) {
  tb_vec3 lo = s->priv->lo, hi = s->priv->hi;
  for (int q = 0; q < sel->n; q++)
    if (sel->sel[q].kind != TB_SEL_IDS && sel->sel[q].kind != TB_SEL_PATCH &&
        picks(s, &sel->sel[q], lo, hi, lo, 0, x))
      return 1;
  return 0;
}

int tb_sim_select(const tb_sim *s, const tb_selection *sel, const char *what, int **out,
                  tb_error *err) {
  const tb_mesh *m = &s->mesh;
  const char *path = s->desc.path[0] ? s->desc.path : s->desc.name;
  char *on = calloc((size_t)(m->nv > 0 ? m->nv : 1), 1);
  *out = malloc(sizeof(int) * (size_t)(m->nv > 0 ? m->nv : 1));
  if (!on || !*out) {
    free(on), free(*out), *out = NULL;
    return tb_error_set(err, path, sel->line, "out of memory");
  }
  tb_vec3 lo, hi;
  tb_mesh_bbox(m, &lo, &hi);
  for (int q = 0; q < sel->n; q++) {
    const tb_selector *e = &sel->sel[q];
    if (e->kind == TB_SEL_IDS) {
      for (int k = 0; k < e->nids; k++) {
        if (e->ids[k] >= m->nv) {
          free(on), free(*out), *out = NULL;
          return tb_error_set(err, path, e->line,
                              "%s: node id %d is out of range (the mesh has %d nodes; ids are "
                              "0-based in the file's node order)",
                              what, e->ids[k], m->nv);
        }
        on[e->ids[k]] = 1;
      }
      continue;
    }
    tb_vec3 patch = lo;
    double radius = 0;
    if (e->kind == TB_SEL_PATCH) {
      if (m->ntri < 1) {
        free(on), free(*out), *out = NULL;
        return tb_error_set(err, path, e->line, "%s: patch needs a surface", what);
      }
      tb_vec3 d =
          tb_v3(tb_expr_eval(e->v[0], s->priv->param), tb_expr_eval(e->v[1], s->priv->param),
                tb_expr_eval(e->v[2], s->priv->param));
      patch = m->x[extreme_surface_node(m, d)];
      radius = tb_expr_eval(e->v[3], s->priv->param) * s->size;
    }
    for (int i = 0; i < m->nv; i++)
      if (!on[i] && (e->kind != TB_SEL_PATCH || s->priv->on_surface[i]) &&
          picks(s, e, lo, hi, patch, radius, m->x[i]))
        on[i] = 1;
  }
  int n = 0;
  for (int i = 0; i < m->nv; i++)
    if (on[i] && (!sel->surface_only || s->priv->on_surface[i])) (*out)[n++] = i;
  free(on);
  if (!n) {
    free(*out), *out = NULL;
    return tb_error_set(err, path, sel->line, "%s selects no node of the mesh (%d nodes)", what,
                        m->nv);
  }
  return n;
}

/* ---- motions ---- */

void tb_sim_motion_free(tb_sim_motion *m) {
  free(m->t), free(m->move), free(m->axis), free(m->angle);
  memset(m, 0, sizeof *m);
}

int tb_sim_motion_make(const tb_motion *m, const double *param, tb_sim_motion *out, tb_error *err) {
  memset(out, 0, sizeof *out);
  int n = m->nkey;
  out->t = malloc(sizeof(double) * (size_t)n);
  out->move = malloc(sizeof(tb_vec3) * (size_t)n);
  out->axis = malloc(sizeof(tb_vec3) * (size_t)n);
  out->angle = malloc(sizeof(double) * (size_t)n);
  if (!out->t || !out->move || !out->axis || !out->angle) {
    tb_sim_motion_free(out);
    return tb_error_set(err, "scene", 0, "out of memory");
  }
  out->nkey = n;
  out->has_direction = m->has_direction;
  if (m->has_direction) {
    tb_vec3 d = tb_expr_vec(m->direction, param);
    if (!(tb_len(d) > 0)) {
      tb_sim_motion_free(out);
      return tb_error_set(err, "scene", n ? m->key[0].line : 0, "direction must not be zero");
    }
    out->direction = tb_normalize(d);
  }
  out->centre = tb_expr_vec(m->centre, param);
  for (int k = 0; k < n; k++) {
    const tb_keyframe *f = &m->key[k];
    out->t[k] = tb_expr_eval(f->t, param);
    out->move[k] = tb_expr_vec(f->move, param);
    tb_vec3 a = tb_expr_vec(f->axis, param);
    out->angle[k] = tb_expr_eval(f->angle, param) * (M_PI / 180.0);
    if (!(tb_len(a) > 0) && out->angle[k] != 0) {
      tb_sim_motion_free(out);
      return tb_error_set(err, "scene", f->line, "keyframe: rotation axis must not be zero");
    }
    out->axis[k] = tb_len(a) > 0 ? tb_normalize(a) : tb_v3(0, 0, 1);
    if (!isfinite(out->t[k]) || (k && !(out->t[k] > out->t[k - 1]))) {
      tb_sim_motion_free(out);
      return tb_error_set(err, "scene", f->line, "keyframe times must increase (got %g after %g)",
                          out->t[k], k ? out->t[k - 1] : 0.0);
    }
  }
  return 0;
}

/* v rotated by angle about unit axis k (Rodrigues). */
static tb_vec3 rotate(tb_vec3 v, tb_vec3 k, double angle) {
  double c = cos(angle), s = sin(angle);
  tb_vec3 kv = tb_cross(k, v);
  return tb_add(tb_add(tb_scale(v, c), tb_scale(kv, s)), tb_scale(k, tb_dot(k, v) * (1 - c)));
}

/* Quaternion (w, x, y, z) of a rotation, and back to axis-angle. */
typedef struct quat {
  double w, x, y, z;
} quat;
static quat quat_of(tb_vec3 axis, double angle) {
  double s = sin(0.5 * angle);
  return (quat){cos(0.5 * angle), axis.x * s, axis.y * s, axis.z * s};
}
static tb_vec3 quat_rotate(quat q, tb_vec3 v) {
  tb_vec3 u = tb_v3(q.x, q.y, q.z);
  tb_vec3 t = tb_scale(tb_cross(u, v), 2);
  return tb_add(tb_add(v, tb_scale(t, q.w)), tb_cross(u, t));
}

tb_vec3 tb_sim_motion_apply(const tb_sim_motion *m, double t, tb_vec3 x) {
  int n = m->nkey, k = 0;
  double u = 0;
  if (t <= m->t[0])
    k = 0, u = 0;
  else if (t >= m->t[n - 1])
    k = n - 1, u = 0;
  else {
    while (k + 1 < n && t > m->t[k + 1]) k++;
    u = (t - m->t[k]) / (m->t[k + 1] - m->t[k]);
  }
  int k1 = u > 0 ? k + 1 : k;
  /* rotation: linear in angle about a shared axis (or when one end has none), else slerp */
  tb_vec3 p = x;
  double a0 = m->angle[k], a1 = m->angle[k1];
  tb_vec3 ax0 = m->axis[k], ax1 = m->axis[k1];
  if (a0 != 0 || a1 != 0) {
    tb_vec3 r = tb_sub(x, m->centre);
    if (a0 == 0) ax0 = ax1;
    if (a1 == 0) ax1 = ax0;
    if (tb_dot(ax0, ax1) > 1 - 1e-12)
      r = rotate(r, ax0, a0 + u * (a1 - a0));
    else {
      quat q0 = quat_of(ax0, a0), q1 = quat_of(ax1, a1);
      double d = q0.w * q1.w + q0.x * q1.x + q0.y * q1.y + q0.z * q1.z;
      if (d < 0) q1 = (quat){-q1.w, -q1.x, -q1.y, -q1.z}, d = -d;
      double th = acos(d > 1 ? 1 : d), w0 = 1 - u, w1 = u;
      if (th > 1e-9) w0 = sin((1 - u) * th) / sin(th), w1 = sin(u * th) / sin(th);
      quat q = {w0 * q0.w + w1 * q1.w, w0 * q0.x + w1 * q1.x, w0 * q0.y + w1 * q1.y,
                w0 * q0.z + w1 * q1.z};
      double l = sqrt(q.w * q.w + q.x * q.x + q.y * q.y + q.z * q.z);
      q.w /= l, q.x /= l, q.y /= l, q.z /= l;
      r = quat_rotate(q, r);
    }
    p = tb_add(m->centre, r);
  }
  if (m->has_direction) {
    double d = m->move[k].x + u * (m->move[k1].x - m->move[k].x);
    return tb_madd(p, d, m->direction);
  }
  tb_vec3 d = tb_add(m->move[k], tb_scale(tb_sub(m->move[k1], m->move[k]), u));
  return tb_add(p, d);
}
