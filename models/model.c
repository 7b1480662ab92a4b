/* The table of deformation models, their shared settings (defaults are the
 * thesis's §3.5 parameters) and the thin wrappers scenes and suites call. */
#include <errno.h>
#include <stddef.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "tb_model.h"

extern const tb_model_class tb_model_msm, tb_model_fem, tb_model_fem_corot, tb_model_sm;

const tb_model_class *const tb_model_classes[] = {&tb_model_msm, &tb_model_fem, &tb_model_fem_corot,
                                                  &tb_model_sm};
const int tb_model_count = (int)(sizeof tb_model_classes / sizeof tb_model_classes[0]);

const tb_model_class *tb_model_find(const char *name) {
  for (int i = 0; i < tb_model_count; i++)
    if (!strcmp(tb_model_classes[i]->name, name)) return tb_model_classes[i];
  return NULL;
}

tb_model_def tb_model_default_def(void) {
  tb_model_def d;
  memset(&d, 0, sizeof d);
  d.density = 1.0; /* SOFA's liver scene */
  d.E = 3000.0, d.nu = 0.3;
  d.ks = 180.0, d.kd = 5.0;
  d.rayleigh_stiffness = 0.02;
  d.sm_mode = TB_SM_QUADRATIC;
  d.alpha = 0.72, d.beta = 0.63;
  d.clusters = 50, d.radius = 1.0;
  d.cluster_mode = TB_CLUSTER_REGIONS;
  return d;
}

/* The settable fields: name, offset, kind (d double, i int, m sm_mode, c cluster_mode). */
typedef struct field {
  const char *key;
  size_t off;
  char kind;
} field;
#define F(name, kind) \
  { #name, offsetof(tb_model_def, name), kind }
static const field fields[] = {
    F(density, 'd'),
    F(node_mass, 'd'),
    F(E, 'd'),
    F(nu, 'd'),
    F(ks, 'd'),
    F(kd, 'd'),
    F(calibrated, 'i'),
    F(rayleigh_mass, 'd'),
    F(rayleigh_stiffness, 'd'),
    F(consistent_mass, 'i'),
    F(quasistatic, 'i'),
    F(sm_mode, 'm'),
    F(alpha, 'd'),
    F(beta, 'd'),
    F(clusters, 'i'),
    F(radius, 'd'),
    F(cluster_mode, 'c'),
    F(sm_damping, 'd'),
};
#undef F

static int pick(const char *v, const char *const *names, int n) {
  for (int i = 0; i < n; i++)
    if (!strcmp(v, names[i])) return i;
  return -1;
}

int tb_model_def_set(tb_model_def *def, const char *kv, tb_error *err) {
  const char *eq = strchr(kv, '=');
  if (!eq || eq == kv) return tb_error_set(err, "--set", 0, "expected key=value, got '%s'", kv);
  size_t klen = (size_t)(eq - kv);
  const char *v = eq + 1;
  for (size_t i = 0; i < sizeof fields / sizeof fields[0]; i++) {
    const field *f = &fields[i];
    if (strlen(f->key) != klen || strncmp(f->key, kv, klen)) continue;
    char *p = (char *)def + f->off, *end;
    if (f->kind == 'm' || f->kind == 'c') {
      static const char *const modes[] = {"rigid", "linear", "quadratic"};
      static const char *const cmodes[] = {"regions", "tets"};
      int k = f->kind == 'm' ? pick(v, modes, 3) : pick(v, cmodes, 2);
      if (k < 0)
        return tb_error_set(err, "--set", 0, "%s: '%s' is not one of %s", f->key, v,
                            f->kind == 'm' ? "rigid, linear, quadratic" : "regions, tets");
      memcpy(p, &k, sizeof k);
      return 0;
    }
    errno = 0;
    if (f->kind == 'i') {
      long n = strtol(v, &end, 10);
      if (!*v || *end || errno || n < 0 || n > 100000000)
        return tb_error_set(err, "--set", 0, "%s: '%s' is not a whole number >= 0", f->key, v);
      int k = (int)n;
      memcpy(p, &k, sizeof k);
    } else {
      double x = strtod(v, &end);
      if (!*v || *end || errno || !isfinite(x))
        return tb_error_set(err, "--set", 0, "%s: '%s' is not a finite number", f->key, v);
      memcpy(p, &x, sizeof x);
    }
    return 0;
  }
  return tb_error_set(err, "--set", 0, "unknown model setting '%.*s'", (int)klen, kv);
}

int tb_model_def_check(const tb_model_def *d, tb_error *err) {
#define REQUIRE(cond, ...) \
  if (!(cond)) return tb_error_set(err, "model settings", 0, __VA_ARGS__)
  REQUIRE(d->density > 0 || d->node_mass > 0, "density or node_mass must be > 0");
  REQUIRE(d->node_mass >= 0, "node_mass must be >= 0");
  REQUIRE(d->E > 0, "E must be > 0 (got %g)", d->E);
  REQUIRE(d->nu > -1 && d->nu < 0.5, "nu must be in (-1, 0.5) (got %g)", d->nu);
  REQUIRE(d->ks >= 0 && d->kd >= 0, "ks and kd must be >= 0");
  REQUIRE(d->rayleigh_mass >= 0 && d->rayleigh_stiffness >= 0, "Rayleigh factors must be >= 0");
  REQUIRE(d->alpha >= 0 && d->alpha <= 1, "alpha must be in [0, 1] (got %g)", d->alpha);
  REQUIRE(d->beta >= 0 && d->beta <= 1, "beta must be in [0, 1] (got %g)", d->beta);
  REQUIRE(d->clusters >= 1, "clusters must be >= 1");
  REQUIRE(d->radius > 0, "radius must be > 0");
  REQUIRE(d->sm_damping >= 0 && d->sm_damping < 1, "sm_damping must be in [0, 1)");
  REQUIRE(d->sm_mode >= TB_SM_RIGID && d->sm_mode <= TB_SM_QUADRATIC, "bad sm_mode");
  REQUIRE(d->cluster_mode == TB_CLUSTER_REGIONS || d->cluster_mode == TB_CLUSTER_TETS,
          "bad cluster_mode");
#undef REQUIRE
  return 0;
}

int tb_model_create(tb_model *m, const char *name, const tb_mesh *mesh, const tb_model_def *def,
                    tb_error *err) {
  memset(m, 0, sizeof *m);
  const tb_model_class *c = tb_model_find(name);
  if (!c) return tb_error_set(err, name, 0, "unknown model (msm, fem, fem-corot, sm)");
  if (tb_model_def_check(def, err)) return -1;
  if (mesh->nv < 1) return tb_error_set(err, name, 0, "the mesh has no nodes");
  void *self = c->create(mesh, def, err);
  if (!self) return -1;
  m->cls = c, m->self = self, m->nv = mesh->nv;
  return 0;
}

int tb_model_step(tb_model *m, const tb_step *in, tb_error *err) {
  if (!(in->dt > 0)) return tb_error_set(err, m->cls->name, 0, "dt must be > 0");
  return m->cls->step(m->self, in, err);
}
const tb_vec3 *tb_model_positions(const tb_model *m) { return m->cls->positions(m->self); }
const tb_vec3 *tb_model_velocities(const tb_model *m) { return m->cls->velocities(m->self); }
double tb_model_energy(const tb_model *m) { return m->cls->energy(m->self); }
void tb_model_destroy(tb_model *m) {
  if (m->cls && m->self) m->cls->destroy(m->self);
  memset(m, 0, sizeof *m);
}
