/* The Bullet peers as models (models/bullet_fem.c over
 * models/bullet_fem_peer.cpp, models/bullet_softbody.c over
 * models/bullet_softbody_peer.cpp): free fall against the integrators' exact
 * discrete recurrence and its O(dt) error against g t^2 / 2, prescribed
 * nodes (held and moved), refused settings, the E/nu -> Lamé conversion
 * (formula and, through Bullet's own energy under a uniform stretch, what
 * Bullet is given), and the cantilever under gravity against our fem. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "tb_test.h"
#include "tb_test_models.h"
#include "meshgen/tb_meshgen.h"
#include "models/tb_deformable.h"
#include "models/tb_model.h"

/* every force of bullet-fem, then bullet-softbody; corotated with a soft
 * material (E 10), inside its explicit stability limit (see
 * bullet_corotated_unstable) */
static const char *const peers[][2] = {{"bullet-fem", "force=neohookean"},
                                       {"bullet-fem", "force=linear"},
                                       {"bullet-fem", "force=corotated E=10"},
                                       {"bullet-softbody", ""}};
#define NPEERS ((int)(sizeof peers / sizeof peers[0]))

static tb_mesh beam(double lx, int nx, int ny, int nz) {
  tb_mesh m;
  tb_error err;
  memset(&m, 0, sizeof m);
  TB_CHECK_MSG(tb_beam(lx, 1, 1, nx, ny, nz, &m, &err) == 0, "%s", err.msg);
  return m;
}

static int create(tb_model *m, const char *name, const tb_mesh *mesh, const char *kvs) {
  tb_error err;
  tb_settings s = tb_test_settings(kvs);
  int rc = tb_model_create(m, name, mesh, &s, &err);
  TB_CHECK_MSG(rc == 0, "create %s (%s): %s", name, kvs, err.msg);
  return rc;
}

/* The largest |z drop of a node - d| after n steps of dt from rest. */
static double fall_error(const char *name, const char *kvs, const tb_mesh *mesh, double dt, int n,
                         double d) {
  tb_model m;
  if (create(&m, name, mesh, kvs)) return INFINITY;
  tb_step s = {.dt = dt, .gravity = tb_v3(0, 0, -9.81)};
  double worst = INFINITY;
  if (!tb_test_steps(&m, &s, n)) {
    const tb_vec3 *x = tb_model_positions(&m);
    worst = 0;
    for (int i = 0; i < mesh->nv; i++) {
      double drop = mesh->x[i].z - x[i].z;
      worst = fmax(worst, fabs(drop - d));
      worst = fmax(worst, fabs(x[i].x - mesh->x[i].x) + fabs(x[i].y - mesh->x[i].y));
    }
  }
  tb_model_destroy(&m);
  return worst;
}

/* Gravity only, no ground, nothing fixed: every node falls as the
 * integrator's recurrence says, v_{k+1} = v_k + dt g, x_{k+1} = x_k + dt
 * v_{k+1}, i.e. a drop of g dt^2 n (n + 1) / 2 after n steps; its error
 * against g t^2 / 2 is g dt t / 2 (first order), so halving dt halves it.
 * Bullet's classic soft-body world hands its solver dt as a float
 * (btSoftRigidDynamicsWorld::predictUnconstraintMotion: float(timeStep)),
 * so bullet-softbody follows the recurrence with dt rounded to float (a
 * relative error of 4.5e-8 in the drop at dt 0.01). */
static void bullet_free_fall(void) {
  tb_mesh mesh = beam(2, 4, 2, 2);
  const double g = 9.81, t = 0.2;
  for (int p = 0; p < NPEERS; p++) {
    double err_dt[2];
    for (int h = 0; h < 2; h++) {
      double dt = 0.01 / (1 << h);
      int n = (int)lround(t / dt);
      double dtb = strcmp(peers[p][0], "bullet-softbody") ? dt : (double)(float)dt;
      double discrete = g * dtb * dtb * n * (n + 1) / 2;
      double e = fall_error(peers[p][0], peers[p][1], &mesh, dt, n, discrete);
      /* 1e-9 of a drop of 0.2: the elastic forces of rounding in the
       * translated positions, solved by CG (bullet-softbody: 1e-15) */
      TB_CHECK_MSG(e < 1e-9, "%s %s dt %g: off the symplectic recurrence by %g", peers[p][0],
                   peers[p][1], dt, e);
      err_dt[h] = discrete - g * t * t / 2;
    }
    TB_CHECK_MSG(fabs(err_dt[0] / err_dt[1] - 2) < 0.1, "%s: error ratio %g for dt halved",
                 peers[p][0], err_dt[0] / err_dt[1]);
  }
  tb_mesh_free(&mesh);
}

/* The root face held where it is, then moved: prescribed nodes end each
 * step exactly at their positions, with the velocity that moved them; the
 * free tip sags under gravity. */
static void bullet_fixed_nodes(void) {
  tb_mesh mesh = beam(4, 4, 2, 2);
  int *ids = malloc(sizeof(int) * (size_t)mesh.nv), nf = 0;
  tb_vec3 *at = malloc(sizeof(tb_vec3) * (size_t)mesh.nv);
  for (int i = 0; i < mesh.nv; i++)
    if (mesh.x[i].x == 0) ids[nf] = i, at[nf++] = mesh.x[i];
  int tip = 0;
  for (int i = 0; i < mesh.nv; i++)
    if (mesh.x[i].x > mesh.x[tip].x) tip = i;
  for (int p = 0; p < NPEERS; p++) {
    if (strstr(peers[p][1], "corotated")) continue; /* explicit in the elasticity: see suites */
    tb_model m;
    if (create(&m, peers[p][0], &mesh, peers[p][1])) continue;
    tb_step s = {
        .dt = 0.01, .gravity = tb_v3(0, 0, -9.81), .nfixed = nf, .fixed = ids, .fixed_x = at};
    if (!tb_test_steps(&m, &s, 30)) {
      const tb_vec3 *x = tb_model_positions(&m), *v = tb_model_velocities(&m);
      int held = 1;
      for (int k = 0; k < nf; k++)
        held &= x[ids[k]].x == at[k].x && x[ids[k]].y == at[k].y && x[ids[k]].z == at[k].z &&
                tb_dot(v[ids[k]], v[ids[k]]) == 0;
      TB_CHECK_MSG(held, "%s %s: a held node moved", peers[p][0], peers[p][1]);
      TB_CHECK_MSG(x[tip].z < mesh.x[tip].z - 1e-6, "%s %s: the tip did not sag (%g)", peers[p][0],
                   peers[p][1], x[tip].z - mesh.x[tip].z);
      /* move the root up by 0.01 in one step */
      tb_vec3 *up = malloc(sizeof(tb_vec3) * (size_t)nf);
      for (int k = 0; k < nf; k++) up[k] = tb_add(at[k], tb_v3(0, 0, 0.01));
      s.fixed_x = up;
      if (!tb_test_steps(&m, &s, 1)) {
        x = tb_model_positions(&m), v = tb_model_velocities(&m);
        int moved = 1;
        for (int k = 0; k < nf; k++)
          moved &= x[ids[k]].z == up[k].z && fabs(v[ids[k]].z - 1.0) < 1e-9 &&
                   fabs(v[ids[k]].x) + fabs(v[ids[k]].y) < 1e-12;
        TB_CHECK_MSG(moved, "%s %s: a moved node is not at its position and velocity", peers[p][0],
                     peers[p][1]);
      }
      free(up);
    }
    tb_model_destroy(&m);
  }
  free(ids), free(at);
  tb_mesh_free(&mesh);
}

static void refused(const char *name, const char *kvs, const char *word) {
  tb_mesh mesh = beam(1, 1, 1, 1);
  tb_settings s = tb_test_settings(kvs);
  tb_model m;
  tb_error err;
  int rc = tb_model_create(&m, name, &mesh, &s, &err);
  TB_CHECK_MSG(rc != 0, "%s accepted %s", name, kvs);
  if (rc)
    TB_CHECK_MSG(strstr(err.msg, word) != NULL, "%s %s: error '%s' does not name %s", name, kvs,
                 err.msg, word);
  else
    tb_model_destroy(&m);
  tb_mesh_free(&mesh);
}

static void bullet_bad_settings(void) {
  refused("bullet-fem", "force=quadratic", "force");
  refused("bullet-fem", "force=3", "force");
  refused("bullet-fem", "E=0", "E");
  refused("bullet-fem", "nu=0.5", "nu");
  refused("bullet-fem", "damping=-1", "damping");
  refused("bullet-fem", "force=neohookean damping_mass=0.1", "damping_mass");
  refused("bullet-fem", "implicit=2", "implicit");
  refused("bullet-softbody", "stiffness=0", "stiffness");
  refused("bullet-softbody", "stiffness=1.5", "stiffness");
  refused("bullet-softbody", "iterations=0", "iterations");
  refused("bullet-softbody", "damping=2", "damping");
  /* a mesh without tets */
  tb_mesh mesh = beam(1, 1, 1, 1);
  free(mesh.tet), mesh.tet = NULL, mesh.ntet = 0;
  for (int k = 0; k < 2; k++) {
    tb_model m;
    tb_error err;
    int rc = tb_model_create(&m, k ? "bullet-softbody" : "bullet-fem", &mesh, NULL, &err);
    TB_CHECK_MSG(rc != 0, "a mesh without tets accepted");
    if (!rc) tb_model_destroy(&m);
  }
  tb_mesh_free(&mesh);
}

/* mu = E / (2 (1 + nu)), lambda = E nu / ((1 + nu)(1 - 2 nu)), and back;
 * then Bullet's linear force's energy under the uniform stretch F = diag(1
 * + e, 1, 1), (mu + lambda / 2) e^2 per volume, shows Bullet got them. */
static void bullet_lame(void) {
  double mu, lambda;
  tb_deformable_lame(3000, 0.3, &mu, &lambda);
  TB_CHECK_NEAR(mu, 3000 / 2.6, 1e-9);
  TB_CHECK_NEAR(lambda, 900 / (1.3 * 0.4), 1e-9);
  TB_CHECK_NEAR(mu * (3 * lambda + 2 * mu) / (lambda + mu), 3000, 1e-9);
  TB_CHECK_NEAR(lambda / (2 * (lambda + mu)), 0.3, 1e-12);
  tb_deformable_lame(1e5, -0.5, &mu, &lambda);
  TB_CHECK_NEAR(mu, 1e5, 1e-6);
  TB_CHECK_NEAR(lambda, -5e4, 1e-6);

  tb_mesh mesh = beam(1, 2, 2, 2);
  const double E = 5000, nu = 0.35, e = 1e-3;
  tb_model m;
  if (!create(&m, "bullet-fem", &mesh, "force=linear E=5000 nu=0.35")) {
    tb_vec3 *x = malloc(sizeof(tb_vec3) * (size_t)mesh.nv);
    int *ids = malloc(sizeof(int) * (size_t)mesh.nv);
    for (int i = 0; i < mesh.nv; i++)
      ids[i] = i, x[i] = tb_v3(mesh.x[i].x * (1 + e), mesh.x[i].y, mesh.x[i].z);
    tb_model_correct(&m, mesh.nv, ids, x, NULL);
    tb_deformable_lame(E, nu, &mu, &lambda);
    double want = (mu + lambda / 2) * e * e * tb_mesh_volume(&mesh);
    double got = tb_model_energy(&m);
    TB_CHECK_MSG(fabs(got - want) <= 1e-9 * want, "energy %.12g, want %.12g", got, want);
    free(x), free(ids);
    tb_model_destroy(&m);
  }
  tb_mesh_free(&mesh);
}

/* The 10 x 1 x 1 cantilever (E 3e6: a tip sag of 0.017 on these coarse
 * tets, small strain) under gravity, root held: bullet-fem linear, damped
 * to rest over 4 s (damping_mass 5), against our fem's static solve. Both
 * are linear elasticity on the same tets (Bullet's linear force is
 * corotated, the same at this sag), so they reach the same equilibrium:
 * measured equal to 6 digits; checked to 0.1% (what is left of the
 * damped oscillation after 4 s is far below that). */
static void bullet_beam_sag(void) {
  tb_mesh mesh = beam(10, 10, 2, 2);
  int *ids = malloc(sizeof(int) * (size_t)mesh.nv), nf = 0;
  for (int i = 0; i < mesh.nv; i++)
    if (mesh.x[i].x == 0) ids[nf++] = i;
  tb_vec3 *at = malloc(sizeof(tb_vec3) * (size_t)mesh.nv);
  for (int k = 0; k < nf; k++) at[k] = mesh.x[ids[k]];
  double sag[2] = {NAN, NAN};
  const char *const name[2] = {"fem", "bullet-fem"};
  const char *const kvs[2] = {"E=3e6 nu=0.3 quasistatic=1",
                              "force=linear E=3e6 nu=0.3 damping_mass=5"};
  const int steps[2] = {1, 400};
  for (int k = 0; k < 2; k++) {
    tb_model m;
    if (create(&m, name[k], &mesh, kvs[k])) continue;
    tb_step s = {
        .dt = 0.01, .gravity = tb_v3(0, 0, -9.81), .nfixed = nf, .fixed = ids, .fixed_x = at};
    if (!tb_test_steps(&m, &s, steps[k])) {
      const tb_vec3 *x = tb_model_positions(&m);
      double z = 0;
      int n = 0;
      for (int i = 0; i < mesh.nv; i++)
        if (mesh.x[i].x == 10) z += x[i].z - mesh.x[i].z, n++;
      sag[k] = z / n;
    }
    tb_model_destroy(&m);
  }
  TB_CHECK_MSG(sag[0] < -0.01 && sag[1] < -0.01, "tip sag fem %g, bullet-fem %g", sag[0], sag[1]);
  TB_CHECK_MSG(fabs(sag[1] / sag[0] - 1) < 1e-3, "tip sag fem %g, bullet-fem %g (ratio %g)", sag[0],
               sag[1], sag[1] / sag[0]);
  free(ids), free(at);
  tb_mesh_free(&mesh);
}

/* Bullet's corotated force has no force differential, so its implicit
 * step is explicit in the elasticity: at E 3000, dt 0.01 (beyond the
 * explicit limit of about h / sqrt((lambda + 2 mu) / rho) = 0.004 for this
 * mesh) a body in free fall is torn apart by the rounding in its
 * translated positions alone (in 20 steps), while neohookean and linear
 * fall rigidly. Shown, not hidden (the suites report it as unstable). */
static void bullet_corotated_unstable(void) {
  tb_mesh mesh = beam(2, 4, 2, 2);
  const char *const kvs[3] = {"force=corotated", "force=neohookean", "force=linear"};
  const double dt = 0.01, drop = 9.81 * dt * dt * 20 * 21 / 2;
  for (int k = 0; k < 3; k++) {
    double e = fall_error("bullet-fem", kvs[k], &mesh, dt, 20, drop);
    if (k == 0)
      TB_CHECK_MSG(!(e < 1), "corotated kept its shape in free fall (off by %g)", e);
    else
      TB_CHECK_MSG(e < 1e-9, "%s off a rigid fall by %g", kvs[k], e);
  }
  tb_mesh_free(&mesh);
}

const tb_test_case tb_tests_bullet_models[] = {
    {"bullet_corotated_unstable", bullet_corotated_unstable},
    {"bullet_free_fall", bullet_free_fall},
    {"bullet_fixed_nodes", bullet_fixed_nodes},
    {"bullet_bad_settings", bullet_bad_settings},
    {"bullet_lame", bullet_lame},
    {"bullet_beam_sag", bullet_beam_sag},
    {0, 0},
};
