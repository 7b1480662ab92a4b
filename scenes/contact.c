/* Contact of a scene's body with a rigid ground plane and a rigid
 * instrument, for every model through the model interface: after the
 * model's step, nodes found inside an obstacle are moved onto its surface
 * and their velocities corrected (tb_model_correct).
 *
 * Ground: plane (x - p).n >= 0. A node below it is projected onto it; the
 * step's tangential displacement is then limited by Coulomb friction in
 * position form (tb_ground_friction, models/ground.c: static friction
 * decided for the contact as a whole, so a block on a slope of angle a
 * sticks exactly when tan a <= mu_s and otherwise slides with acceleration
 * g (sin a - mu_k cos a)); the normal velocity is reflected with the
 * restitution coefficient. Models whose class says own_ground (the
 * position-based ones) project the ground inside their step instead, with
 * the same friction; for them this file only measures the depth.
 *
 * Instrument: its real closed mesh. The composite BVH (collision/) finds
 * the body's surface triangles crossing the instrument's; their nodes and
 * last step's contacts are tested for inside (winding number of the
 * instrument mesh) and moved to the closest point of its surface (plus a
 * margin), with the normal part of their velocity relative to the
 * instrument removed. Nodes in contact are also prescribed on the
 * instrument's surface during the next step (so quasi-static solvers feel
 * the instrument too). The largest depth of a node inside the instrument
 * (before and after the response) and below the ground is recorded per
 * step. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "meshgen/tb_meshgen.h"
#include "sim_priv.h"

/* ---- geometry ---- */

/* Generalised winding number of a closed mesh at p (1 inside, 0 outside;
 * Van Oosterom & Strackee's solid angle per triangle). */
static double winding(const tb_vec3 *x, const int *tri, int ntri, tb_vec3 p) {
  double sum = 0;
  for (int k = 0; k < ntri; k++) {
    tb_vec3 a = tb_sub(x[tri[3 * k]], p), b = tb_sub(x[tri[3 * k + 1]], p),
            c = tb_sub(x[tri[3 * k + 2]], p);
    double la = tb_len(a), lb = tb_len(b), lc = tb_len(c);
    double num = tb_dot(a, tb_cross(b, c));
    double den = la * lb * lc + tb_dot(a, b) * lc + tb_dot(b, c) * la + tb_dot(c, a) * lb;
    sum += 2 * atan2(num, den);
  }
  return sum / (4 * M_PI);
}

/* Inside the instrument at its current pose: the depth (distance to its
 * surface) and the closest surface point; 0 when outside. */
static int inside_tool(const tb_sim *s, tb_vec3 p, double *depth, tb_vec3 *closest) {
  const tb_mesh *t = &s->priv->tool;
  if (winding(s->priv->tool_x, t->tri, t->ntri, p) < 0.5) return 0;
  double best = INFINITY;
  for (int k = 0; k < t->ntri; k++) {
    const int *v = t->tri + 3 * k;
    tb_vec3 q = tb_closest_on_triangle(p, s->priv->tool_x[v[0]], s->priv->tool_x[v[1]],
                                       s->priv->tool_x[v[2]]);
    double d = tb_dist(p, q);
    if (d < best) best = d, *closest = q;
  }
  *depth = best;
  return 1;
}

/* Where a node inside the instrument goes: the closest point of its
 * surface (plus the margin); where parts of the instrument overlap, that
 * point can lie inside another part, and the node then goes on along the
 * same direction until it is out (doubling steps, then bisection). */
static tb_vec3 way_out(const tb_sim *s, tb_vec3 x, tb_vec3 q, tb_vec3 dir) {
  const tb_mesh *t = &s->priv->tool;
  tb_vec3 p = tb_madd(q, s->priv->tool_margin, dir);
  if (winding(s->priv->tool_x, t->tri, t->ntri, p) < 0.5) return p;
  double lo = tb_dist(x, p), hi = lo, step = 0.01 * s->size;
  for (int k = 0; k < 12; k++) {
    hi += step, step *= 2;
    if (winding(s->priv->tool_x, t->tri, t->ntri, tb_madd(x, hi, dir)) < 0.5) break;
  }
  for (int k = 0; k < 30; k++) {
    double mid = 0.5 * (lo + hi);
    if (winding(s->priv->tool_x, t->tri, t->ntri, tb_madd(x, mid, dir)) < 0.5)
      hi = mid;
    else
      lo = mid;
  }
  return tb_madd(x, hi + s->priv->tool_margin, dir);
}

/* ---- the instrument's pose ---- */

/* The instrument's pose at t: x = R x_local + tr. */
static void pose_at(const tb_sim *s, double t, tb_mat3 *R, tb_vec3 *tr) {
  tb_vec3 o = tb_sim_motion_apply(&s->priv->tool_motion, t, tb_v3(0, 0, 0));
  tb_vec3 ex = tb_sub(tb_sim_motion_apply(&s->priv->tool_motion, t, tb_v3(1, 0, 0)), o);
  tb_vec3 ey = tb_sub(tb_sim_motion_apply(&s->priv->tool_motion, t, tb_v3(0, 1, 0)), o);
  tb_vec3 ez = tb_sub(tb_sim_motion_apply(&s->priv->tool_motion, t, tb_v3(0, 0, 1)), o);
  *R = (tb_mat3){{{ex.x, ey.x, ez.x}, {ex.y, ey.y, ez.y}, {ex.z, ey.z, ez.z}}};
  *tr = tb_add(o, s->priv->tool_origin);
}

void tb_sim_tool_pose(tb_sim *s, double t, tb_mat3 *R, tb_vec3 *tr) {
  pose_at(s, t, R, tr);
  for (int i = 0; i < s->priv->tool.nv; i++)
    s->priv->tool_x[i] = tb_add(tb_m3_mulv(*R, s->priv->tool.x[i]), *tr);
}

/* World velocity of the instrument's material point now (pose s->priv->tool_R,
 * s->priv->tool_t) at world position p: where it was at t - dt, over dt. */
static tb_vec3 tool_velocity(const tb_sim *s, tb_vec3 p) {
  tb_mat3 R0;
  tb_vec3 t0;
  pose_at(s, s->t - s->def.dt, &R0, &t0);
  tb_vec3 local = tb_m3_mulv(tb_m3_transpose(s->priv->tool_R), tb_sub(p, s->priv->tool_t));
  tb_vec3 before = tb_add(tb_m3_mulv(R0, local), t0);
  return tb_scale(tb_sub(p, before), 1.0 / s->def.dt);
}

/* ---- set-up ---- */

/* The composite BVH over the model's current surface (outward triangles,
 * the side a push goes) against the instrument; rebuilt when the model
 * reports a new surface (its version changes: refinement, cutting). */
static int collider_for_surface(tb_sim *s, tb_error *err) {
  tb_surface su = tb_model_surface(&s->model);
  if (su.nv != s->mesh.nv)
    return tb_error_set(err, s->name, 0,
                        "the model's surface has %d points, the scene %d: contact with a model "
                        "whose points change is not supported yet",
                        su.nv, s->mesh.nv);
  tb_collider_free(s->priv->collider);
  s->priv->collider = NULL;
  s->priv->tool_surface = (tb_mesh){su.nv, (tb_vec3 *)su.x, su.ntri, (int *)su.tri, 0, NULL, 0};
  s->priv->surface_version = su.version;
  s->priv->collider =
      tb_collider_new("composite", &s->priv->tool_surface, &s->priv->tool, NULL, NULL, NULL, err);
  return s->priv->collider ? 0 : -1;
}

int tb_sim_contact_setup(tb_sim *s, tb_error *err) {
  const tb_scene_desc *d = &s->desc;
  const double *P = s->priv->param;
  const char *path = d->path[0] ? d->path : d->name;
  if (d->has_ground) { /* ground = 0: the plane is kept for pictures, and does not act */
    const tb_scene_ground *g = &d->ground;
    s->has_ground = s->priv->param[TB_P_GROUND] != 0, s->ground_off = !s->has_ground;
    tb_ground *gr = &s->ground;
    gr->p = tb_expr_vec(g->point, P);
    gr->n = tb_normalize(tb_expr_vec(g->normal, P));
    tb_mat3 R; /* `rotate`: about the origin, as the mesh's */
    int turned = tb_expr_rotation(g->axis, g->angle, P, &R);
    if (turned < 0)
      return tb_error_set(err, path, g->line, "[ground] rotate: the axis must not be zero");
    if (turned) gr->p = tb_m3_mulv(R, gr->p), gr->n = tb_m3_mulv(R, gr->n);
    if (!(tb_len(gr->n) > 0) || !tb_isfinite3(gr->n))
      return tb_error_set(err, path, g->line, "[ground] normal must not be zero");
    gr->mu_s = tb_expr_eval(g->mu_s, P), gr->mu_k = tb_expr_eval(g->mu_k, P);
    gr->restitution = tb_expr_eval(g->restitution, P);
    if (!(gr->mu_s >= 0) || !(gr->mu_k >= 0) || gr->mu_k > gr->mu_s)
      return tb_error_set(err, path, g->line, "[ground] needs 0 <= mu_k <= mu_s (got %g, %g)",
                          gr->mu_k, gr->mu_s);
    if (!(gr->restitution >= 0 && gr->restitution <= 1))
      return tb_error_set(err, path, g->line, "[ground] restitution must be in [0, 1]");
    s->priv->settle = tb_expr_eval(g->settle, P);
    if (!(s->priv->settle >= 0 && s->priv->settle <= 1e3))
      return tb_error_set(err, path, g->line, "[ground] settle must be in [0, 1000] s (got %g)",
                          s->priv->settle);
  }
  if (!d->has_tool) return 0;
  const tb_scene_tool *t = &d->tool;
  s->has_tool = 1;
  if (tb_sim_build_mesh(&t->mesh, path, P, 0, &s->priv->tool, err)) return -1;
  if (s->priv->tool.ntri < 1)
    return tb_error_set(err, path, t->line, "the instrument mesh has no triangles");
  tb_mesh_topo topo = tb_mesh_topology(&s->priv->tool);
  int holes = 0;
  if (!topo.closed && t->close) {
    tb_error e2;
    if (tb_mesh_close(&s->priv->tool, &holes, &e2))
      return tb_error_set(err, path, t->line, "the instrument mesh: %s", e2.msg);
    topo = tb_mesh_topology(&s->priv->tool);
  }
  if (!topo.closed)
    return tb_error_set(
        err, path, t->line,
        "the instrument mesh is not closed (%d boundary edges): inside is undefined "
        "(close = 1 caps its holes, as tissuebench mesh close does)",
        topo.boundary_edges);
  s->priv->tool_x = malloc(sizeof(tb_vec3) * (size_t)s->priv->tool.nv);
  s->priv->contact = calloc((size_t)s->mesh.nv, 1);
  s->priv->slot = malloc(sizeof(int) * (size_t)s->mesh.nv);
  if (!s->priv->tool_x || !s->priv->contact || !s->priv->slot)
    return tb_error_set(err, path, t->line, "out of memory");
  for (int i = 0; i < s->mesh.nv; i++) s->priv->slot[i] = -1;
  tb_vec3 o = tb_expr_vec(t->origin, P);
  if (t->origin_extreme) {
    tb_vec3 dir = o;
    int best = s->mesh.tri[0];
    for (int k = 0; k < 3 * s->mesh.ntri; k++)
      if (tb_dot(s->mesh.x[s->mesh.tri[k]], dir) > tb_dot(s->mesh.x[best], dir))
        best = s->mesh.tri[k];
    o = s->mesh.x[best];
  }
  s->priv->tool_origin = tb_add(o, tb_expr_vec(t->offset, P));
  s->priv->tool_margin = tb_expr_eval(t->margin, P);
  s->priv->tool_friction = tb_expr_eval(t->friction, P);
  if (!(s->priv->tool_margin >= 0) || !(s->priv->tool_friction >= 0))
    return tb_error_set(err, path, t->line, "[instrument] margin and friction must be >= 0");
  if (tb_sim_motion_make(&t->motion, P, &s->priv->tool_motion, err)) return -1;
  return collider_for_surface(s, err);
}

void tb_sim_contact_free(tb_sim *s) {
  tb_collider_free(s->priv->collider);
  tb_pairlist_free(&s->pairs);
  tb_mesh_free(&s->priv->tool);
  tb_sim_motion_free(&s->priv->tool_motion);
  free(s->priv->tool_x), free(s->priv->contact), free(s->priv->slot);
  s->priv->collider = NULL, s->priv->tool_x = NULL, s->priv->contact = NULL, s->priv->slot = NULL;
}

/* ---- after a step ---- */

static void ground(tb_sim *s, int *n) {
  const tb_vec3 *x = tb_model_positions(&s->model), *v = tb_model_velocities(&s->model);
  const tb_ground *g = &s->ground;
  int first = *n;
  for (int i = 0; i < s->mesh.nv; i++) { /* the contacts: each node below put on the plane */
    double h = tb_dot(tb_sub(x[i], g->p), g->n);
    if (h >= 0 || s->mark[i]) continue;
    s->priv->ids_buf[*n] = i, s->priv->xc_buf[*n] = tb_madd(x[i], -h, g->n),
    s->priv->depth_buf[*n] = -h;
    (*n)++;
  }
  tb_ground_friction(g, *n - first, s->priv->ids_buf + first, s->priv->depth_buf + first,
                     s->priv->x_prev, s->mass, s->priv->xc_buf + first, s->priv->keep_buf + first);
  for (int k = first; k < *n; k++) { /* velocity: friction's share, restitution */
    tb_vec3 vi = v[s->priv->ids_buf[k]];
    double vn = tb_dot(vi, g->n);
    tb_vec3 vt = tb_scale(tb_madd(vi, -vn, g->n), s->priv->keep_buf[k]);
    if (vn < 0) vn = -g->restitution * vn;
    s->priv->vc_buf[k] = tb_madd(vt, vn, g->n);
  }
}

/* The instrument's corrections for the body at positions x against the
 * instrument at its current pose, into s->priv->ids_buf/xc_buf/vc_buf from *n
 * (vc_buf: the push direction): nodes inside it go to its surface (plus
 * the margin); a surface triangle it pierces between its nodes (an
 * instrument vertex behind the triangle, over it) is moved behind that
 * vertex, each node by its barycentric share (the vertex-triangle
 * projection of position-based dynamics). *before: the largest depth of a
 * node inside the instrument. */
static int tool_response(tb_sim *s, const tb_vec3 *x, int *n, double *before, tb_error *err) {
  if (tb_model_surface(&s->model).version != s->priv->surface_version &&
      collider_for_surface(s, err))
    return -1;
  const tb_mesh *surf = &s->priv->tool_surface;
  if (tb_collider_deform(s->priv->collider, x, 0, err) ||
      tb_collider_pose(s->priv->collider, s->priv->tool_R, s->priv->tool_t, err) ||
      tb_collider_query(s->priv->collider, &s->pairs, NULL, err))
    return -1;
  for (int k = 0; k < s->pairs.n; k++)
    for (int c = 0; c < 3; c++) s->priv->contact[surf->tri[3 * s->pairs.ij[2 * k] + c]] = 1;
  int first = *n;
  *before = 0;
  for (int i = 0; i < s->mesh.nv; i++) {
    if (!s->priv->contact[i]) continue;
    s->priv->contact[i] = 0;
    double depth;
    tb_vec3 q;
    if (s->mark[i] || !inside_tool(s, x[i], &depth, &q)) continue;
    if (depth > *before) *before = depth;
    tb_vec3 dir = depth > 1e-12 * s->size ? tb_scale(tb_sub(q, x[i]), 1.0 / depth) : tb_v3(0, 0, 1);
    s->priv->slot[i] = *n;
    s->priv->ids_buf[*n] = i, s->priv->xc_buf[*n] = way_out(s, x[i], q, dir),
    s->priv->vc_buf[*n] = dir;
    (*n)++;
  }
  /* pierced triangles (a node put out of the instrument above keeps that place) */
  int pushes = *n;
  double reach = 0.25 * s->size;
  for (int k = 0; k < s->pairs.n; k++) {
    const int *v = surf->tri + 3 * s->pairs.ij[2 * k],
              *w = s->priv->tool.tri + 3 * s->pairs.ij[2 * k + 1];
    tb_vec3 a = x[v[0]], b = x[v[1]], c = x[v[2]];
    tb_vec3 nrm = tb_cross(tb_sub(b, a), tb_sub(c, a));
    double area2 = tb_len(nrm);
    if (!(area2 > 0)) continue;
    nrm = tb_scale(nrm, 1.0 / area2);
    for (int e = 0; e < 3; e++) {
      tb_vec3 p = s->priv->tool_x[w[e]];
      double h = tb_dot(tb_sub(p, a), nrm);
      if (h >= 0 || -h > reach) continue;
      tb_vec3 pp = tb_madd(p, -h, nrm);
      double wa = tb_dot(tb_cross(tb_sub(b, pp), tb_sub(c, pp)), nrm) / area2;
      double wb = tb_dot(tb_cross(tb_sub(c, pp), tb_sub(a, pp)), nrm) / area2, wc = 1 - wa - wb;
      if (wa < 0 || wb < 0 || wc < 0) continue;
      double wt[3] = {wa, wb, wc}, sw = wa * wa + wb * wb + wc * wc;
      double push = h - s->priv->tool_margin; /* < 0: along -nrm */
      for (int q = 0; q < 3; q++) {
        int i = v[q];
        if (s->mark[i]) continue;
        tb_vec3 target = tb_madd(x[i], wt[q] / sw * push, nrm);
        if (s->priv->slot[i] < first) {
          s->priv->slot[i] = *n;
          s->priv->ids_buf[*n] = i, s->priv->xc_buf[*n] = target,
          s->priv->vc_buf[*n] = tb_scale(nrm, -1);
          (*n)++;
        } else if (s->priv->slot[i] >= pushes &&
                   tb_dot(tb_sub(target, s->priv->xc_buf[s->priv->slot[i]]), nrm) < 0)
          s->priv->xc_buf[s->priv->slot[i]] = target; /* the deeper push */
      }
    }
  }
  /* a push that ends inside the instrument goes out of it */
  for (int k = pushes; k < *n; k++) {
    double depth;
    tb_vec3 q;
    if (!inside_tool(s, s->priv->xc_buf[k], &depth, &q)) continue;
    tb_vec3 dir = depth > 1e-12 * s->size ? tb_scale(tb_sub(q, s->priv->xc_buf[k]), 1.0 / depth)
                                          : s->priv->vc_buf[k];
    s->priv->xc_buf[k] = way_out(s, s->priv->xc_buf[k], q, dir);
  }
  for (int k = first; k < *n; k++)
    s->priv->contact[s->priv->ids_buf[k]] = 1, s->priv->slot[s->priv->ids_buf[k]] = -1;
  return 0;
}

/* Before the model's step at t: the instrument at its new pose against
 * the body as it is; the nodes it would hold or push are prescribed there
 * for the step (so every model, quasi-static ones too, feels it). */
int tb_sim_contact_prestep(tb_sim *s, double t, tb_error *err) {
  if (!s->has_tool) return 0;
  tb_sim_tool_pose(s, t, &s->priv->tool_R, &s->priv->tool_t);
  int n = 0;
  double before;
  if (tool_response(s, tb_model_positions(&s->model), &n, &before, err)) return -1;
  for (int k = 0; k < n; k++) {
    int i = s->priv->ids_buf[k];
    s->mark[i] = 1, s->target[i] = s->priv->xc_buf[k];
  }
  s->ncontact = n;
  return 0;
}

/* After the step: what the step itself pushed inside is put back out, the
 * normal part of its velocity relative to the instrument removed. */
static int tool(tb_sim *s, int *n, tb_error *err) {
  tb_sim_tool_pose(s, s->t, &s->priv->tool_R, &s->priv->tool_t);
  const tb_vec3 *x = tb_model_positions(&s->model), *v = tb_model_velocities(&s->model);
  int first = *n;
  double before, after = 0;
  if (tool_response(s, x, n, &before, err)) return -1;
  for (int k = first; k < *n; k++) {
    int i = s->priv->ids_buf[k];
    tb_vec3 dir = s->priv->vc_buf[k], vt = tool_velocity(s, s->priv->xc_buf[k]),
            rel = tb_sub(v[i], vt);
    double vn = tb_dot(rel, dir);
    if (vn < 0) {
      rel = tb_madd(rel, -vn, dir);
      if (s->priv->tool_friction > 0) {
        double lt = tb_len(rel), cut = s->priv->tool_friction * -vn;
        rel = lt > cut ? tb_scale(rel, 1 - cut / lt) : tb_v3(0, 0, 0);
      }
    }
    s->priv->vc_buf[k] = tb_add(vt, rel);
  }
  /* what is left inside after the response */
  for (int k = first; k < *n; k++) {
    double depth;
    tb_vec3 q;
    if (inside_tool(s, s->priv->xc_buf[k], &depth, &q) && depth > after) after = depth;
  }
  s->pen_tool = after;
  if (after > s->pen_tool_max) s->pen_tool_max = after;
  if (before > s->pen_tool_before_max) s->pen_tool_before_max = before;
  return 0;
}

int tb_sim_contact(tb_sim *s, tb_error *err) {
  int n = 0;
  if (s->has_ground && !tb_model_owns_ground(&s->model)) ground(s, &n); /* else done in the step */
  /* a node caught by both keeps the instrument's answer (applied last) */
  if (s->has_tool && tool(s, &n, err)) return -1;
  if (n) tb_model_correct(&s->model, n, s->priv->ids_buf, s->priv->xc_buf, s->priv->vc_buf);
  if (s->has_ground) {
    const tb_vec3 *x = tb_model_positions(&s->model);
    double worst = 0;
    for (int i = 0; i < s->mesh.nv; i++) {
      double h = tb_dot(tb_sub(x[i], s->ground.p), s->ground.n);
      if (-h > worst) worst = -h;
    }
    s->pen_ground = worst;
    if (worst > s->pen_ground_max) s->pen_ground_max = worst;
  }
  return 0;
}

int tb_sim_contact_triangles(const tb_sim *s, int **tri) {
  *tri = NULL;
  if (!s->has_tool || !s->pairs.n) return 0;
  const tb_mesh *surf = &s->priv->tool_surface;
  int *t = malloc(sizeof(int) * 3 * (size_t)s->pairs.n), n = 0;
  if (!t) return -1;
  for (int k = 0; k < s->pairs.n; k++) /* sorted: a triangle's pairs are adjacent */
    if (!k || s->pairs.ij[2 * k] != s->pairs.ij[2 * k - 2])
      memcpy(t + 3 * n++, surf->tri + 3 * s->pairs.ij[2 * k], sizeof(int) * 3);
  *tri = t;
  return n;
}

int tb_sim_instrument(tb_sim *s, tb_mesh *out) {
  memset(out, 0, sizeof *out);
  if (!s->has_tool) return 0;
  tb_mat3 R;
  tb_vec3 t;
  tb_sim_tool_pose(s, s->t, &R, &t);
  out->nv = s->priv->tool.nv, out->x = s->priv->tool_x, out->ntri = s->priv->tool.ntri,
  out->tri = s->priv->tool.tri;
  return 1;
}
