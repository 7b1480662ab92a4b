/* Cutting the metaball model (tb_model.h's tb_cut_event; the metaball
 * patent's step 3): BEGIN starts the volume's cut (models/metaball_cut.c),
 * MOVE hands it the blade's folded plane so far, END re-packs the point set
 * into spheres (models/metaball_repack.c), splits and closes the skinned
 * surface with the same folded plane (cutting/cut_surface.c) and skins the
 * new and changed vertices anew on their side of the blade; the model's
 * points, masses and surface are replaced (npoints grows, the surface's
 * version changes). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "metaball_model_priv.h"
#include "tb_meshless.h"
#include "cutting/tb_cut_surface.h"

/* The point set's points within half its support of the folded plane
 * (malloc'ed into *out; their count, or -1): the crack's points (the
 * patent: "the boundary points near the folded plane, projected onto it"). */
static int crack_points(const mb_model *s, tb_vec3 **out) {
  const tb_vec3 *px;
  int np = tb_metaball_cut_points(s->mb, &px), n = 0;
  const tb_meshless *ml = tb_metaball_cut_meshless(s->mb);
  *out = malloc(sizeof(tb_vec3) * (size_t)(np > 0 ? np : 1));
  if (!*out) return -1;
  if (!ml || !s->have_fold) return 0;
  double reach = tb_meshless_support(ml) / 2;
  for (int p = 0; p < np; p++) {
    tb_fold_near nr;
    tb_fold_nearest(&s->fold, px[p], &nr);
    if (nr.dist < reach) (*out)[n++] = px[p];
  }
  return n;
}

/* The rest positions of the cut surface's vertices, consistent with the
 * old surface's: an old vertex keeps its own, a copy its original's; a
 * vertex on an old triangle (a corner of a triangle cut from one) the
 * combination of that triangle's corners' rest positions with its
 * barycentric coordinates now; a vertex inside the crack its current
 * position moved by a displacement harmonic over the surface's edges, the
 * rim's displacements fixed (Gauss-Seidel, to REST_TOL of the largest
 * displacement or REST_SWEEPS sweeps). Inverting each vertex's skin
 * instead (the spheres' rotations blended at the current configuration)
 * puts neighbours out of step where their spheres turn differently: old
 * vertices' rest positions moved by up to 0.28 (the steak's mean edge is
 * 0.18), and pieces relaxed into crumpled, self-intersecting shapes. */
#define REST_SWEEPS 500
#define REST_TOL 1e-9

static int rest_positions(const mb_model *s, const tb_cut_result *cr, tb_vec3 *x0) {
  const tb_metaball *m = s->mb;
  int old = s->nv, nv = cr->nv;
  unsigned char *known = calloc((size_t)nv, 1);
  int *start = calloc((size_t)nv + 1, sizeof(int)),
      *adj = malloc(sizeof(int) * 6 * (size_t)cr->ntri);
  tb_vec3 *d = malloc(sizeof(tb_vec3) * (size_t)nv);
  if (!known || !start || !adj || !d) return free(known), free(start), free(adj), free(d), -1;
  for (int v = 0; v < nv; v++) {
    int o = v < old ? v : cr->origin[v];
    if (o >= 0 && o < old) x0[v] = m->x0[o], known[v] = 1;
  }
  for (int t = 0; t < cr->ntri; t++) {
    int f = cr->tri_from[t];
    if (f < 0) continue;
    const int *T = s->tri + 3 * f;
    tb_vec3 A = s->x[T[0]], B = s->x[T[1]], C = s->x[T[2]];
    tb_vec3 n = tb_cross(tb_sub(B, A), tb_sub(C, A));
    double nn = tb_dot(n, n);
    for (int k = 0; k < 3 && nn > 0; k++) {
      int v = cr->tri[3 * t + k];
      if (known[v]) continue;
      tb_vec3 p = cr->x[v];
      double a = tb_dot(tb_cross(tb_sub(C, B), tb_sub(p, B)), n) / nn;
      double b = tb_dot(tb_cross(tb_sub(A, C), tb_sub(p, C)), n) / nn, c = 1 - a - b;
      x0[v] = tb_add(tb_add(tb_scale(m->x0[T[0]], a), tb_scale(m->x0[T[1]], b)),
                     tb_scale(m->x0[T[2]], c));
      known[v] = 1;
    }
  }
  /* the crack's inside: neighbours by edge, each edge listed from both ends */
  for (int t = 0; t < cr->ntri; t++)
    for (int k = 0; k < 3; k++) start[cr->tri[3 * t + k] + 1] += 2;
  for (int v = 0; v < nv; v++) start[v + 1] += start[v];
  for (int t = 0; t < cr->ntri; t++)
    for (int k = 0; k < 3; k++) {
      int v = cr->tri[3 * t + k];
      adj[start[v]++] = cr->tri[3 * t + (k + 1) % 3],
      adj[start[v]++] = cr->tri[3 * t + (k + 2) % 3];
    }
  for (int v = nv; v > 0; v--) start[v] = start[v - 1];
  start[0] = 0;
  double scale = 0;
  for (int v = 0; v < nv; v++) {
    d[v] = known[v] ? tb_sub(x0[v], cr->x[v]) : tb_v3(0, 0, 0);
    scale = fmax(scale, tb_len(d[v]));
  }
  for (int sweep = 0; sweep < REST_SWEEPS; sweep++) {
    double change = 0;
    for (int v = 0; v < nv; v++) {
      if (known[v] || start[v + 1] == start[v]) continue;
      tb_vec3 sum = tb_v3(0, 0, 0);
      for (int e = start[v]; e < start[v + 1]; e++) sum = tb_add(sum, d[adj[e]]);
      sum = tb_scale(sum, 1.0 / (start[v + 1] - start[v]));
      change = fmax(change, tb_dist(sum, d[v])), d[v] = sum;
    }
    if (!(change > REST_TOL * scale)) break;
  }
  for (int v = 0; v < nv; v++)
    if (!known[v]) x0[v] = tb_add(cr->x[v], d[v]);
  free(known), free(start), free(adj), free(d);
  return 0;
}

/* The blade has left: the surface split and closed by the folded plane
 * (tb_cut_surface; the point set's points near the plane, projected,
 * among the crack's points), then the spheres from the points
 * (tb_metaball_cut_end), the new and changed vertices skinned anew on their
 * side, points, masses and the surface replaced. The surface is cut first:
 * when it cannot be, nothing has changed and the cut is still running. */
static int cut_end(mb_model *s, tb_cut_stats *st, tb_error *err) {
  tb_metaball *m = s->mb;
  tb_metaball_cut_report rep;
  tb_cut_result cr;
  memset(&cr, 0, sizeof cr);
  if (s->have_fold) {
    tb_vec3 *extra;
    int nextra = crack_points(s, &extra);
    if (nextra < 0) return tb_error_set(err, "metaball", 0, "out of memory");
    tb_cut_def def = tb_cut_default_def();
    def.extra = extra, def.nextra = nextra;
    int failed = tb_cut_surface(s->nv, s->x, s->ntri, s->tri, &s->fold, &def, &cr, err);
    free(extra);
    if (failed) return -1;
  }
  int first_new = m->n;
  if (tb_metaball_cut_end(m, &rep, err)) return tb_cut_result_free(&cr), -1;
  if (st)
    st->removed = rep.removed, st->created = rep.created, st->removed_r = rep.removed_r,
    st->created_r = rep.created_r, st->points = rep.points, st->uncovered = rep.uncovered;
  if (!s->have_fold) return 0; /* the blade never moved */
  int rc = 0, old = s->nv;
  signed char *side = malloc((size_t)cr.nv);
  unsigned char *rebind = calloc((size_t)cr.nv, 1);
  tb_vec3 *vel = malloc(sizeof(tb_vec3) * (size_t)cr.nv);
  tb_vec3 *x0 = malloc(sizeof(tb_vec3) * (size_t)cr.nv);
  if (!side || !rebind || !vel || !x0 || rest_positions(s, &cr, x0)) {
    rc = tb_error_set(err, "metaball", 0, "out of memory (cut: %d points)", cr.nv);
    goto done;
  }
  for (int v = 0; v < cr.nv; v++) { /* a copy moves on as its original did */
    int o = cr.origin[v];
    side[v] = (signed char)cr.side[v];
    vel[v] = v < old ? s->v[v] : (o >= 0 && o < old ? s->v[o] : tb_v3(0, 0, 0));
  }
  for (int k = 0; k < cr.nreskin; k++) rebind[cr.reskin[k]] = 1;
  tb_metaball_skin_def sd = {cr.nv, cr.x, vel, side, rebind, cr.ntri, cr.tri, first_new, x0};
  if ((rc = tb_metaball_set_skin(m, &sd, &s->last_skin, err))) goto done;
  if (mb_grow(s, cr.nv, m->n)) {
    rc = tb_error_set(err, "metaball", 0, "out of memory (cut: %d points)", cr.nv);
    goto done;
  }
  memcpy(s->v + old, vel + old, sizeof(tb_vec3) * (size_t)(cr.nv - old));
  s->nv = cr.nv, s->ns = m->n;
  memcpy(s->x, m->x, sizeof(tb_vec3) * (size_t)s->nv);
  if ((rc = mb_share_masses(s, err))) goto done;
  free(s->tri);
  s->tri = cr.tri, s->ntri = cr.ntri, cr.tri = NULL;
  if (cr.cut) s->version++;
  if (st)
    st->split_tris = cr.split_tris, st->crack_tris = cr.crack_tris, st->new_points = cr.nv - old,
    st->components = cr.components_after;
done:
  free(side), free(rebind), free(vel), free(x0);
  tb_cut_result_free(&cr);
  return rc;
}

int mb_cut(void *self, const tb_cut_event *ev, tb_cut_stats *st, tb_error *err) {
  mb_model *s = self;
  tb_metaball *m = s->mb;
  if (ev->kind == TB_CUT_BEGIN) {
    if (s->cutting) return tb_error_set(err, "metaball", 0, "a cut is already running");
    tb_metaball_cut_settings cs;
    tb_metaball_cut_settings_default(&cs);
    cs.per_sphere = s->set.cut_points, cs.E = s->set.cut_E;
    /* the tissue's density, not the spheres' (their volumes overlap several
     * times: 0.13 on the gallbladder, which made the point set 2.8 times
     * stiffer in frequency and its cut frames 33 ms) */
    if (s->set.density > 0 && !(s->set.node_mass > 0)) cs.density = s->set.density;
    if (tb_metaball_cut_begin(m, &cs, err)) return -1;
    s->cutting = 1;
    return 0;
  }
  if (!s->cutting) return tb_error_set(err, "metaball", 0, "no cut is running (BEGIN first)");
  if (ev->kind == TB_CUT_MOVE) {
    tb_fold f;
    if (tb_fold_init(&f, ev->path, ev->npath, ev->depth, err)) return -1;
    if (s->have_fold) tb_fold_free(&s->fold);
    s->fold = f, s->have_fold = 1;
    return tb_metaball_cut_advance(m, &s->fold, err) < 0 ? -1 : 0;
  }
  int rc = cut_end(s, st, err);
  if (rc) return -1; /* the surface unchanged, the cut still running */
  s->cutting = 0;
  if (s->have_fold) tb_fold_free(&s->fold), s->have_fold = 0;
  if (st)
    st->components = st->components ? st->components : tb_cut_components(s->nv, s->ntri, s->tri);
  return rc;
}
