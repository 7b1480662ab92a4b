/* Cutting the metaball model (tb_model.h's tb_cut_event; the metaball
 * patent's step 3): BEGIN starts the volume's cut (models/metaball_cut.c),
 * MOVE hands it the blade's folded plane so far, END re-packs the point set
 * into spheres (models/metaball_repack.c), splits and closes the skinned
 * surface with the same folded plane (cutting/cut_surface.c) and skins the
 * new and changed vertices anew on their side of the blade; the model's
 * points, masses and surface are replaced (npoints grows, the surface's
 * version changes). */
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
  if (!side || !rebind || !vel) {
    rc = tb_error_set(err, "metaball", 0, "out of memory (cut: %d points)", cr.nv);
    goto done;
  }
  for (int v = 0; v < cr.nv; v++) { /* a copy moves on as its original did */
    int o = cr.origin[v];
    side[v] = (signed char)cr.side[v];
    vel[v] = v < old ? s->v[v] : (o >= 0 && o < old ? s->v[o] : tb_v3(0, 0, 0));
  }
  for (int k = 0; k < cr.nreskin; k++) rebind[cr.reskin[k]] = 1;
  tb_metaball_skin_def sd = {cr.nv, cr.x, vel, side, rebind, cr.ntri, cr.tri, first_new};
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
  free(side), free(rebind), free(vel);
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
