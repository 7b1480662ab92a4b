/* The table of deformation models; settings as key=value text checked
 * against each model's own table (parsing, ranges, listing); the thin
 * wrappers scenes and suites call. */
#include <errno.h>
#include <stddef.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "tb_model.h"
#include "core/tb_threads.h"
#include "core/tb_timer.h"

extern const tb_model_class tb_model_msm, tb_model_fem, tb_model_fem_corot, tb_model_sm,
    tb_model_pbd_stvk, tb_model_xpbd_stvk, tb_model_msm_vvs, tb_model_metaball, tb_model_bullet_fem,
    tb_model_bullet_softbody;

const tb_model_class *const tb_model_classes[] = {&tb_model_msm,        &tb_model_fem,
                                                  &tb_model_fem_corot,  &tb_model_sm,
                                                  &tb_model_pbd_stvk,   &tb_model_xpbd_stvk,
                                                  &tb_model_msm_vvs,    &tb_model_metaball,
                                                  &tb_model_bullet_fem, &tb_model_bullet_softbody};
const int tb_model_count = (int)(sizeof tb_model_classes / sizeof tb_model_classes[0]);

const tb_model_class *tb_model_find(const char *name) {
  for (int i = 0; i < tb_model_count; i++)
    if (!strcmp(tb_model_classes[i]->name, name)) return tb_model_classes[i];
  return NULL;
}

/* ---- tb_settings: key=value text, checked by the model that reads it ---- */

void tb_settings_init(tb_settings *s) { memset(s, 0, sizeof *s); }

int tb_settings_set(tb_settings *s, const char *kv, tb_error *err) {
  const char *eq = strchr(kv, '=');
  if (!eq || eq == kv) return tb_error_set(err, "settings", 0, "expected key=value, got '%s'", kv);
  size_t klen = (size_t)(eq - kv), vlen = strlen(eq + 1);
  if (klen >= sizeof s->kv[0].key || vlen >= sizeof s->kv[0].value)
    return tb_error_set(err, "settings", 0, "'%s': key (< %d) or value (< %d characters) too long",
                        kv, (int)sizeof s->kv[0].key, (int)sizeof s->kv[0].value);
  int i = 0;
  while (i < s->n && (strlen(s->kv[i].key) != klen || strncmp(s->kv[i].key, kv, klen))) i++;
  if (i == s->n) {
    if (s->n >= TB_SETTINGS_MAX)
      return tb_error_set(err, "settings", 0, "'%s': more than %d settings", kv, TB_SETTINGS_MAX);
    s->n++;
  }
  memcpy(s->kv[i].key, kv, klen);
  s->kv[i].key[klen] = 0;
  memcpy(s->kv[i].value, eq + 1, vlen + 1);
  return 0;
}

int tb_settings_setd(tb_settings *s, const char *key, double v, tb_error *err) {
  char buf[128];
  snprintf(buf, sizeof buf, "%s=%.17g", key, v);
  return tb_settings_set(s, buf, err);
}

/* ---- a model's table ---- */

static const tb_setting *find_setting(const tb_model_class *c, const char *key) {
  for (int i = 0; i < c->nsettings; i++)
    if (!strcmp(c->settings[i].key, key)) return &c->settings[i];
  return NULL;
}

/* Index of name in "a|b|c", or -1. */
static int choice_index(const char *choices, const char *name) {
  size_t n = strlen(name);
  int k = 0;
  for (const char *p = choices; p; k++) {
    const char *bar = strchr(p, '|');
    size_t len = bar ? (size_t)(bar - p) : strlen(p);
    if (len == n && !strncmp(p, name, n)) return k;
    p = bar ? bar + 1 : NULL;
  }
  return -1;
}

/* Name k of "a|b|c" into out. */
static void choice_name(const char *choices, int k, char *out, size_t cap) {
  const char *p = choices;
  for (int i = 0; i < k && p; i++) p = strchr(p, '|'), p = p ? p + 1 : NULL;
  if (!p) p = "?";
  const char *bar = strchr(p, '|');
  int len = bar ? (int)(bar - p) : (int)strlen(p);
  snprintf(out, cap, "%.*s", len, p);
}

/* "[lo, hi]" with open bounds as ( ). */
static void range_text(const tb_setting *st, char *out, size_t cap) {
  snprintf(out, cap, "%c%g, %g%c", st->open & TB_OPEN_LO ? '(' : '[', st->lo, st->hi,
           st->open & TB_OPEN_HI || isinf(st->hi) ? ')' : ']');
}

/* Parses text for setting st of model c into *out (REAL: the number; INT:
 * a whole number; CHOICE: the index) and checks the range. */
static int parse_value(const tb_model_class *c, const tb_setting *st, const char *text, double *out,
                       tb_error *err) {
  char *end;
  double x;
  if (st->type == TB_SETTING_CHOICE) {
    int k = choice_index(st->choices, text);
    if (k >= 0) return *out = k, 0;
    errno = 0;
    x = strtod(text, &end);
    if (!*text || *end || errno || x != floor(x) || x < st->lo || x > st->hi)
      return tb_error_set(err, c->name, 0, "%s: '%s' is not one of %s", st->key, text, st->choices);
    return *out = x, 0;
  }
  errno = 0;
  x = strtod(text, &end);
  if (!*text || *end || isnan(x))
    return tb_error_set(err, c->name, 0, "%s: '%s' is not a number", st->key, text);
  if (isinf(x)) { /* "inf", or beyond the largest double (an underflow keeps its tiny value) */
    char r[96];
    range_text(st, r, sizeof r);
    return tb_error_set(err, c->name, 0, "%s = %s is out of range: %s, finite", st->key, text, r);
  }
  if (st->type == TB_SETTING_INT && x != floor(x))
    return tb_error_set(err, c->name, 0, "%s: '%s' is not a whole number", st->key, text);
  int below = st->open & TB_OPEN_LO ? !(x > st->lo) : !(x >= st->lo);
  int above = st->open & TB_OPEN_HI ? !(x < st->hi) : !(x <= st->hi);
  if (below || above) {
    char r[96];
    range_text(st, r, sizeof r);
    return tb_error_set(err, c->name, 0, "%s = %s is out of range %s", st->key, text, r);
  }
  *out = x;
  return 0;
}

static void store(const tb_setting *st, void *dst, double x) {
  char *p = (char *)dst + st->offset;
  if (st->type == TB_SETTING_REAL) {
    memcpy(p, &x, sizeof x);
  } else {
    int k = (int)x;
    memcpy(p, &k, sizeof k);
  }
}

/* The text set gives for key, or NULL. */
static const char *given(const tb_settings *set, const char *key) {
  for (int i = 0; set && i < set->n; i++)
    if (!strcmp(set->kv[i].key, key)) return set->kv[i].value;
  return NULL;
}

/* The effective value of st (set's text, else the default); 1 when set has
 * the key, 0 when defaulted, -1 on a bad value. */
static int value_of(const tb_model_class *c, const tb_setting *st, const tb_settings *set,
                    double *out, tb_error *err) {
  const char *text = given(set, st->key);
  *out = st->def;
  if (!text) return 0;
  return parse_value(c, st, text, out, err) ? -1 : 1;
}

/* A FILE setting's text (set's, else ""), copied into dst's field. */
static int file_of(const tb_model_class *c, const tb_setting *st, const tb_settings *set, void *dst,
                   tb_error *err) {
  const char *text = given(set, st->key);
  if (!text) text = "";
  if (strlen(text) >= TB_SETTING_TEXT_MAX)
    return tb_error_set(err, c->name, 0, "%s: a file name of at most %d characters", st->key,
                        TB_SETTING_TEXT_MAX - 1);
  if (dst) memcpy((char *)dst + st->offset, text, strlen(text) + 1);
  return 0;
}

/* Fills dst (NULL: only checks) from the table's defaults and set's values. */
static int resolve(const tb_model_class *c, const tb_settings *set, void *dst, tb_error *err) {
  for (int i = 0; set && i < set->n; i++)
    if (!find_setting(c, set->kv[i].key)) {
      char keys[512];
      size_t len = 0;
      keys[0] = 0;
      for (int k = 0; k < c->nsettings && len < sizeof keys; k++)
        len += (size_t)snprintf(keys + len, sizeof keys - len, "%s%s", k ? " " : "",
                                c->settings[k].key);
      return tb_error_set(err, c->name, 0, "unknown setting '%s' for model %s (its keys: %s)",
                          set->kv[i].key, c->name, keys);
    }
  for (int i = 0; i < c->nsettings; i++) {
    double x;
    if (c->settings[i].type == TB_SETTING_FILE) {
      if (file_of(c, &c->settings[i], set, dst, err)) return -1;
      continue;
    }
    if (value_of(c, &c->settings[i], set, &x, err) < 0) return -1;
    if (dst) store(&c->settings[i], dst, x);
  }
  /* the mass fragment: one of the two must give a mass */
  const tb_setting *rho = find_setting(c, "density"), *nm = find_setting(c, "node_mass");
  double r, m;
  if (rho && nm && value_of(c, rho, set, &r, err) >= 0 && value_of(c, nm, set, &m, err) >= 0 &&
      !(r > 0 || m > 0))
    return tb_error_set(err, c->name, 0, "density or node_mass must be > 0");
  return 0;
}

static const tb_model_class *find_or_error(const char *name, tb_error *err) {
  const tb_model_class *c = tb_model_find(name);
  if (!c) {
    char names[256];
    size_t len = 0;
    for (int i = 0; i < tb_model_count && len < sizeof names; i++)
      len += (size_t)snprintf(names + len, sizeof names - len, "%s%s", i ? ", " : "",
                              tb_model_classes[i]->name);
    tb_error_set(err, name, 0, "unknown model (%s)", names);
  }
  return c;
}

int tb_model_check_settings(const char *name, const tb_settings *set, tb_error *err) {
  const tb_model_class *c = find_or_error(name, err);
  return c ? resolve(c, set, NULL, err) : -1;
}

int tb_model_setting(const char *name, const tb_settings *set, const char *key, double *out) {
  const tb_model_class *c = tb_model_find(name);
  const tb_setting *st = c ? find_setting(c, key) : NULL;
  if (!st || st->type == TB_SETTING_FILE) return -1;
  return value_of(c, st, set, out, NULL) < 0 ? -1 : 0;
}

int tb_model_has_setting(const char *name, const char *key) {
  const tb_model_class *c = tb_model_find(name);
  return c && find_setting(c, key) != NULL;
}

int tb_model_file_setting(const char *key) {
  for (int i = 0; i < tb_model_count; i++) {
    const tb_setting *st = find_setting(tb_model_classes[i], key);
    if (st && st->type == TB_SETTING_FILE) return 1;
  }
  return 0;
}

void tb_model_print_settings(FILE *f, const tb_model_class *c) {
  for (int i = 0; i < c->nsettings; i++) {
    const tb_setting *st = &c->settings[i];
    char def[64], range[96];
    if (st->type == TB_SETTING_CHOICE) {
      choice_name(st->choices, (int)st->def, def, sizeof def);
      snprintf(range, sizeof range, "%s", st->choices);
    } else if (st->type == TB_SETTING_FILE) {
      snprintf(def, sizeof def, "none"), snprintf(range, sizeof range, "a file name");
    } else {
      snprintf(def, sizeof def, "%g", st->def);
      range_text(st, range, sizeof range);
    }
    static const char *const types[] = {"real", "int", "choice", "file"};
    fprintf(f, "    %-18s %-6s %-9s %-24s %s\n", st->key, types[st->type], def, range, st->doc);
  }
}

/* ---- instances ---- */

int tb_model_create(tb_model *m, const char *name, const tb_mesh *mesh, const tb_settings *set,
                    tb_error *err) {
  memset(m, 0, sizeof *m);
  const tb_model_class *c = find_or_error(name, err);
  if (!c) return -1;
  if (mesh->nv < 1) return tb_error_set(err, name, 0, "the mesh has no nodes");
  void *settings = calloc(1, c->settings_size ? c->settings_size : 1);
  if (!settings) return tb_error_set(err, name, 0, "out of memory");
  if (resolve(c, set, settings, err)) {
    free(settings);
    return -1;
  }
  void *self = c->create(mesh, settings, err);
  free(settings);
  if (!self) return -1;
  m->cls = c, m->self = self, m->nv = mesh->nv;
  if (!c->surface) { /* the default surface: the rest mesh's boundary */
    m->ntri = mesh->ntet > 0 ? tb_mesh_tet_boundary(mesh, &m->tri) : mesh->ntri;
    if (mesh->ntet < 1 && mesh->ntri > 0) {
      m->tri = malloc(sizeof(int) * 3 * (size_t)mesh->ntri);
      if (m->tri) memcpy(m->tri, mesh->tri, sizeof(int) * 3 * (size_t)mesh->ntri);
    }
    if (m->ntri < 0 || (m->ntri > 0 && !m->tri)) {
      tb_model_destroy(m);
      return tb_error_set(err, name, 0, "out of memory");
    }
  }
  return 0;
}

_Static_assert(TB_MODEL_PROBES == 3, "median3 takes the probes' median");
static double median3(const double *v) {
  double a = v[0], b = v[1], c = v[2];
  return fmax(fmin(a, b), fmin(fmax(a, b), c));
}

int tb_model_step(tb_model *m, const tb_step *in, tb_error *err) {
  if (!(in->dt > 0)) return tb_error_set(err, m->cls->name, 0, "dt must be > 0");
  if (!tb_threads_auto() || tb_threads() < 2) return m->cls->step(m->self, in, err);
  /* step 0 warms up; then probes 1 .. 2 TB_MODEL_PROBES of each round */
  long k = m->steps++ % TB_MODEL_REPROBE;
  int probing = k >= 1 && k <= 2 * TB_MODEL_PROBES, one = probing ? !(k & 1) : m->serial;
  int was = one ? tb_threads_serial_begin() : 0;
  uint64_t t0 = probing ? tb_time_ns() : 0;
  int rc = m->cls->step(m->self, in, err);
  if (probing) m->probe[one][(k - 1) / 2] = (double)(tb_time_ns() - t0);
  if (one) tb_threads_serial_end(was);
  if (k == 2 * TB_MODEL_PROBES) m->serial = median3(m->probe[1]) <= median3(m->probe[0]);
  return rc;
}
const tb_vec3 *tb_model_positions(const tb_model *m) { return m->cls->positions(m->self); }
const tb_vec3 *tb_model_velocities(const tb_model *m) { return m->cls->velocities(m->self); }
double tb_model_energy(const tb_model *m) { return m->cls->energy(m->self); }
const double *tb_model_masses(const tb_model *m) { return m->cls->masses(m->self); }
int tb_model_npoints(const tb_model *m) {
  return m->cls->npoints ? m->cls->npoints(m->self) : m->nv;
}
tb_surface tb_model_surface(const tb_model *m) {
  if (m->cls->surface) return m->cls->surface(m->self);
  tb_surface s = {m->nv, m->ntri, tb_model_positions(m), m->tri, 0, NULL};
  return s;
}
void tb_model_correct(tb_model *m, int n, const int *ids, const tb_vec3 *x, const tb_vec3 *v) {
  m->cls->correct(m->self, n, ids, x, v);
}
int tb_model_cut(tb_model *m, const tb_cut_event *ev, tb_cut_stats *stats, tb_error *err) {
  if (stats) memset(stats, 0, sizeof *stats);
  if (!m->cls->cut)
    return tb_error_set(err, m->cls->name, 0, "the %s model cannot be cut", m->cls->name);
  if (ev->kind == TB_CUT_MOVE && (ev->npath < 2 || !ev->path))
    return tb_error_set(err, m->cls->name, 0, "a cut's path needs 2 points or more, not %d",
                        ev->npath);
  return m->cls->cut(m->self, ev, stats, err);
}
int tb_model_can_cut(const tb_model *m) { return m->cls->cut != NULL; }
const unsigned char *tb_model_tets_alive(const tb_model *m) {
  return m->cls->tets_alive ? m->cls->tets_alive(m->self) : NULL;
}
int tb_model_owns_ground(const tb_model *m) {
  return m->cls->owns_ground ? m->cls->owns_ground(m->self) : m->cls->own_ground;
}
void tb_model_destroy(tb_model *m) {
  if (m->cls && m->self) m->cls->destroy(m->self);
  free(m->tri);
  memset(m, 0, sizeof *m);
}
