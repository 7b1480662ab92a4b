/* Scene files: INI (libinih) into a tb_scene_desc. inih reads the file
 * through our line reader, which counts lines, so every error names the
 * line of the key it is about. The format is documented in
 * scenes/README.md. */
#include <errno.h>
#include <ini.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "scene_priv.h"
#include "core/tb_parse.h"
#include "meshgen/tb_generators.h"
#include "models/tb_model.h"

const char *const tb_scene_param_names[TB_P_COUNT] = {
    "dt",        "duration", "amplitude",     "release",      "nodes",      "gravity", "vmax",
    "inversion", "drag",     "energy_factor", "energy_every", "rest_speed", "ground"};

int tb_scene_param_index(const char *name) {
  for (int i = 0; i < TB_P_COUNT; i++)
    if (!strcmp(tb_scene_param_names[i], name)) return i;
  return -1;
}

static void mesh_source_init(tb_mesh_source *m) {
  m->scale = (tb_expr){1, -1};
  for (int i = 0; i < 3; i++) m->axis[i] = m->translate[i] = m->prefer_axis[i] = (tb_expr){0, -1};
  m->axis[2].k = 1;
  m->angle = m->prefer_angle = (tb_expr){0, -1};
}

void tb_scene_desc_init(tb_scene_desc *d) {
  memset(d, 0, sizeof *d);
  mesh_source_init(&d->mesh);
  mesh_source_init(&d->tool.mesh);
  d->param[TB_P_DT] = 0.01;
  d->param[TB_P_DURATION] = 1.0;
  d->param[TB_P_RELEASE] = INFINITY;
  d->param[TB_P_ENERGY_FACTOR] = 100;
  d->param[TB_P_ENERGY_EVERY] = 16;
  d->param[TB_P_REST_SPEED] = 1e-3;
  d->param[TB_P_GROUND] = 1;
  d->gravity_dir = tb_v3(0, 0, -1);
  d->seed = 1;
}

static void selection_free(tb_selection *s) {
  for (int i = 0; i < s->n; i++) free(s->sel[i].ids);
  free(s->sel);
  memset(s, 0, sizeof *s);
}

void tb_scene_desc_free(tb_scene_desc *d) {
  for (int i = 0; i < d->nfix; i++) selection_free(&d->fix[i]);
  selection_free(&d->probe);
  for (int i = 0; i < d->nforce; i++) selection_free(&d->force[i].where);
  for (int i = 0; i < d->nmove; i++) {
    selection_free(&d->move[i].where);
    free(d->move[i].motion.key);
  }
  free(d->tool.motion.key);
  memset(d, 0, sizeof *d);
}

/* ---- the handler's state ---- */
typedef struct parser {
  tb_scene_desc *d;
  FILE *f;
  long line; /* the line inih handed us last */
  char dir[1024];
  tb_error *err;
  int failed;
  /* the item a section adds to: its section text and kind */
  char section[96];
  void *item;
  /* keys seen in this section (for "given twice"); repeatable keys are not listed */
  char seen[48][32];
  int nseen;
} parser;

static char *reader(char *str, int num, void *stream) {
  parser *p = stream;
  char *r = fgets(str, num, p->f);
  if (r && (strchr(r, '\n') || feof(p->f))) p->line++;
  return r;
}

static int fail(parser *p, const char *fmt, const char *a, const char *b) {
  if (!p->failed) {
    char msg[400];
    snprintf(msg, sizeof msg, fmt, a, b);
    tb_error_set(p->err, p->d->path, p->line, "%s", msg);
  }
  p->failed = 1;
  return 0;
}

/* ---- selectors ---- */
static int add_selector(parser *p, tb_selection *s, const char *key, const char *value) {
  static const char *const keys[] = {"ids",   "id_file", "box",  "box_fraction",
                                     "plane", "sphere",  "patch"};
  static const int kinds[] = {TB_SEL_IDS,   TB_SEL_IDS,    TB_SEL_BOX,  TB_SEL_FRACTION,
                              TB_SEL_PLANE, TB_SEL_SPHERE, TB_SEL_PATCH};
  for (int k = 0; k < 7; k++) {
    if (strcmp(key, keys[k])) continue;
    tb_selector *g = realloc(s->sel, sizeof *g * (size_t)(s->n + 1));
    if (!g) return fail(p, "out of memory%s%s", "", "");
    s->sel = g;
    if (!s->line) s->line = (int)p->line;
    if (tb_selector_parse(&s->sel[s->n], kinds[k], value, p->d->path, (int)p->line,
                          k == 1 ? p->dir : NULL, p->err))
      return p->failed = 1, 0;
    s->n++;
    return 1;
  }
  if (!strcmp(key, "surface")) {
    if (strcmp(value, "0") && strcmp(value, "1"))
      return fail(p, "surface: '%s' is not 0 or 1%s", value, "");
    s->surface_only = value[0] == '1';
    return 1;
  }
  return -1; /* not a selector key */
}

/* ---- keyframes ---- */
static int add_keyframe(parser *p, tb_motion *m, const char *value) {
  tb_expr e[8];
  int n = tb_scene_parse_list(value, e, 2, 8);
  int want_dist = m->has_direction;
  if (!(n == 2 && want_dist) && !(n == 4 && !want_dist) && !(n == 5 && want_dist) && n != 8 &&
      !(n == 6 && want_dist))
    return fail(p,
                "keyframe '%s': expected t, dx,dy,dz [, ax,ay,az, degrees] (or t, distance [, "
                "ax,ay,az, degrees] after `direction`)%s",
                value, "");
  tb_keyframe *g = realloc(m->key, sizeof *g * (size_t)(m->nkey + 1));
  if (!g) return fail(p, "out of memory%s%s", "", "");
  m->key = g;
  tb_keyframe *k = &m->key[m->nkey++];
  memset(k, 0, sizeof *k);
  k->line = (int)p->line;
  k->t = e[0];
  int nmove = want_dist ? 1 : 3;
  for (int i = 0; i < 3; i++) k->move[i] = (tb_expr){0, -1}, k->axis[i] = (tb_expr){0, -1};
  k->axis[2].k = 1;
  k->angle = (tb_expr){0, -1};
  if (n < 1 + nmove) return fail(p, "keyframe '%s': too few numbers%s", value, "");
  for (int i = 0; i < nmove; i++) k->move[i] = e[1 + i];
  if (n == 1 + nmove + 4) {
    for (int i = 0; i < 3; i++) k->axis[i] = e[1 + nmove + i];
    k->angle = e[1 + nmove + 3];
  } else if (n != 1 + nmove)
    return fail(p, "keyframe '%s': a rotation needs ax,ay,az, degrees%s", value, "");
  if (m->nkey > 1 && k->t.param < 0 && m->key[m->nkey - 2].t.param < 0 &&
      !(k->t.k > m->key[m->nkey - 2].t.k))
    return fail(p, "keyframe '%s': times must increase%s", value, "");
  return 1;
}

static int motion_key(parser *p, tb_motion *m, const char *key, const char *value) {
  if (!strcmp(key, "keyframe")) return add_keyframe(p, m, value);
  if (!strcmp(key, "direction")) {
    if (m->nkey) return fail(p, "direction must come before the keyframes%s%s", "", "");
    if (tb_scene_parse_list(value, m->direction, 3, 3) < 0)
      return fail(p, "direction: '%s' is not dx,dy,dz%s", value, "");
    m->has_direction = 1;
    return 1;
  }
  if (!strcmp(key, "centre") || !strcmp(key, "center")) {
    if (tb_scene_parse_list(value, m->centre, 3, 3) < 0)
      return fail(p, "%s: '%s' is not x,y,z", key, value);
    return 1;
  }
  return -1;
}

/* ---- meshes ---- */

/* `rotate`-like keys: "ax,ay,az, degrees" into axis and angle. */
static int rotate_key(parser *p, const char *key, const char *value, tb_expr axis[3],
                      tb_expr *angle) {
  tb_expr e[4];
  if (tb_scene_parse_list(value, e, 4, 4) < 0)
    return fail(p, "%s: '%s' is not ax,ay,az, degrees", key, value);
  for (int i = 0; i < 3; i++) axis[i] = e[i];
  *angle = e[3];
  return 1;
}

static int mesh_key(parser *p, tb_mesh_source *m, const char *key, const char *value) {
  if (!m->line) m->line = (int)p->line;
  if (!strcmp(key, "scale")) {
    if (tb_scene_parse_expr(value, &m->scale))
      return fail(p, "scale: '%s' is not a number%s", value, "");
    return 1;
  }
  if (!strcmp(key, "translate")) {
    if (tb_scene_parse_list(value, m->translate, 3, 3) < 0)
      return fail(p, "translate: '%s' is not x,y,z%s", value, "");
    return 1;
  }
  if (!strcmp(key, "rotate")) return rotate_key(p, key, value, m->axis, &m->angle);
  if (!strcmp(key, "prefer_rotate"))
    return rotate_key(p, key, value, m->prefer_axis, &m->prefer_angle);
  if (!strcmp(key, "bottom")) {
    if (tb_scene_parse_list(value, m->bottom, 3, 3) < 0)
      return fail(p, "bottom: '%s' is not x,y,z%s", value, "");
    m->has_bottom = 1;
    return 1;
  }
  if (!strcmp(key, "prefer")) { /* unreadable (e.g. no ../shared/data): the generator is used */
    const char *why;
    if (tb_scene_resolve_path(p->dir, value, m->prefer, sizeof m->prefer, &why)) m->prefer[0] = 0;
    return 1;
  }
  if (!strcmp(key, "file")) {
    if (m->generator[0]) return fail(p, "give either file or generate, not both%s%s", "", "");
    const char *why;
    if (tb_scene_resolve_path(p->dir, value, m->path, sizeof m->path, &why))
      return fail(p, "mesh file '%s': %s", value, why);
    return 1;
  }
  if (!strcmp(key, "generate")) {
    if (m->path[0]) return fail(p, "give either file or generate, not both%s%s", "", "");
    if (!tb_generator_find(value) || strlen(value) >= sizeof m->generator)
      return fail(p, "generate: unknown generator '%s' (liver, instrument, sphere, beam)%s", value,
                  "");
    strcpy(m->generator, value);
    return 1;
  }
  if (!m->generator[0]) return -1;
  /* generator settings, plus the scene shorthands `nodes` (liver) and `cells` (beam) */
  const tb_generator *g = tb_generator_find(m->generator);
  int known = (!strcmp(m->generator, "liver") && !strcmp(key, "nodes")) ||
              (!strcmp(m->generator, "beam") && !strcmp(key, "cells"));
  for (int k = 0; !known && k < TB_GEN_MAX_PARAMS && g->params[k].key; k++)
    known = !strcmp(g->params[k].key, key);
  if (!known) return -1;
  if (m->nset == 12 || strlen(key) >= sizeof m->setkey[0])
    return fail(p, "too many mesh settings%s%s", "", "");
  const char *const *names = NULL;
  for (int k = 0; k < TB_GEN_MAX_PARAMS && g->params[k].key; k++)
    if (!strcmp(g->params[k].key, key)) names = g->params[k].names;
  int pick = -1;
  for (int k = 0; names && names[k]; k++)
    if (!strcmp(names[k], value)) pick = k;
  if (pick >= 0)
    m->setval[m->nset] = (tb_expr){pick, -1};
  else if (tb_scene_parse_expr(value, &m->setval[m->nset]))
    return fail(p, "%s: '%s' is not a number or scene parameter", key, value);
  strcpy(m->setkey[m->nset++], key);
  return 1;
}

/* ---- sections ---- */
static int scene_key(parser *p, const char *key, const char *value) {
  tb_scene_desc *d = p->d;
  if (!strcmp(key, "name")) return snprintf(d->name, sizeof d->name, "%s", value), 1;
  if (!strcmp(key, "summary")) return snprintf(d->summary, sizeof d->summary, "%s", value), 1;
  if (!strcmp(key, "gravity_direction")) {
    tb_expr e[3];
    if (tb_scene_parse_list(value, e, 3, 3) < 0 || e[0].param >= 0 || e[1].param >= 0 ||
        e[2].param >= 0)
      return fail(p, "gravity_direction: '%s' is not three numbers%s", value, "");
    tb_vec3 g = tb_v3(e[0].k, e[1].k, e[2].k);
    if (!(tb_len(g) > 0)) return fail(p, "gravity_direction must not be zero%s%s", "", "");
    d->gravity_dir = tb_scale(g, 1.0 / tb_len(g));
    return 1;
  }
  if (!strcmp(key, "seed")) {
    char *end;
    errno = 0;
    unsigned long long s = strtoull(value, &end, 10);
    if (!*value || *end || errno || value[0] == '-')
      return fail(p, "seed: '%s' is not a whole number >= 0%s", value, "");
    d->seed = s;
    return 1;
  }
  int i = tb_scene_param_index(key);
  if (i < 0) return -1;
  char *end;
  errno = 0;
  double v = strtod(value, &end);
  if (!*value || *end || errno || !isfinite(v) || v < 0)
    return fail(p, "%s: '%s' is not a finite number >= 0", key, value);
  d->param[i] = v, d->param_given[i] = 1;
  return 1;
}

static int model_key(parser *p, const char *key, const char *value) {
  tb_scene_desc *d = p->d;
  if (!strcmp(key, "name")) return snprintf(d->model, sizeof d->model, "%s", value), 1;
  if (d->nmodel_set == TB_SCENE_MAX_SETTINGS) return fail(p, "too many model settings%s%s", "", "");
  char path[TB_SETTING_TEXT_MAX];
  const char *why;
  if (tb_model_file_setting(key)) { /* a file: relative to the scene, or data: */
    if (tb_scene_resolve_path(p->dir, value, path, sizeof path, &why))
      return fail(p, "%s: %s", key, why);
    value = path;
  }
  if (snprintf(d->model_set[d->nmodel_set], sizeof d->model_set[0], "%s=%s", key, value) >=
      (int)sizeof d->model_set[0])
    return fail(p, "setting too long: %s%s", key, "");
  d->model_set_line[d->nmodel_set++] = (int)p->line;
  return 1;
}

static int force_key(parser *p, tb_scene_force *f, const char *key, const char *value) {
  if (!strcmp(key, "total") || !strcmp(key, "each")) {
    if (tb_scene_parse_list(value, f->value, 3, 3) < 0)
      return fail(p, "%s: '%s' is not fx,fy,fz", key, value);
    f->per_node = key[0] == 'e', f->has_value = 1;
    return 1;
  }
  if (!strcmp(key, "start") || !strcmp(key, "stop")) {
    if (tb_scene_parse_expr(value, key[2] == 'a' ? &f->start : &f->stop))
      return fail(p, "%s: '%s' is not a time", key, value);
    return 1;
  }
  return -1;
}

static int ground_key(parser *p, tb_scene_ground *g, const char *key, const char *value) {
  if (!strcmp(key, "point") || !strcmp(key, "normal")) {
    if (tb_scene_parse_list(value, key[0] == 'p' ? g->point : g->normal, 3, 3) < 0)
      return fail(p, "%s: '%s' is not x,y,z", key, value);
    return 1;
  }
  if (!strcmp(key, "rotate")) return rotate_key(p, key, value, g->axis, &g->angle);
  tb_expr *e = !strcmp(key, "mu_s")          ? &g->mu_s
               : !strcmp(key, "mu_k")        ? &g->mu_k
               : !strcmp(key, "restitution") ? &g->restitution
               : !strcmp(key, "settle")      ? &g->settle
                                             : NULL;
  if (!e) return -1;
  if (tb_scene_parse_expr(value, e)) return fail(p, "%s: '%s' is not a number", key, value);
  return 1;
}

static int tool_key(parser *p, tb_scene_tool *t, const char *key, const char *value) {
  int r = motion_key(p, &t->motion, key, value);
  if (r >= 0) return r;
  if (!strcmp(key, "origin")) {
    const char *v = value;
    if (!strncmp(v, "extreme ", 8)) t->origin_extreme = 1, v += 8;
    if (tb_scene_parse_list(v, t->origin, 3, 3) < 0)
      return fail(p, "origin: '%s' is not x,y,z or 'extreme dx,dy,dz'%s", value, "");
    return 1;
  }
  if (!strcmp(key, "offset")) {
    if (tb_scene_parse_list(value, t->offset, 3, 3) < 0)
      return fail(p, "offset: '%s' is not x,y,z%s", value, "");
    return 1;
  }
  if (!strcmp(key, "margin") || !strcmp(key, "friction")) {
    if (tb_scene_parse_expr(value, key[0] == 'm' ? &t->margin : &t->friction))
      return fail(p, "%s: '%s' is not a number", key, value);
    return 1;
  }
  if (!strcmp(key, "close")) {
    if (strcmp(value, "0") && strcmp(value, "1"))
      return fail(p, "close: '%s' is not 0 or 1%s", value, "");
    t->close = value[0] == '1';
    return 1;
  }
  return mesh_key(p, &t->mesh, key, value);
}

static int cut_key(parser *p, tb_scene_cut *c, const char *key, const char *value) {
  if (!strcmp(key, "point")) {
    if (c->npoint == TB_SCENE_MAX_ITEMS)
      return fail(p, "point: more than %s path points%s", "16", "");
    if (tb_scene_parse_list(value, c->point[c->npoint], 3, 3) < 0)
      return fail(p, "point: '%s' is not x,y,z%s", value, "");
    c->npoint++;
    return 1;
  }
  if (!strcmp(key, "depth")) {
    if (tb_scene_parse_list(value, c->depth, 3, 3) < 0)
      return fail(p, "depth: '%s' is not dx,dy,dz%s", value, "");
    return 1;
  }
  if (!strcmp(key, "start") || !strcmp(key, "stop")) {
    if (tb_scene_parse_expr(value, key[2] == 'a' ? &c->start : &c->stop))
      return fail(p, "%s: '%s' is not a time", key, value);
    return 1;
  }
  return -1;
}

/* The [cut] or [cut NAME] section being read: a new scalpel at its first
 * key (a section of the same name again, not next to it, is another). */
static tb_scene_cut *cut_item(parser *p, const char *section) {
  tb_scene_desc *d = p->d;
  if (!strcmp(p->section, section) && p->item) return p->item;
  if (d->ncut == TB_SCENE_MAX_CUTS) return fail(p, "more than %s [cut] sections%s", "8", ""), NULL;
  tb_scene_cut *c = &d->cut[d->ncut++];
  memset(c, 0, sizeof *c);
  c->line = (int)p->line;
  snprintf(c->name, sizeof c->name, "%s", section[3] ? section + 4 : "");
  c->start = (tb_expr){0, -1}, c->stop = (tb_expr){-1, -1};
  for (int i = 0; i < 3; i++) c->depth[i] = (tb_expr){0, -1};
  p->item = c;
  return c;
}

/* Items of repeatable sections ([fix], [fix back], [force tip], ...). */
static void *section_item(parser *p, const char *kind, const char *section) {
  tb_scene_desc *d = p->d;
  if (!strcmp(p->section, section) && p->item) return p->item;
  int *n = !strcmp(kind, "fix") ? &d->nfix : !strcmp(kind, "force") ? &d->nforce : &d->nmove;
  if (*n == TB_SCENE_MAX_ITEMS) return fail(p, "too many [%s] sections%s", kind, ""), NULL;
  void *item = !strcmp(kind, "fix")     ? (void *)&d->fix[*n]
               : !strcmp(kind, "force") ? (void *)&d->force[*n]
                                        : (void *)&d->move[*n];
  if (!strcmp(kind, "force")) {
    tb_scene_force *f = item;
    f->start = (tb_expr){0, -1}, f->stop = (tb_expr){-1, -1};
  }
  (*n)++;
  return item;
}

static int repeatable(const char *section, const char *key) {
  return !strcmp(key, "keyframe") || (!strncmp(section, "cut", 3) && !strcmp(key, "point")) ||
         (strncmp(section, "scene", 5) && strncmp(section, "model", 5) &&
          strncmp(section, "mesh", 4) &&
          (!strcmp(key, "ids") || !strcmp(key, "box") || !strcmp(key, "box_fraction") ||
           !strcmp(key, "plane") || !strcmp(key, "sphere") || !strcmp(key, "patch") ||
           !strcmp(key, "id_file")));
}

static int handler(void *user, const char *section, const char *key, const char *value) {
  parser *p = user;
  if (p->failed) return 0;
  if (strcmp(p->section, section)) {
    snprintf(p->section, sizeof p->section, "%s", section);
    p->item = NULL, p->nseen = 0;
  }
  if (!repeatable(section, key)) {
    for (int i = 0; i < p->nseen; i++)
      if (!strcmp(p->seen[i], key)) return fail(p, "'%s' given twice in [%s]", key, section);
    if (p->nseen < 48) snprintf(p->seen[p->nseen++], sizeof p->seen[0], "%s", key);
  }
  char kind[16];
  size_t kl = strcspn(section, " \t");
  snprintf(kind, sizeof kind, "%.*s", (int)(kl < 15 ? kl : 15), section);
  int r = -2;
  tb_scene_desc *d = p->d;
  if (!strcmp(section, "scene"))
    r = scene_key(p, key, value);
  else if (!strcmp(section, "mesh"))
    r = mesh_key(p, &d->mesh, key, value);
  else if (!strcmp(section, "model"))
    r = model_key(p, key, value);
  else if (!strcmp(section, "ground")) {
    if (!d->has_ground) {
      d->has_ground = 1, d->ground.line = (int)p->line;
      d->ground.normal[2] = (tb_expr){1, -1};
      d->ground.normal[0] = d->ground.normal[1] = (tb_expr){0, -1};
      for (int i = 0; i < 3; i++) d->ground.point[i] = (tb_expr){0, -1};
      d->ground.mu_s = d->ground.mu_k = d->ground.restitution = (tb_expr){0, -1};
      d->ground.settle = (tb_expr){0, -1};
      d->ground.axis[0] = d->ground.axis[1] = (tb_expr){0, -1};
      d->ground.axis[2] = (tb_expr){1, -1}, d->ground.angle = (tb_expr){0, -1};
    }
    r = ground_key(p, &d->ground, key, value);
  } else if (!strcmp(section, "instrument")) {
    if (!d->has_tool) {
      d->has_tool = 1, d->tool.line = (int)p->line;
      d->tool.margin = d->tool.friction = (tb_expr){0, -1};
      for (int i = 0; i < 3; i++) d->tool.origin[i] = d->tool.offset[i] = (tb_expr){0, -1};
      for (int i = 0; i < 3; i++) d->tool.motion.centre[i] = (tb_expr){0, -1};
    }
    r = tool_key(p, &d->tool, key, value);
  } else if (!strcmp(kind, "cut")) {
    tb_scene_cut *c = cut_item(p, section);
    r = c ? cut_key(p, c, key, value) : 0;
  } else if (!strcmp(section, "output")) {
    if (!strcmp(key, "every")) {
      char *end;
      double v = strtod(value, &end);
      if (!*value || *end || !(v > 0) || !isfinite(v))
        return fail(p, "every: '%s' is not a time > 0 (seconds between frames)%s", value, "");
      d->frame_interval = v, r = 1;
    } else
      r = add_selector(p, &d->probe, key, value);
  } else if (!strcmp(kind, "fix") || !strcmp(kind, "force") || !strcmp(kind, "move")) {
    void *item = section_item(p, kind, section);
    if (!item) return 0;
    p->item = item;
    if (!strcmp(kind, "fix"))
      r = add_selector(p, item, key, value);
    else if (!strcmp(kind, "force")) {
      tb_scene_force *f = item;
      r = add_selector(p, &f->where, key, value);
      if (r == -1) r = force_key(p, f, key, value);
    } else {
      tb_scene_move *m = item;
      r = add_selector(p, &m->where, key, value);
      if (r == -1) r = motion_key(p, &m->motion, key, value);
      if (r == -1 && !strcmp(key, "release")) {
        if (tb_scene_parse_expr(value, &m->release))
          return fail(p, "release: '%s' is not a time%s", value, "");
        m->has_release = 1, r = 1;
      }
    }
  } else
    return fail(p,
                "unknown section [%s] (scene, mesh, model, fix, force, move, ground, instrument, "
                "cut, output)%s",
                section, "");
  if (r == -1)
    return fail(p, "unknown key '%s' in [%s] (scenes/README.md lists the keys)", key, section);
  return r > 0;
}

static int check(parser *p) {
  tb_scene_desc *d = p->d;
  tb_error *err = p->err;
  if (!d->mesh.path[0] && !d->mesh.generator[0])
    return tb_error_set(err, d->path, 0, "no mesh: give [mesh] file = PATH or generate = NAME");
  for (int i = 0; i < d->nfix; i++)
    if (!d->fix[i].n)
      return tb_error_set(err, d->path, d->fix[i].line,
                          "[fix] selects nothing (give ids, box, ...)");
  for (int i = 0; i < d->nforce; i++) {
    tb_scene_force *f = &d->force[i];
    if (!f->where.n) return tb_error_set(err, d->path, 0, "a [force] section selects no nodes");
    if (!f->has_value)
      return tb_error_set(err, d->path, f->where.line, "[force] needs total = or each = fx,fy,fz");
  }
  for (int i = 0; i < d->nmove; i++) {
    tb_scene_move *m = &d->move[i];
    if (!m->where.n) return tb_error_set(err, d->path, 0, "a [move] section selects no nodes");
    if (!m->motion.nkey) return tb_error_set(err, d->path, m->where.line, "[move] has no keyframe");
  }
  if (d->has_tool) {
    if (!d->tool.mesh.path[0] && !d->tool.mesh.generator[0])
      return tb_error_set(err, d->path, d->tool.line, "[instrument] needs file = or generate =");
    if (!d->tool.motion.nkey)
      return tb_error_set(err, d->path, d->tool.line, "[instrument] has no keyframe");
  }
  for (int i = 0; i < d->ncut; i++) {
    const tb_scene_cut *c = &d->cut[i];
    if (c->npoint < 2)
      return tb_error_set(err, d->path, c->line,
                          "[cut%s%s] needs two or more 'point = x,y,z' lines (the blade's path), "
                          "not %d",
                          c->name[0] ? " " : "", c->name, c->npoint);
    if (c->stop.param < 0 && c->stop.k < 0)
      return tb_error_set(err, d->path, c->line,
                          "[cut%s%s] needs stop = TIME (the blade at the path's last point)",
                          c->name[0] ? " " : "", c->name);
  }
  if (d->has_ground) {
    tb_scene_ground *g = &d->ground;
    for (int c = 0; c < 3; c++)
      if (g->normal[c].param >= 0)
        return tb_error_set(err, d->path, g->line, "[ground] normal must be numbers");
    if (!(tb_len(tb_v3(g->normal[0].k, g->normal[1].k, g->normal[2].k)) > 0))
      return tb_error_set(err, d->path, g->line, "[ground] normal must not be zero");
  }
  return 0;
}

int tb_scene_desc_load(tb_scene_desc *d, const char *path, tb_error *err) {
  tb_scene_desc_init(d);
  snprintf(d->path, sizeof d->path, "%s", path);
  parser p;
  memset(&p, 0, sizeof p);
  p.d = d, p.err = err;
  const char *slash = strrchr(path, '/');
  if (slash)
    snprintf(p.dir, sizeof p.dir, "%.*s", (int)(slash - path), path);
  else
    snprintf(p.dir, sizeof p.dir, ".");
  p.f = fopen(path, "r");
  if (!p.f) return tb_error_set(err, path, 0, "cannot open the scene file");
  tb_ini_setup();
  int rc = ini_parse_stream(reader, &p, handler, &p);
  fclose(p.f);
  if (p.failed) return tb_scene_desc_free(d), -1;
  if (rc > 0) {
    tb_scene_desc_free(d);
    return tb_error_set(err, path, rc, "not INI syntax (expected [section] or key = value)");
  }
  if (rc < 0) {
    tb_scene_desc_free(d);
    return tb_error_set(err, path, 0, "cannot read the scene file");
  }
  if (!d->name[0]) {
    const char *base = slash ? slash + 1 : path;
    snprintf(d->name, sizeof d->name, "%.*s", (int)strcspn(base, "."), base);
  }
  if (check(&p)) return tb_scene_desc_free(d), -1;
  return 0;
}
