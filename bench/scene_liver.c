/* The liver scenes of thesis §3.5. `liver-stretch`: the liver held along
 * its back (the 15% of its length at lowest x), a surface patch at the far
 * lobe pulled outward by `amplitude` (ramped over the first half of the
 * time before `release`, then held), released at `release`, then left to
 * recover. `liver-press`: the liver resting on its lowest 15%, the grasper
 * (closed jaws, pointing down) pushed `amplitude` into the top of the
 * surface; the composite BVH (collision/) finds the surface triangles the
 * instrument crosses, and their nodes inside the instrument are projected
 * out of it (radially from its axis; a capsule of the shaft's radius stands
 * for the instrument's surface) and held there for the step; a surface
 * triangle the tip has passed into between its nodes is pushed down to the
 * tip. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "sim_priv.h"
#include "tb_meshgen.h"

int tb_sim_liver_mesh(const tb_sim_def *d, tb_mesh *out, tb_error *err) {
  tb_liver_def ld = tb_liver_default_def();
  if (d->nodes < 100 || d->nodes > 100000)
    return tb_error_set(err, "liver", 0, "nodes must be 100..100000 (got %d)", d->nodes);
  double r = (double)d->nodes / ld.tet_verts;
  /* the surface takes a larger share of a coarse mesh's nodes */
  ld.surface_verts = (int)lround(ld.surface_verts * (r < 1 ? r : pow(r, 2.0 / 3.0)));
  ld.tets = d->nodes == ld.tet_verts ? 0 : -1; /* the thesis's 4230 tets, else any */
  ld.tet_verts = d->nodes;
  if (d->seed) ld.seed = d->seed;
  tb_mesh surf;
  if (tb_liver_surface(&ld, &surf, err)) return -1;
  int rc = tb_liver_tets(&ld, &surf, out, err);
  tb_mesh_free(&surf);
  return rc;
}

typedef struct slab {
  int axis;
  double below;
} slab;
static int in_slab(tb_vec3 x, const void *data) {
  const slab *s = data;
  return tb_comp(x, s->axis) < s->below;
}

/* Nodes whose coordinate along axis is in the lowest 15% of the extent. */
static int anchor_slab(tb_sim *s, int axis, tb_error *err) {
  tb_vec3 lo, hi;
  tb_mesh_bbox(&s->mesh, &lo, &hi);
  slab sl = {axis, tb_comp(lo, axis) + 0.15 * (tb_comp(hi, axis) - tb_comp(lo, axis))};
  s->nanchor = tb_sim_select(&s->mesh, in_slab, &sl, &s->anchor);
  if (s->nanchor < 1) return tb_error_set(err, s->scene->name, 0, "no anchored nodes");
  return 0;
}

/* The surface node extreme along dir. */
static int extreme_surface_node(const tb_mesh *m, tb_vec3 dir) {
  int best = m->tri[0];
  for (int k = 0; k < 3 * m->ntri; k++)
    if (tb_dot(m->x[m->tri[k]], dir) > tb_dot(m->x[best], dir)) best = m->tri[k];
  return best;
}

/* ---- liver-stretch ---- */
static int stretch_setup(tb_sim *s, tb_error *err) {
  if (anchor_slab(s, 0, err)) return -1;
  const tb_mesh *m = &s->mesh;
  if (m->ntri < 1) return tb_error_set(err, "liver-stretch", 0, "the mesh has no surface");
  tb_vec3 tip = m->x[extreme_surface_node(m, tb_v3(1, 0, 0))];
  double radius = 0.1 * s->size;
  char *on = calloc((size_t)m->nv, 1);
  s->driven = malloc(sizeof(int) * (size_t)m->nv);
  if (!on || !s->driven) return free(on), tb_error_set(err, "liver-stretch", 0, "out of memory");
  for (int k = 0; k < 3 * m->ntri; k++) on[m->tri[k]] = 1;
  for (int i = 0; i < m->nv; i++)
    if (on[i] && tb_dist(m->x[i], tip) < radius) s->driven[s->ndriven++] = i;
  free(on);
  s->drive = tb_normalize(tb_v3(1, 0, 0.3));
  return 0;
}

static int stretch_inputs(tb_sim *s, double t, tb_error *err) {
  (void)err;
  double f = tb_sim_ramp(s, t);
  if (f < 0) return 0; /* let go */
  for (int k = 0; k < s->ndriven; k++) {
    int i = s->driven[k];
    s->mark[i] = 1, s->target[i] = tb_madd(s->mesh.x[i], f * s->def.amplitude, s->drive);
  }
  return 0;
}

const tb_sim_scene tb_scene_liver_stretch = {
    "liver-stretch",
    "liver held along its back, a far surface patch pulled `amplitude` out, let go at `release`",
    {.dt = 0.01, .duration = 2.0, .amplitude = 2.0, .release = 1.0, .nodes = 1206, .seed = 1},
    tb_sim_liver_mesh,
    stretch_setup,
    stretch_inputs,
};

/* ---- liver-press ---- */
#define GAP 0.2 /* the tool's start above the surface */

static int press_setup(tb_sim *s, tb_error *err) {
  if (anchor_slab(s, 2, err)) return -1;
  tb_instrument_def id = tb_instrument_default_def();
  id.jaw_opening = 0;
  if (tb_instrument(&id, &s->tool, err)) return -1;
  s->contact = calloc((size_t)s->mesh.nv, 1);
  if (!s->contact) return tb_error_set(err, "liver-press", 0, "out of memory");
  /* the tool's lowest point above the top of the surface */
  tb_vec3 top = s->mesh.x[extreme_surface_node(&s->mesh, tb_v3(0, 0, 1))];
  s->tool_tip = tb_v3(top.x, top.y, top.z + GAP);
  s->collider = tb_collider_new("composite", &s->mesh, &s->tool, NULL, NULL, NULL, err);
  return s->collider ? 0 : -1;
}

/* Closest point to p on segment [a, b]. */
static tb_vec3 closest_on_segment(tb_vec3 p, tb_vec3 a, tb_vec3 b) {
  tb_vec3 ab = tb_sub(b, a);
  double u = tb_dot(tb_sub(p, a), ab) / tb_dot(ab, ab);
  return tb_madd(a, u < 0 ? 0 : (u > 1 ? 1 : u), ab);
}

/* Does the vertical line through p cross triangle (a, b, c) (upward-facing
 * or not)? Then *z is the triangle's height there. */
static int above_point(tb_vec3 a, tb_vec3 b, tb_vec3 c, tb_vec3 p, double *z) {
  double d = (b.x - a.x) * (c.y - a.y) - (c.x - a.x) * (b.y - a.y);
  if (fabs(d) < 1e-14) return 0;
  double u = ((b.x - p.x) * (c.y - p.y) - (c.x - p.x) * (b.y - p.y)) / d;
  double v = ((c.x - p.x) * (a.y - p.y) - (a.x - p.x) * (c.y - p.y)) / d;
  double w = 1 - u - v;
  if (u < 0 || v < 0 || w < 0) return 0;
  *z = u * a.z + v * b.z + w * c.z;
  return 1;
}

static int press_inputs(tb_sim *s, double t, tb_error *err) {
  tb_sim_hold_anchor(s);
  tb_instrument_def id = tb_instrument_default_def();
  double press = 0.75 * s->def.duration, f = t < press ? t / press : 1.0;
  tb_vec3 tip = s->tool_tip;
  tip.z -= f * (s->def.amplitude + GAP);
  /* the tool's frame: tip (hinge) at the origin, jaws to -z: lift by the jaw length */
  tb_vec3 origin = tb_v3(tip.x, tip.y, tip.z + id.jaw_length);
  const tb_vec3 *x = tb_model_positions(&s->model);
  if (tb_collider_deform(s->collider, x, 0, err) ||
      tb_collider_pose(s->collider, tb_m3_identity(), origin, err) ||
      tb_collider_query(s->collider, &s->pairs, NULL, err))
    return -1;
  /* candidates: nodes of crossing surface triangles and last step's contacts */
  for (int k = 0; k < s->pairs.n; k++)
    for (int c = 0; c < 3; c++) s->contact[s->mesh.tri[3 * s->pairs.ij[2 * k] + c]] = 1;
  double r = id.radius;
  tb_vec3 a = tb_v3(tip.x, tip.y, tip.z + r), b = tb_madd(origin, id.length, tb_v3(0, 0, 1));
  s->ncontact = 0;
  for (int i = 0; i < s->mesh.nv; i++) {
    if (!s->contact[i]) continue;
    tb_vec3 c = closest_on_segment(x[i], a, b), d = tb_sub(x[i], c);
    double len = tb_len(d);
    s->contact[i] = len < r;
    if (!s->contact[i] || s->mark[i]) continue;
    tb_vec3 n = len > 1e-12 * r ? tb_scale(d, 1.0 / len) : tb_v3(0, 0, -1);
    s->mark[i] = 1, s->target[i] = tb_madd(c, r, n);
    s->ncontact++;
  }
  /* the tip inside a surface triangle (it passed between nodes): the
   * triangle is pushed down to the tip */
  for (int k = 0; k < s->mesh.ntri; k++) {
    const int *v = s->mesh.tri + 3 * k;
    double z;
    if (!above_point(x[v[0]], x[v[1]], x[v[2]], tip, &z) || z <= tip.z || z > tip.z + r) continue;
    for (int c = 0; c < 3; c++) {
      if (s->mark[v[c]] && s->target[v[c]].z <= x[v[c]].z - (z - tip.z)) continue;
      if (!s->mark[v[c]]) s->ncontact++;
      s->mark[v[c]] = 1, s->contact[v[c]] = 1;
      s->target[v[c]] = tb_v3(x[v[c]].x, x[v[c]].y, x[v[c]].z - (z - tip.z));
    }
  }
  return 0;
}

const tb_sim_scene tb_scene_liver_press = {
    "liver-press",
    "liver resting on its lowest 15%, the grasper pushed `amplitude` into its top surface",
    {.dt = 0.01, .duration = 1.5, .amplitude = 1.0, .release = 1.5, .nodes = 1206, .seed = 1},
    tb_sim_liver_mesh,
    press_setup,
    press_inputs,
};
