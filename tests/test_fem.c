/* Tests of the linear (models/fem.c) and corotational (models/fem_corot.c)
 * tetrahedral FEM and their shared core (models/fem_core.c; thesis §3.3.2,
 * Müller & Gross 2004): patch tests, CHOLMOD residuals, factor reuse and a
 * step free of allocations, rigid-motion invariance, singular and inverted
 * input, free fall against backward Euler's closed form, energy decay,
 * determinism, and the cantilever against Euler-Bernoulli. */
#include <SuiteSparse_config.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "tb_test.h"
#include "tb_test_models.h"
#include "meshgen/tb_meshgen.h"
#include "models/tb_fem.h"
#include "models/tb_model.h"

static const char *const models[] = {"fem", "fem-corot"};

static tb_mesh beam(double lx, int nx, int ny, int nz) {
  tb_mesh m;
  tb_error err;
  memset(&m, 0, sizeof m);
  TB_CHECK_MSG(tb_beam(lx, 1, 1, nx, ny, nz, &m, &err) == 0, "%s", err.msg);
  return m;
}

/* fem-corot on its exact path (solver=exact, the reference) unless the
 * settings name a solver: these tests hold it to CHOLMOD's residual and
 * closed forms; the default solver (pcg, exact to cg_tol) is held to the
 * exact path in tests/test_fem_corot.c. */
static int create(tb_model *m, const char *name, const tb_mesh *mesh, const tb_settings *d) {
  tb_error err;
  tb_settings set = *d;
  int named = 0;
  for (int k = 0; k < set.n; k++) named |= !strcmp(set.kv[k].key, "solver");
  if (!strcmp(name, "fem-corot") && !named)
    TB_CHECK(tb_settings_set(&set, "solver=exact", &err) == 0);
  int rc = tb_model_create(m, name, mesh, &set, &err);
  TB_CHECK_MSG(rc == 0, "create %s: %s", name, err.msg);
  return rc;
}

static tb_fem_stats stats(tb_model *m) {
  tb_fem_stats s;
  tb_error err;
  memset(&s, 0, sizeof s);
  TB_CHECK_MSG(tb_fem_get_stats(m, &s, &err) == 0, "%s", err.msg);
  return s;
}

static tb_step plain(double dt, tb_vec3 g) {
  tb_step s = {0};
  memset(&s, 0, sizeof s);
  s.dt = dt, s.gravity = g;
  return s;
}

/* Nodes with x <= x0 + 1e-12, prescribed at their rest positions. */
static int clamp_left(const tb_mesh *m, double x0, int *idx, tb_vec3 *pos) {
  int n = 0;
  for (int i = 0; i < m->nv; i++)
    if (m->x[i].x <= x0 + 1e-12) idx[n] = i, pos[n++] = m->x[i];
  return n;
}

/* ---- 1. patch test ---- */

static tb_vec3 affine(tb_vec3 p) {
  static const double G[3][3] = {
      {0.012, -0.004, 0.003}, {0.005, -0.02, 0.001}, {-0.002, 0.006, 0.015}};
  tb_vec3 c = tb_v3(0.1, -0.2, 0.05);
  return tb_v3(c.x + G[0][0] * p.x + G[0][1] * p.y + G[0][2] * p.z,
               c.y + G[1][0] * p.x + G[1][1] * p.y + G[1][2] * p.z,
               c.z + G[2][0] * p.x + G[2][1] * p.y + G[2][2] * p.z);
}

/* Prescribes u = G X + c on the boundary nodes of m (quasi-static, no
 * load); every interior node must reproduce it. */
static void patch(const tb_mesh *m, const char *name) {
  int *faces = NULL;
  int nf = tb_mesh_tet_boundary(m, &faces);
  TB_CHECK(nf > 0);
  unsigned char *on = calloc((size_t)m->nv, 1);
  int *idx = malloc(sizeof(int) * (size_t)m->nv);
  tb_vec3 *pos = malloc(sizeof(tb_vec3) * (size_t)m->nv);
  for (int k = 0; k < 3 * nf; k++) on[faces[k]] = 1;
  int nfix = 0, interior = 0;
  for (int i = 0; i < m->nv; i++)
    if (on[i])
      idx[nfix] = i, pos[nfix++] = tb_add(m->x[i], affine(m->x[i]));
    else
      interior++;
  TB_CHECK_MSG(interior >= 5, "%s: only %d interior nodes", name, interior);
  tb_settings d = tb_test_settings("quasistatic=1");
  tb_model mod;
  if (create(&mod, name, m, &d) == 0) {
    tb_step s = plain(0.01, tb_v3(0, 0, 0));
    s.nfixed = nfix, s.fixed = idx, s.fixed_x = pos;
    for (int rep = 0; rep < 2; rep++) { /* corot: the second step re-linearises */
      if (tb_test_steps(&mod, &s, 1)) break;
      const tb_vec3 *x = tb_model_positions(&mod);
      double worst = 0, umax = 0;
      for (int i = 0; i < m->nv; i++) {
        tb_vec3 u = affine(m->x[i]);
        umax = fmax(umax, tb_len(u));
        if (!on[i]) worst = fmax(worst, tb_dist(tb_sub(x[i], m->x[i]), u));
      }
      TB_CHECK_MSG(worst <= 1e-9 * umax, "%s step %d: interior error %.3g (|u| %.3g)", name, rep,
                   worst, umax);
    }
    tb_model_destroy(&mod);
  }
  free(faces), free(on), free(idx), free(pos);
}

static void test_patch_beam(void) {
  tb_mesh m = beam(2, 6, 3, 3); /* 20 interior nodes */
  for (int k = 0; k < 2; k++) patch(&m, models[k]);
  tb_mesh_free(&m);
}

static void test_patch_unstructured(void) {
  tb_mesh s, m;
  tb_error err;
  memset(&m, 0, sizeof m);
  TB_CHECK_MSG(tb_geosphere(162, 1.0, &s, &err) == 0, "%s", err.msg);
  TB_CHECK_MSG(tb_tetgen(&s, "pq1.4a0.01", &m, &err) == 0, "%s", err.msg);
  TB_CHECK(m.ntet > 100);
  for (int k = 0; k < 2; k++) patch(&m, models[k]);
  tb_mesh_free(&s), tb_mesh_free(&m);
}

/* ---- 2. residual of the CHOLMOD solves ---- */

static void test_residual(void) {
  tb_mesh m = beam(4, 8, 2, 2);
  int idx[64];
  tb_vec3 pos[64];
  int nf = clamp_left(&m, 0, idx, pos);
  for (int k = 0; k < 2; k++)
    for (int qs = 0; qs < 2; qs++) {
      tb_settings d = tb_test_settings(""); /* lumped for fem, consistent for corot */
      tb_settings_setd(&d, "quasistatic", qs, NULL),
          tb_settings_setd(&d, "consistent_mass", k, NULL);
      tb_model mod;
      if (create(&mod, models[k], &m, &d)) continue;
      tb_step s = plain(0.01, tb_v3(0, 0, -9.81));
      s.nfixed = nf, s.fixed = idx, s.fixed_x = pos;
      for (int i = 0; i < 3; i++) {
        if (tb_test_steps(&mod, &s, 1)) break;
        tb_fem_stats st = stats(&mod);
        TB_CHECK_MSG(st.residual < 1e-10, "%s qs=%d step %d: residual %.3g", models[k], qs, i,
                     st.residual);
        TB_CHECK(st.solves == i + 1);
      }
      tb_model_destroy(&mod);
    }
  tb_mesh_free(&m);
}

/* ---- 3. one factorisation per prescribed set; a re-solve allocates nothing ---- */

static long nalloc;
static void *(*real_malloc)(size_t);
static void *(*real_calloc)(size_t, size_t);
static void *(*real_realloc)(void *, size_t);
static void *count_malloc(size_t n) { return nalloc++, real_malloc(n); }
static void *count_calloc(size_t n, size_t s) { return nalloc++, real_calloc(n, s); }
static void *count_realloc(void *p, size_t n) { return nalloc++, real_realloc(p, n); }

static void count_cholmod_allocations(void) {
  if (SuiteSparse_config.malloc_func == count_malloc) return; /* already counting */
  real_malloc = SuiteSparse_config.malloc_func;
  real_calloc = SuiteSparse_config.calloc_func;
  real_realloc = SuiteSparse_config.realloc_func;
  SuiteSparse_config.malloc_func = count_malloc;
  SuiteSparse_config.calloc_func = count_calloc;
  SuiteSparse_config.realloc_func = count_realloc;
}

static void test_factor_once(void) {
  tb_mesh m = beam(4, 8, 2, 2);
  int idx[64];
  tb_vec3 pos[64];
  int nf = clamp_left(&m, 0, idx, pos);
  count_cholmod_allocations();
  tb_settings d = tb_test_settings("");
  tb_model mod;
  if (create(&mod, "fem", &m, &d) == 0) {
    tb_step s = plain(0.01, tb_v3(0, 0, -9.81));
    s.nfixed = nf, s.fixed = idx, s.fixed_x = pos;
    tb_test_steps(&mod, &s, 1);
    long before = nalloc;
    tb_test_steps(&mod, &s, 99);
    TB_CHECK_MSG(nalloc == before, "CHOLMOD allocated %ld times in 99 re-solves", nalloc - before);
    TB_CHECK(stats(&mod).factorizations == 1);
    TB_CHECK(stats(&mod).solves == 100);
    s.nfixed = nf - 1; /* a different set: one more */
    tb_test_steps(&mod, &s, 10);
    TB_CHECK(stats(&mod).factorizations == 2);
    s.nfixed = nf; /* back */
    tb_test_steps(&mod, &s, 10);
    TB_CHECK(stats(&mod).factorizations == 3);
    s.dt = 0.005; /* dt enters the matrix */
    tb_test_steps(&mod, &s, 10);
    TB_CHECK(stats(&mod).factorizations == 4);
    s.nfixed = 0; /* to the empty set and back */
    tb_test_steps(&mod, &s, 3);
    s.nfixed = nf;
    tb_test_steps(&mod, &s, 3);
    TB_CHECK(stats(&mod).factorizations == 6);
    tb_model_destroy(&mod);
  }
  /* quasi-static: dt does not enter K */
  tb_settings_set(&d, "quasistatic=1", NULL);
  if (create(&mod, "fem", &m, &d) == 0) {
    tb_step s = plain(0.01, tb_v3(0, 0, -9.81));
    s.nfixed = nf, s.fixed = idx, s.fixed_x = pos;
    tb_test_steps(&mod, &s, 5);
    s.dt = 0.02;
    tb_test_steps(&mod, &s, 5);
    TB_CHECK(stats(&mod).factorizations == 1);
    tb_model_destroy(&mod);
  }
  /* corot refactors every step (numerically, same analysis) */
  tb_settings_set(&d, "quasistatic=0", NULL);
  if (create(&mod, "fem-corot", &m, &d) == 0) {
    tb_step s = plain(0.01, tb_v3(0, 0, -9.81));
    s.nfixed = nf, s.fixed = idx, s.fixed_x = pos;
    tb_test_steps(&mod, &s, 7);
    TB_CHECK(stats(&mod).factorizations == 7);
    tb_model_destroy(&mod);
  }
  tb_mesh_free(&m);
}

/* fem-corot's pcg, lagged and pd: a step that does not refactor allocates
 * nothing in CHOLMOD (cholmod_solve2 reuses its workspaces); without a
 * reason to (cg_max and cg_refactor not reached, lag not over, pd) none
 * refactors. */
static void test_corot_no_alloc(void) {
  tb_mesh m = beam(4, 8, 2, 2);
  int idx[64];
  tb_vec3 pos[64];
  int nf = clamp_left(&m, 0, idx, pos);
  count_cholmod_allocations();
  static const char *const kvs[] = {"solver=pcg cg_max=50 cg_refactor=1000000", "solver=pd",
                                    "solver=lagged lag=1000 refine=0", "solver=pcg"};
  for (int k = 0; k < 4; k++) {
    tb_settings d = tb_test_settings(kvs[k]);
    tb_model mod;
    if (create(&mod, "fem-corot", &m, &d)) continue;
    tb_step s = plain(0.01, tb_v3(0, 0, -9.81));
    s.nfixed = nf, s.fixed = idx, s.fixed_x = pos;
    tb_test_steps(&mod, &s, 2);
    long before = nalloc;
    int factors = stats(&mod).factorizations;
    tb_test_steps(&mod, &s, 50);
    if (stats(&mod).factorizations == factors)
      TB_CHECK_MSG(nalloc == before, "%s: CHOLMOD allocated %ld times in 50 steps", kvs[k],
                   nalloc - before);
    else
      TB_CHECK_MSG(k == 3, "%s: refactored (%d -> %d)", kvs[k], factors,
                   stats(&mod).factorizations);
    tb_model_destroy(&mod);
  }
  tb_mesh_free(&m);
}

/* ---- 4. rigid motions ---- */

static void test_rigid_motion(void) {
  tb_mesh m = beam(4, 8, 2, 2);
  tb_mat3 r = tb_m3_rotation(tb_v3(1, 1, 0.5), M_PI / 2);
  tb_vec3 t = tb_v3(3, -2, 7);
  tb_vec3 *x = malloc(sizeof(tb_vec3) * (size_t)m.nv);
  for (int i = 0; i < m.nv; i++) x[i] = tb_add(tb_m3_mulv(r, m.x[i]), t);
  for (int k = 0; k < 2; k++) {
    tb_settings d = tb_test_settings("");
    tb_model mod;
    tb_error err;
    if (create(&mod, models[k], &m, &d)) continue;
    TB_CHECK_MSG(tb_fem_set_state(&mod, x, NULL, &err) == 0, "%s", err.msg);
    double e0 = tb_model_energy(&mod);
    tb_step s = plain(0.01, tb_v3(0, 0, 0));
    if (tb_test_steps(&mod, &s, 1) == 0) {
      const tb_vec3 *v = tb_model_velocities(&mod);
      double vmax = 0;
      for (int i = 0; i < m.nv; i++) vmax = fmax(vmax, tb_len(v[i]));
      if (k == 1) {
        TB_CHECK_MSG(vmax <= 1e-9, "fem-corot: |v| %.3g after a rigid rotation", vmax);
        TB_CHECK_MSG(fabs(e0) <= 1e-9 && fabs(tb_model_energy(&mod)) <= 1e-9,
                     "fem-corot: energy %.3g -> %.3g", e0, tb_model_energy(&mod));
      } else { /* the known limitation of linear FEM: rotation looks like strain */
        TB_CHECK_MSG(vmax > 1.0, "fem: |v| %.3g, expected large spurious forces", vmax);
        TB_CHECK_MSG(e0 > 1000.0, "fem: energy %.3g of a rotated body", e0);
      }
    }
    tb_model_destroy(&mod);
  }
  free(x);
  tb_mesh_free(&m);
}

/* ---- 5. singular and inverted ---- */

static void test_not_positive_definite(void) {
  tb_mesh m = beam(4, 8, 2, 2);
  int idx[64];
  tb_vec3 pos[64];
  int nf = clamp_left(&m, 0, idx, pos);
  for (int k = 0; k < 2; k++) {
    tb_settings d = tb_test_settings("quasistatic=1");
    tb_model mod;
    tb_error err;
    if (create(&mod, models[k], &m, &d)) continue;
    tb_step s = plain(0.01, tb_v3(0, 0, -9.81)); /* no prescribed node: K is singular */
    memset(&err, 0, sizeof err);
    TB_CHECK(tb_model_step(&mod, &s, &err) != 0);
    TB_CHECK_MSG(strstr(err.msg, "not positive definite at column"), "%s: '%s'", models[k],
                 err.msg);
    /* one prescribed node leaves the rotations free: still singular */
    s.nfixed = 1, s.fixed = idx, s.fixed_x = pos;
    TB_CHECK(tb_model_step(&mod, &s, &err) != 0);
    TB_CHECK_MSG(strstr(err.msg, "not positive definite"), "%s: '%s'", models[k], err.msg);
    const tb_vec3 *x = tb_model_positions(&mod);
    for (int i = 0; i < m.nv; i++) TB_CHECK(tb_isfinite3(x[i]));
    s.nfixed = nf; /* recovers once clamped */
    TB_CHECK_MSG(tb_model_step(&mod, &s, &err) == 0, "%s", err.msg);
    tb_model_destroy(&mod);
  }
  /* bad prescribed lists are errors, not crashes */
  {
    tb_settings d = tb_test_settings("");
    tb_model mod;
    tb_error err;
    if (create(&mod, "fem", &m, &d) == 0) {
      int bad[2] = {5, 3};
      tb_vec3 bp[2] = {m.x[5], m.x[3]};
      tb_step s = plain(0.01, tb_v3(0, 0, 0));
      s.nfixed = 2, s.fixed = bad, s.fixed_x = bp;
      TB_CHECK(tb_model_step(&mod, &s, &err) != 0 && strstr(err.msg, "ascending"));
      bad[0] = -1;
      TB_CHECK(tb_model_step(&mod, &s, &err) != 0);
      tb_model_destroy(&mod);
    }
  }
  /* an inverted tet, also with node_mass (which skips the mass check) */
  int tmp = m.tet[4 * 7 + 1];
  m.tet[4 * 7 + 1] = m.tet[4 * 7 + 2], m.tet[4 * 7 + 2] = tmp;
  for (int k = 0; k < 2; k++)
    for (int nm = 0; nm < 2; nm++) {
      tb_settings d = tb_test_settings(nm ? "node_mass=1" : "node_mass=0");
      tb_model mod;
      tb_error err;
      memset(&err, 0, sizeof err);
      TB_CHECK(tb_model_create(&mod, models[k], &m, &d, &err) != 0);
      TB_CHECK_MSG(strstr(err.msg, "tet 7"), "%s: '%s'", models[k], err.msg);
    }
  tb_mesh_free(&m);
}

/* ---- 6. free fall ---- */

static tb_vec3 centre(const tb_mesh *m, const tb_vec3 *x) {
  tb_vec3 c = tb_v3(0, 0, 0);
  double w = 0;
  for (int t = 0; t < m->ntet; t++) { /* lumped masses of a uniform density */
    const int *e = m->tet + 4 * t;
    double v = tb_tet_volume(m->x[e[0]], m->x[e[1]], m->x[e[2]], m->x[e[3]]);
    for (int k = 0; k < 4; k++) c = tb_madd(c, v, x[e[k]]);
    w += 4 * v;
  }
  return tb_scale(c, 1.0 / w);
}

static void test_free_fall(void) {
  tb_mesh m = beam(4, 8, 2, 2);
  double g = -9.81, dt = 0.01;
  int n = 50;
  tb_vec3 c0 = centre(&m, m.x);
  for (int k = 0; k < 2; k++)
    for (int cm = 0; cm < 2; cm++) {
      double zdrop[2];
      for (int damped = 0; damped < 2; damped++) {
        tb_settings d = tb_test_settings(damped ? "rayleigh_mass=2" : "rayleigh_mass=0");
        tb_settings_setd(&d, "consistent_mass", cm, NULL);
        tb_model mod;
        if (create(&mod, models[k], &m, &d)) continue;
        tb_step s = plain(dt, tb_v3(0, 0, g));
        if (tb_test_steps(&mod, &s, n)) {
          tb_model_destroy(&mod);
          continue;
        }
        /* backward Euler with C = a M: v+ = (v + dt g) / (1 + dt a), x+ = x + dt v+ */
        double a = damped ? 2.0 : 0.0, v = 0, z = 0;
        for (int i = 0; i < n; i++) v = (v + dt * g) / (1 + dt * a), z += dt * v;
        tb_vec3 c = centre(&m, tb_model_positions(&mod));
        zdrop[damped] = c.z - c0.z;
        TB_CHECK_MSG(fabs(zdrop[damped] - z) <= 1e-9 * fabs(z),
                     "%s cm=%d a=%g: drop %.15g, closed form %.15g", models[k], cm, a,
                     zdrop[damped], z);
        TB_CHECK_NEAR(c.x, c0.x, 1e-9);
        TB_CHECK_NEAR(c.y, c0.y, 1e-9);
        /* a = 0: exactly -g dt^2 n (n+1) / 2 */
        if (!damped) TB_CHECK_NEAR(zdrop[0], g * dt * dt * n * (n + 1) / 2, 1e-9);
        /* and no deformation: all velocities equal */
        const tb_vec3 *vel = tb_model_velocities(&mod);
        for (int i = 0; i < m.nv; i++) TB_CHECK_NEAR(vel[i].z, v, 1e-9);
        tb_model_destroy(&mod);
      }
      TB_CHECK_MSG(fabs(zdrop[1]) > 0.5 * fabs(zdrop[0]) && fabs(zdrop[1]) < 0.8 * fabs(zdrop[0]),
                   "mass damping should slow the fall: %g vs %g", zdrop[1], zdrop[0]);
    }
  tb_mesh_free(&m);
}

/* External node forces m_i g act like gravity g (lumped masses), clamped. */
static void test_forces_like_gravity(void) {
  tb_mesh m = beam(4, 8, 2, 2);
  int idx[64];
  tb_vec3 pos[64];
  int nf = clamp_left(&m, 0, idx, pos);
  tb_settings d = tb_test_settings("");
  double *mass = malloc(sizeof(double) * (size_t)m.nv);
  tb_vec3 *force = malloc(sizeof(tb_vec3) * (size_t)m.nv), g = tb_v3(0.5, -1, -9.81);
  tb_error err;
  TB_CHECK(tb_lumped_masses(&m, 1.0, 0.0, mass, &err) == 0); /* fem's defaults */
  for (int i = 0; i < m.nv; i++) force[i] = tb_scale(g, mass[i]);
  for (int k = 0; k < 2; k++)
    for (int qs = 0; qs < 2; qs++) {
      tb_model a, b;
      tb_settings_setd(&d, "quasistatic", qs, NULL);
      if (create(&a, models[k], &m, &d)) continue;
      if (create(&b, models[k], &m, &d)) {
        tb_model_destroy(&a);
        continue;
      }
      tb_step sa = plain(0.01, g), sb = plain(0.01, tb_v3(0, 0, 0));
      sa.nfixed = sb.nfixed = nf, sa.fixed = sb.fixed = idx, sa.fixed_x = sb.fixed_x = pos;
      sb.force = force;
      tb_test_steps(&a, &sa, 5);
      tb_test_steps(&b, &sb, 5);
      double dmax = 0, umax = 0;
      for (int i = 0; i < m.nv; i++) {
        dmax = fmax(dmax, tb_dist(tb_model_positions(&a)[i], tb_model_positions(&b)[i]));
        umax = fmax(umax, tb_dist(tb_model_positions(&a)[i], m.x[i]));
      }
      TB_CHECK_MSG(umax > 1e-3 && dmax <= 1e-10 * umax, "%s qs=%d: %.3g of %.3g", models[k], qs,
                   dmax, umax);
      tb_model_destroy(&a), tb_model_destroy(&b);
    }
  free(mass), free(force);
  tb_mesh_free(&m);
}

/* ---- energy, prescribed motion, small-strain agreement ---- */

/* Backward Euler dissipates: with no load and no damping the energy of a
 * stretched, released beam never grows, and drops. */
static void test_energy_decays(void) {
  tb_mesh m = beam(4, 8, 2, 2);
  tb_vec3 *x = malloc(sizeof(tb_vec3) * (size_t)m.nv);
  for (int i = 0; i < m.nv; i++) x[i] = tb_v3(1.05 * m.x[i].x, m.x[i].y, 0.97 * m.x[i].z);
  for (int k = 0; k < 2; k++) {
    tb_settings d = tb_test_settings("rayleigh_stiffness=0");
    tb_model mod;
    tb_error err;
    if (create(&mod, models[k], &m, &d)) continue;
    tb_fem_set_state(&mod, x, NULL, &err);
    double e0 = tb_model_energy(&mod), e = e0;
    TB_CHECK(e0 > 0);
    tb_step s = plain(0.002, tb_v3(0, 0, 0));
    for (int i = 0; i < 40; i++) {
      if (tb_test_steps(&mod, &s, 1)) break;
      double en = tb_model_energy(&mod);
      if (k == 0)
        TB_CHECK_MSG(en <= e * (1 + 1e-12), "fem step %d: energy %.10g -> %.10g", i, e, en);
      e = en;
    }
    TB_CHECK_MSG(e < 0.99 * e0 && e > 0.05 * e0, "%s: energy %.6g -> %.6g", models[k], e0, e);
    tb_model_destroy(&mod);
  }
  free(x);
  tb_mesh_free(&m);
}

/* Prescribed nodes end exactly where told, with the velocity that moved them. */
static void test_prescribed_motion(void) {
  tb_mesh m = beam(4, 8, 2, 2);
  int idx[64];
  tb_vec3 pos[64], goal[64];
  int nf = clamp_left(&m, 0, idx, pos);
  for (int k = 0; k < 2; k++) {
    tb_settings d = tb_test_settings("");
    tb_model mod;
    if (create(&mod, models[k], &m, &d)) continue;
    tb_step s = plain(0.01, tb_v3(0, 0, -9.81));
    s.nfixed = nf, s.fixed = idx, s.fixed_x = goal;
    for (int i = 0; i < 5; i++) {
      for (int j = 0; j < nf; j++) goal[j] = tb_add(pos[j], tb_v3(0.01 * i, 0, 0.02 * i * i));
      tb_vec3 old[64];
      for (int j = 0; j < nf; j++) old[j] = tb_model_positions(&mod)[idx[j]];
      if (tb_test_steps(&mod, &s, 1)) break;
      for (int j = 0; j < nf; j++) {
        tb_vec3 xj = tb_model_positions(&mod)[idx[j]], vj = tb_model_velocities(&mod)[idx[j]];
        TB_CHECK(xj.x == goal[j].x && xj.y == goal[j].y && xj.z == goal[j].z);
        TB_CHECK_NEAR(tb_dist(vj, tb_scale(tb_sub(goal[j], old[j]), 1 / 0.01)), 0, 1e-12);
      }
    }
    tb_model_destroy(&mod);
  }
  tb_mesh_free(&m);
}

/* Under a small load the corotational model agrees with the linear one,
 * statically (quasi-static iterations converge) and dynamically. */
static void test_corot_small_strain(void) {
  tb_mesh m = beam(4, 8, 2, 2);
  int idx[64];
  tb_vec3 pos[64];
  int nf = clamp_left(&m, 0, idx, pos);
  for (int qs = 0; qs < 2; qs++) {
    tb_model lin, cor;
    tb_settings d = tb_test_settings("");
    tb_settings_setd(&d, "quasistatic", qs, NULL);
    if (create(&lin, "fem", &m, &d)) continue;
    if (create(&cor, "fem-corot", &m, &d)) {
      tb_model_destroy(&lin);
      continue;
    }
    tb_step s = plain(0.01, tb_v3(0, 0, -0.0981));
    s.nfixed = nf, s.fixed = idx, s.fixed_x = pos;
    int n = qs ? 10 : 30;
    tb_test_steps(&lin, &s, n);
    tb_test_steps(&cor, &s, n);
    double dmax = 0, umax = 0;
    for (int i = 0; i < m.nv; i++) {
      dmax = fmax(dmax, tb_dist(tb_model_positions(&lin)[i], tb_model_positions(&cor)[i]));
      umax = fmax(umax, tb_dist(tb_model_positions(&lin)[i], m.x[i]));
    }
    TB_CHECK_MSG(umax > 1e-3 && dmax < 0.01 * umax, "qs=%d: linear vs corot %.3g of %.3g", qs, dmax,
                 umax);
    tb_model_destroy(&lin), tb_model_destroy(&cor);
  }
  tb_mesh_free(&m);
}

/* ---- 7. determinism ---- */

static void test_deterministic(void) {
  tb_mesh m = beam(4, 8, 2, 2);
  int idx[64];
  tb_vec3 pos[64];
  int nf = clamp_left(&m, 0, idx, pos);
  for (int k = 0; k < 2; k++) {
    tb_vec3 *run[2] = {NULL, NULL};
    for (int r = 0; r < 2; r++) {
      tb_settings d = tb_test_settings("");
      tb_model mod;
      if (create(&mod, models[k], &m, &d)) continue;
      tb_step s = plain(0.01, tb_v3(0, 0, -9.81));
      s.nfixed = nf, s.fixed = idx, s.fixed_x = pos;
      tb_test_steps(&mod, &s, 20);
      s.nfixed = nf - 2;
      tb_test_steps(&mod, &s, 5);
      run[r] = malloc(sizeof(tb_vec3) * (size_t)m.nv);
      memcpy(run[r], tb_model_positions(&mod), sizeof(tb_vec3) * (size_t)m.nv);
      tb_model_destroy(&mod);
    }
    TB_CHECK(run[0] && run[1] && !memcmp(run[0], run[1], sizeof(tb_vec3) * (size_t)m.nv));
    free(run[0]), free(run[1]);
  }
  tb_mesh_free(&m);
}

/* ---- 8. cantilever vs Euler-Bernoulli ---- */

static void test_cantilever(void) {
  static const int res[3][3] = {{8, 2, 2}, {16, 4, 4}, {24, 6, 6}};
  double L = 4, g = 9.81, E = 3000, rho = 1, A = 1, I = 1.0 / 12;
  double eb = rho * g * A * L * L * L * L / (8 * E * I);
  double tip[3] = {0, 0, 0};
  for (int r = 0; r < 3; r++) {
    tb_mesh m = beam(L, res[r][0], res[r][1], res[r][2]);
    int *idx = malloc(sizeof(int) * (size_t)m.nv);
    tb_vec3 *pos = malloc(sizeof(tb_vec3) * (size_t)m.nv);
    int nf = clamp_left(&m, 0, idx, pos);
    tb_settings d = tb_test_settings("quasistatic=1");
    tb_settings_setd(&d, "E", E, NULL), tb_settings_setd(&d, "density", rho, NULL);
    tb_model mod;
    if (create(&mod, "fem", &m, &d) == 0) {
      tb_step s = plain(0.01, tb_v3(0, 0, -g));
      s.nfixed = nf, s.fixed = idx, s.fixed_x = pos;
      if (tb_test_steps(&mod, &s, 1) == 0) {
        const tb_vec3 *x = tb_model_positions(&mod);
        int n = 0;
        for (int i = 0; i < m.nv; i++)
          if (m.x[i].x >= L - 1e-12) tip[r] += x[i].z - m.x[i].z, n++;
        tip[r] = -tip[r] / n;
      }
      tb_model_destroy(&mod);
    }
    printf("  cantilever %dx%dx%d cubes: tip deflection %.5f, Euler-Bernoulli %.5f (%.1f%%)\n",
           res[r][0], res[r][1], res[r][2], tip[r], eb, 100 * tip[r] / eb);
    free(idx), free(pos);
    tb_mesh_free(&m);
  }
  TB_CHECK_MSG(tip[0] > 0 && tip[0] < tip[1] && tip[1] < tip[2], "tips %g %g %g", tip[0], tip[1],
               tip[2]);
  TB_CHECK_MSG(fabs(tip[2] - eb) < 0.4 * eb, "finest tip %g vs E-B %g", tip[2], eb);
}

const tb_test_case tb_tests_fem[] = {
    {"patch_beam", test_patch_beam},
    {"patch_unstructured", test_patch_unstructured},
    {"residual", test_residual},
    {"factor_once", test_factor_once},
    {"corot_no_alloc", test_corot_no_alloc},
    {"rigid_motion", test_rigid_motion},
    {"not_positive_definite", test_not_positive_definite},
    {"free_fall", test_free_fall},
    {"forces_like_gravity", test_forces_like_gravity},
    {"energy_decays", test_energy_decays},
    {"prescribed_motion", test_prescribed_motion},
    {"corot_small_strain", test_corot_small_strain},
    {"deterministic", test_deterministic},
    {"cantilever", test_cantilever},
    {0, 0},
};
