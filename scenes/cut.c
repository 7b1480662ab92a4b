/* The scene's scalpels ([cut] and [cut NAME], scenes/README.md): each
 * blade's edge travels its path's points at constant speed from `start`
 * to `stop`, its depth vector fixed; each step while it moves hands the
 * model the path so far (tb_model_cut's MOVE: the points passed, then the
 * blade's position), the step after `stop` ends the cut (END). A model
 * cuts with one blade at a time: blades run in the order of their start
 * times, and one that starts while another is still cutting begins when
 * that one has ended, with the path it has swept by then. After a cut the
 * model has more points (the cut's new surface vertices): the scene's
 * per-point force array grows with them (zero forces), and those at rest
 * inside a [fix] region are held there. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "sim_priv.h"
#include "cutting/tb_fold.h"

/* "[cut]" or "[cut NAME]" of blade b, for messages. */
static const char *blade_name(const tb_sim *s, int b, char *buf, size_t cap) {
  const char *n = s->desc.cut[b].name;
  snprintf(buf, cap, "[cut%s%s]", n[0] ? " " : "", n);
  return buf;
}

/* Resolves and checks blade b of the description. */
static int blade_setup(tb_sim *s, int b, tb_error *err) {
  const tb_scene_cut *d = &s->desc.cut[b];
  tb_sim_blade *bl = &s->priv->blade[b];
  const char *path = s->desc.path[0] ? s->desc.path : s->desc.name;
  char nm[48];
  blade_name(s, b, nm, sizeof nm);
  bl->n = d->npoint, bl->line = d->line;
  bl->path = malloc(sizeof(tb_vec3) * (size_t)bl->n);
  bl->now = malloc(sizeof(tb_vec3) * (size_t)bl->n);
  if (!bl->path || !bl->now) return tb_error_set(err, path, 0, "out of memory");
  for (int i = 0; i < bl->n; i++) bl->path[i] = tb_expr_vec(d->point[i], s->priv->param);
  bl->depth = tb_expr_vec(d->depth, s->priv->param);
  bl->start = tb_expr_eval(d->start, s->priv->param);
  bl->stop = tb_expr_eval(d->stop, s->priv->param);
  if (!(bl->stop > bl->start) || !(bl->start >= 0))
    return tb_error_set(err, path, d->line, "%s: need 0 <= start < stop (start %g, stop %g)", nm,
                        bl->start, bl->stop);
  if (!(tb_len(bl->depth) > 0))
    return tb_error_set(err, path, d->line, "%s: depth must not be zero", nm);
  for (int i = 0; i + 1 < bl->n; i++)
    if (!(tb_dist(bl->path[i], bl->path[i + 1]) > 0))
      return tb_error_set(err, path, d->line, "%s: points %d and %d are the same", nm, i + 1,
                          i + 2);
  /* the whole path as the blade's folded plane: a depth along a segment is
   * an error of the file, found here rather than when the blade gets there */
  tb_fold f;
  tb_error e;
  if (tb_fold_init(&f, bl->path, bl->n, bl->depth, &e)) {
    const char *why = strchr(e.msg, ':');
    return tb_error_set(err, path, d->line, "%s: %s", nm, why ? why + 2 : e.msg);
  }
  tb_fold_free(&f);
  return 0;
}

int tb_sim_cut_setup(tb_sim *s, tb_error *err) {
  const tb_scene_desc *d = &s->desc;
  s->priv->active = -1;
  if (!d->ncut) return 0;
  const char *path = d->path[0] ? d->path : d->name;
  if (!tb_model_can_cut(&s->model)) {
    char can[256] = "";
    for (int i = 0, len = 0; i < tb_model_count && len < (int)sizeof can; i++)
      if (tb_model_classes[i]->cut)
        len += snprintf(can + len, sizeof can - (size_t)len, "%s%s", len ? ", " : "",
                        tb_model_classes[i]->name);
    return tb_error_set(err, path, d->cut[0].line,
                        "[cut]: the %s model cannot be cut (models that can: %s)",
                        s->model.cls->name, can);
  }
  s->priv->blade = calloc((size_t)d->ncut, sizeof *s->priv->blade);
  if (!s->priv->blade) return tb_error_set(err, path, 0, "out of memory");
  s->priv->nblade = d->ncut;
  for (int b = 0; b < d->ncut; b++)
    if (blade_setup(s, b, err)) return -1;
  return 0;
}

/* Blade bl's path so far at time t into bl->now; returns its point count. */
static int path_at(tb_sim_blade *bl, double t) {
  double total = 0;
  for (int i = 0; i + 1 < bl->n; i++) total += tb_dist(bl->path[i], bl->path[i + 1]);
  double u = (t - bl->start) / (bl->stop - bl->start);
  double left = (u < 0 ? 0 : u > 1 ? 1 : u) * total;
  int n = 0;
  bl->now[n++] = bl->path[0];
  for (int i = 0; i + 1 < bl->n; i++) {
    double len = tb_dist(bl->path[i], bl->path[i + 1]);
    if (left >= len) {
      bl->now[n++] = bl->path[i + 1], left -= len;
      continue;
    }
    if (left > 1e-9 * len) /* the blade inside segment i */
      bl->now[n++] =
          tb_add(bl->path[i], tb_scale(tb_sub(bl->path[i + 1], bl->path[i]), left / len));
    break;
  }
  return n;
}

/* The next blade to begin at time t: the earliest start among those not
 * begun (ties: the file's order), or -1. */
static int next_blade(const tb_sim *s, double t) {
  int best = -1;
  for (int b = 0; b < s->priv->nblade; b++) {
    const tb_sim_blade *bl = &s->priv->blade[b];
    if (bl->state == 0 && bl->start <= t && (best < 0 || bl->start < s->priv->blade[best].start))
      best = b;
  }
  return best;
}

int tb_sim_cut_before(tb_sim *s, double t, tb_error *err) {
  tb_sim_priv *p = s->priv;
  if (p->active < 0) {
    int b = next_blade(s, t);
    if (b < 0) return 0;
    tb_cut_event ev = {TB_CUT_BEGIN, 0, NULL, p->blade[b].depth};
    if (tb_model_cut(&s->model, &ev, NULL, err)) return -1;
    p->blade[b].state = 1, p->active = b;
  }
  tb_sim_blade *bl = &p->blade[p->active];
  int n = path_at(bl, t);
  if (n < 2 || (n == bl->last_n && !memcmp(&bl->now[n - 1], &bl->last, sizeof bl->last))) return 0;
  bl->last_n = n, bl->last = bl->now[n - 1];
  tb_cut_event ev = {TB_CUT_MOVE, n, bl->now, bl->depth};
  return tb_model_cut(&s->model, &ev, NULL, err);
}

/* The new points [from, to) a cut made inside a [fix] region, held where
 * the cut left them (between the region's held nodes, which have not
 * moved): a clamp holds the material in it, the cut's faces too. */
static int hold_new(tb_sim *s, int from, int to, tb_error *err) {
  tb_sim_priv *p = s->priv;
  tb_surface su = tb_model_surface(&s->model);
  if (su.nv < to || !s->desc.nfix) return 0;
  int cap = s->mesh.nv + p->nheld_new + (to - from);
  int *ids = realloc(p->held_new, sizeof(int) * (size_t)(p->nheld_new + to - from));
  if (ids) p->held_new = ids;
  tb_vec3 *at = realloc(p->held_new_x, sizeof(tb_vec3) * (size_t)(p->nheld_new + to - from));
  if (at) p->held_new_x = at;
  int *fx = realloc(s->fixed, sizeof(int) * (size_t)cap);
  if (fx) s->fixed = fx;
  tb_vec3 *fxx = realloc(s->fixed_x, sizeof(tb_vec3) * (size_t)cap);
  if (fxx) s->fixed_x = fxx;
  if (!ids || !at || !fx || !fxx) return tb_error_set(err, "scene", 0, "out of memory");
  for (int i = from; i < to; i++)
    for (int k = 0; k < s->desc.nfix; k++)
      if (tb_sim_select_point(s, &s->desc.fix[k], su.x[i])) {
        p->held_new[p->nheld_new] = i, p->held_new_x[p->nheld_new++] = su.x[i];
        break;
      }
  return 0;
}

int tb_sim_cut_after(tb_sim *s, double t, tb_error *err) {
  tb_sim_priv *p = s->priv;
  if (p->active < 0 || t < p->blade[p->active].stop) return 0;
  tb_sim_blade *bl = &p->blade[p->active];
  tb_cut_event ev = {TB_CUT_END, 0, NULL, bl->depth};
  if (tb_model_cut(&s->model, &ev, &bl->stats, err)) return -1;
  bl->state = 2, p->active = -1;
  p->cut_stats = bl->stats;
  int np = tb_model_npoints(&s->model);
  int had = p->nforce_points > s->mesh.nv ? p->nforce_points : s->mesh.nv;
  if (np > had) { /* forces for the new points: none */
    tb_vec3 *f = realloc(s->force, sizeof(tb_vec3) * (size_t)np);
    if (!f) return tb_error_set(err, s->model.cls->name, 0, "out of memory");
    memset(f + had, 0, sizeof(tb_vec3) * (size_t)(np - had));
    s->force = f, p->nforce_points = np;
    return hold_new(s, had, np, err);
  }
  return 0;
}

void tb_sim_cut_free(tb_sim *s) {
  for (int b = 0; s->priv->blade && b < s->priv->nblade; b++)
    free(s->priv->blade[b].path), free(s->priv->blade[b].now);
  free(s->priv->blade);
  s->priv->blade = NULL, s->priv->nblade = 0;
}
