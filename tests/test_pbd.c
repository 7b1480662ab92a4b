/* Tests of the position-based models pbd-stvk and xpbd-stvk
 * (models/pbd*.c): the constraint gradient against finite differences, rest
 * and rigid motions, a projection lowering the energy, inverted tets, the
 * ground (nothing below it; sticking and sliding as mu says), the
 * integrators' free fall (BDF2 exact velocity, measured orders), thread
 * independence, and a run beyond its bound reported as unstable. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "tb_test.h"
#include "tb_test_models.h"
#include "core/tb_threads.h"
#include "meshgen/tb_meshgen.h"
#include "models/pbd_priv.h"
#include "scenes/tb_sim.h"

/* V psi(F) of the tet a, b, c, d (rest A..D) and its gradient, from pbd_energy. */
static double tet_energy(int kind, double mu, double lam, const tb_vec3 rest[4], const tb_vec3 x[4],
                         tb_vec3 grad[4]) {
  tb_mat3 dm, inv;
  double ds[9], F[9], P[9], psi = 0;
  for (int j = 0; j < 3; j++) {
    tb_vec3 d = tb_sub(rest[j], rest[3]), e = tb_sub(x[j], x[3]);
    dm.m[0][j] = d.x, dm.m[1][j] = d.y, dm.m[2][j] = d.z;
    ds[j] = e.x, ds[3 + j] = e.y, ds[6 + j] = e.z;
  }
  tb_m3_inverse(dm, &inv);
  for (int r = 0; r < 3; r++)
    for (int c = 0; c < 3; c++)
      F[3 * r + c] =
          ds[3 * r] * inv.m[0][c] + ds[3 * r + 1] * inv.m[1][c] + ds[3 * r + 2] * inv.m[2][c];
  TB_CHECK(pbd_energy(kind, mu, lam, F, &psi, P));
  double V = fabs(tb_m3_det(dm)) / 6;
  if (grad) {
    for (int j = 0; j < 3; j++) { /* V P D_m^-T, column j */
      double g[3];
      for (int r = 0; r < 3; r++)
        g[r] =
            V * (P[3 * r] * inv.m[j][0] + P[3 * r + 1] * inv.m[j][1] + P[3 * r + 2] * inv.m[j][2]);
      grad[j] = tb_v3(g[0], g[1], g[2]);
    }
    grad[3] = tb_scale(tb_add(tb_add(grad[0], grad[1]), grad[2]), -1);
  }
  return V * psi;
}

static void gradient_matches_finite_differences(void) {
  const tb_vec3 rest[4] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  tb_vec3 x[4] = {{0.1, -0.05, 0.02}, {1.3, 0.1, -0.1}, {0.05, 0.8, 0.2}, {-0.1, 0.15, 1.2}};
  for (int kind = PBD_STVK; kind <= PBD_NEOHOOKEAN; kind++) {
    tb_vec3 g[4];
    double U = tet_energy(kind, 1000, 1500, rest, x, g), h = 1e-5;
    TB_CHECK(U > 0);
    double gmax = 0, errmax = 0;
    for (int j = 0; j < 4; j++)
      for (int c = 0; c < 3; c++) {
        tb_vec3 xp[4], xm[4];
        memcpy(xp, x, sizeof xp), memcpy(xm, x, sizeof xm);
        double *pp = c == 0 ? &xp[j].x : c == 1 ? &xp[j].y : &xp[j].z;
        double *pm = c == 0 ? &xm[j].x : c == 1 ? &xm[j].y : &xm[j].z;
        *pp += h, *pm -= h;
        double fd = (tet_energy(kind, 1000, 1500, rest, xp, NULL) -
                     tet_energy(kind, 1000, 1500, rest, xm, NULL)) /
                    (2 * h);
        double an = tb_comp(g[j], c);
        gmax = fmax(gmax, fabs(an));
        errmax = fmax(errmax, fabs(an - fd));
      }
    TB_CHECK_MSG(errmax <= 1e-7 * gmax, "energy %d: gradient error %g of %g", kind, errmax, gmax);
  }
}

static tb_mesh cube(void) {
  tb_mesh m;
  tb_error err;
  TB_CHECK(tb_beam(1, 1, 1, 2, 2, 2, &m, &err) == 0);
  return m;
}

static tb_step still(double dt) {
  tb_step s = {0};
  s.dt = dt;
  return s;
}

/* At rest and after any rigid motion every constraint is zero: nothing moves. */
static void rest_and_rigid_motion(void) {
  tb_mesh m = cube();
  const char *names[] = {"pbd-stvk", "xpbd-stvk"};
  for (int k = 0; k < 2; k++) {
    tb_model md;
    tb_error err;
    tb_settings set = tb_test_settings("energy=neohookean");
    for (int e = 0; e < 2; e++) {
      TB_CHECK(tb_model_create(&md, names[k], &m, e ? &set : NULL, &err) == 0);
      tb_mat3 R = tb_m3_rotation(tb_v3(1, 2, 3), 0.7);
      int *ids = malloc(sizeof(int) * (size_t)m.nv);
      tb_vec3 *xr = malloc(sizeof(tb_vec3) * (size_t)m.nv);
      for (int i = 0; i < m.nv; i++)
        ids[i] = i, xr[i] = tb_add(tb_m3_mulv(R, m.x[i]), tb_v3(5, -2, 1));
      tb_step st = still(0.01);
      TB_CHECK(tb_model_step(&md, &st, &err) == 0);
      double d0 = 0;
      for (int i = 0; i < m.nv; i++) d0 = fmax(d0, tb_dist(tb_model_positions(&md)[i], m.x[i]));
      TB_CHECK_MSG(d0 < 1e-12, "%s at rest moved %g", names[k], d0);
      tb_model_correct(&md, m.nv, ids, xr, NULL);
      for (int s = 0; s < 5; s++) TB_CHECK(tb_model_step(&md, &st, &err) == 0);
      double d = 0;
      for (int i = 0; i < m.nv; i++) d = fmax(d, tb_dist(tb_model_positions(&md)[i], xr[i]));
      TB_CHECK_MSG(d < 1e-10, "%s (energy %d) after a rigid motion moved %g", names[k], e, d);
      free(ids), free(xr);
      tb_model_destroy(&md);
    }
  }
  tb_mesh_free(&m);
}

/* The strain energy sum V psi of positions x. */
static double strain_energy(const tb_mesh *m, const tb_vec3 *x) {
  double e = 0;
  for (int t = 0; t < m->ntet; t++) {
    tb_vec3 r[4], y[4];
    for (int k = 0; k < 4; k++) r[k] = m->x[m->tet[4 * t + k]], y[k] = x[m->tet[4 * t + k]];
    e += tet_energy(PBD_STVK, 1, 1, r, y, NULL);
  }
  return e;
}

/* One projection sweep from a stretched state lowers the energy, the more
 * the larger the stiffness k. */
static void projection_lowers_energy(void) {
  tb_mesh m = cube();
  tb_vec3 *xs = malloc(sizeof(tb_vec3) * (size_t)m.nv);
  int *ids = malloc(sizeof(int) * (size_t)m.nv);
  for (int i = 0; i < m.nv; i++)
    ids[i] = i, xs[i] = tb_v3(1.3 * m.x[i].x, m.x[i].y, 0.9 * m.x[i].z);
  double e0 = strain_energy(&m, xs), e_prev = e0;
  const char *ks[] = {"k=0.2 iterations=1", "k=1 iterations=1"};
  for (int k = 0; k < 2; k++) {
    tb_settings set = tb_test_settings(ks[k]);
    tb_model md;
    tb_error err;
    TB_CHECK(tb_model_create(&md, "pbd-stvk", &m, &set, &err) == 0);
    tb_model_correct(&md, m.nv, ids, xs, NULL);
    tb_step st = still(0.01);
    TB_CHECK(tb_model_step(&md, &st, &err) == 0);
    double e1 = strain_energy(&m, tb_model_positions(&md));
    TB_CHECK_MSG(e1 < e_prev, "%s: energy %g -> %g", ks[k], e_prev, e1);
    e_prev = e1;
    tb_model_destroy(&md);
  }
  TB_CHECK(e_prev < e0);
  free(xs), free(ids);
  tb_mesh_free(&m);
}

/* An inverted tet (a node mirrored through the opposite face) is restored
 * by the projection, for both energies; the health check sees it meanwhile. */
static void inverted_tet_restored(void) {
  tb_mesh m = {0};
  tb_vec3 x[4] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  int tet[4] = {0, 1, 2, 3};
  if (tb_tet_volume(x[0], x[1], x[2], x[3]) < 0) tet[0] = 1, tet[1] = 0;
  m.nv = 4, m.ntet = 1, m.x = x, m.tet = tet;
  const char *sets[] = {"energy=stvk", "energy=neohookean"};
  for (int e = 0; e < 2; e++) {
    tb_settings set = tb_test_settings(sets[e]);
    tb_model md;
    tb_error err;
    TB_CHECK(tb_model_create(&md, "pbd-stvk", &m, &set, &err) == 0);
    int ids[1] = {3};
    tb_vec3 flip[1] = {{0, 0, -1}}; /* node 3 through the face z = 0 */
    tb_model_correct(&md, 1, ids, flip, NULL);
    const tb_vec3 *p = tb_model_positions(&md);
    tb_health h = tb_model_health(&m, p, tb_model_velocities(&md), 0, 1);
    TB_CHECK_MSG(!h.ok && strstr(h.reason, "inverted"), "%s: health says '%s'", sets[e], h.reason);
    tb_step st = still(0.01);
    for (int s = 0; s < 200; s++) TB_CHECK(tb_model_step(&md, &st, &err) == 0);
    p = tb_model_positions(&md);
    double v = tb_tet_volume(p[tet[0]], p[tet[1]], p[tet[2]], p[tet[3]]);
    TB_CHECK_MSG(v > 0.5 / 6, "%s: volume %g after 200 steps (rest 1/6)", sets[e], v);
    tb_model_destroy(&md);
  }
}

/* Runs scene `scene` with model and overrides kvs; returns the simulation. */
static int run_scene(tb_sim *s, const char *scene, const char *model, const char *kvs, double T) {
  tb_sim_def def;
  tb_sim_def_init(&def);
  tb_settings set;
  tb_settings_init(&set);
  tb_error err;
  char buf[256], *save = NULL;
  snprintf(buf, sizeof buf, "%s", kvs);
  for (char *tok = strtok_r(buf, " ", &save); tok; tok = strtok_r(NULL, " ", &save))
    if (tb_sim_def_set(&def, tok, &err) == 1) TB_CHECK(tb_settings_set(&set, tok, &err) == 0);
  if (T > 0) def.duration = T;
  if (tb_sim_create(s, scene, &def, model, &set, NULL, &err)) {
    TB_CHECK_MSG(0, "%s: %s", scene, err.msg);
    return -1;
  }
  long n = lround(s->def.duration / s->def.dt);
  for (long k = 0; k < n; k++)
    if (tb_sim_step(s, &err)) {
      TB_CHECK_MSG(0, "%s %s: %s", scene, model, err.msg);
      return -1;
    }
  return 0;
}

/* The liver dropped onto the ground never ends below it and comes to rest
 * on it at the scene's defaults (tb_sim_at_rest); without the ground it
 * falls through the plane, which is kept, off, for the pictures (fig. 9). */
static void ground_holds(void) {
  const char *models[] = {"pbd-stvk", "xpbd-stvk"};
  for (int k = 0; k < 2; k++) {
    tb_sim s;
    if (run_scene(&s, "liver-drop", models[k], "", 0) == 0) {
      TB_CHECK_MSG(s.pen_ground_max <= 1e-6 * s.size, "%s: %g below the ground (size %g)",
                   models[k], s.pen_ground_max, s.size);
      tb_sim_metrics mt = tb_sim_measure(&s);
      TB_CHECK_MSG(mt.com_z > 0, "%s: centre of mass at %g", models[k], mt.com_z);
      double speed, tol, zmin = INFINITY;
      const tb_vec3 *x = tb_model_positions(&s.model);
      for (int i = 0; i < s.mesh.nv; i++) zmin = fmin(zmin, x[i].z);
      TB_CHECK_MSG(tb_sim_at_rest(&s, &speed, &tol), "%s: not at rest after %g s (speed %g > %g)",
                   models[k], s.t, speed, tol);
      TB_CHECK_MSG(fabs(zmin) <= 1e-6 * s.size, "%s: lowest node at z = %g, not on the ground",
                   models[k], zmin);
    }
    tb_sim_destroy(&s);
    if (run_scene(&s, "liver-drop", models[k], "ground=0", 1.5) == 0) {
      tb_sim_metrics mt = tb_sim_measure(&s);
      TB_CHECK_MSG(mt.com_z < 0, "%s without ground: centre of mass at %g", models[k], mt.com_z);
      TB_CHECK_MSG(!s.has_ground && s.ground_off && s.ground.n.z == 1 && s.pen_ground_max == 0,
                   "%s without ground: has %d, off %d, normal z %g, penetration %g", models[k],
                   s.has_ground, s.ground_off, s.ground.n.z, s.pen_ground_max);
    }
    tb_sim_destroy(&s);
  }
}

/* Constraint damping damps: the beam let go from 50% stretch (no drag)
 * keeps less kinetic energy over its third second with rayleigh_stiffness
 * 0.02 than without, for both models. */
static void damping_damps(void) {
  const char *models[] = {"pbd-stvk", "xpbd-stvk"};
  for (int k = 0; k < 2; k++) {
    double ke[2];
    for (int d = 0; d < 2; d++) {
      tb_sim s;
      ke[d] = NAN;
      if (run_scene(&s, "beam-stretch", models[k],
                    d ? "amplitude=2 drag=0 rayleigh_stiffness=0.02"
                      : "amplitude=2 drag=0 rayleigh_stiffness=0",
                    2) == 0) {
        tb_error err;
        ke[d] = 0;
        for (int n = 0; n < 100 && tb_sim_step(&s, &err) == 0; n++) {
          const tb_vec3 *v = tb_model_velocities(&s.model);
          const double *m = tb_model_masses(&s.model);
          for (int i = 0; i < s.mesh.nv; i++) ke[d] += 0.5 * m[i] * tb_dot(v[i], v[i]) / 100;
        }
      }
      tb_sim_destroy(&s);
    }
    printf(
        "  %s, beam let go from 50%% stretch, mean kinetic energy over 2-3 s: %.4g undamped, "
        "%.4g damped\n",
        models[k], ke[0], ke[1]);
    TB_CHECK_MSG(ke[1] < 0.5 * ke[0], "%s: kinetic energy %g damped, %g undamped", models[k], ke[1],
                 ke[0]);
  }
}

/* The block on the slope (mu_s 0.5, mu_k 0.4) sticks at 20 degrees and at
 * 35 slides as a rigid block would, s = g (sin a - mu_k cos a) t^2 / 2. */
static void slope_sticks_and_slides(void) {
  const char *models[] = {"pbd-stvk", "xpbd-stvk"};
  for (int k = 0; k < 2; k++) {
    tb_sim s;
    if (run_scene(&s, "slope", models[k], "amplitude=20", 1) == 0) {
      tb_sim_metrics mt = tb_sim_measure(&s);
      TB_CHECK_MSG(mt.max_disp < 0.01, "%s at 20 degrees moved %g", models[k], mt.max_disp);
    }
    tb_sim_destroy(&s);
    if (run_scene(&s, "slope", models[k], "amplitude=35", 1) == 0) {
      double a = 35 * M_PI / 180, want = 0.5 * 9.81 * (sin(a) - 0.4 * cos(a));
      tb_sim_metrics mt = tb_sim_measure(&s);
      TB_CHECK_MSG(fabs(mt.rms_disp - want) < 0.05 * want, "%s at 35 degrees slid %g, rigid %g",
                   models[k], mt.rms_disp, want);
    }
    tb_sim_destroy(&s);
  }
}

/* Free fall of a cube for 0.5 s at step h: the error of the centre's drop
 * against g t^2 / 2, and the last velocity's error against g t. */
static void free_fall(const char *integrator, double h, double *xerr, double *verr) {
  tb_mesh m = cube();
  char kv[64];
  snprintf(kv, sizeof kv, "integrator=%s", integrator);
  tb_settings set = tb_test_settings(kv);
  tb_model md;
  tb_error err;
  TB_CHECK(tb_model_create(&md, "pbd-stvk", &m, &set, &err) == 0);
  tb_step st = still(h);
  st.gravity = tb_v3(0, 0, -9.81);
  int n = (int)lround(0.5 / h);
  for (int k = 0; k < n; k++) TB_CHECK(tb_model_step(&md, &st, &err) == 0);
  double t = n * h;
  *xerr = fabs(tb_model_positions(&md)[0].z - m.x[0].z + 0.5 * 9.81 * t * t);
  *verr = fabs(tb_model_velocities(&md)[0].z + 9.81 * t);
  tb_model_destroy(&md);
  tb_mesh_free(&m);
}

/* bdf2: the velocity is exact (positions on a parabola), the drop's error
 * second order in h; euler first order; the patent's pair falls at 2 g. */
static void integrator_orders(void) {
  double x1, v1, x2, v2;
  free_fall("bdf2", 0.01, &x1, &v1);
  free_fall("bdf2", 0.005, &x2, &v2);
  TB_CHECK_MSG(v1 < 1e-10 && v2 < 1e-10, "bdf2 velocity errors %g %g", v1, v2);
  double order = log2(x1 / x2);
  printf("  free fall, 0.5 s: bdf2 drop error %.3g (h 0.01), %.3g (h 0.005): order %.2f\n", x1, x2,
         order);
  TB_CHECK_MSG(fabs(order - 2) < 0.1, "bdf2 order %g", order);
  free_fall("euler", 0.01, &x1, &v1);
  free_fall("euler", 0.005, &x2, &v2);
  order = log2(x1 / x2);
  printf("  free fall, 0.5 s: euler drop error %.3g, %.3g: order %.2f\n", x1, x2, order);
  TB_CHECK_MSG(fabs(order - 1) < 0.1, "euler order %g", order);
  free_fall("patent", 0.005, &x1, &v1);
  double v = 9.81 * 0.5, ratio = (v + v1) / v;
  printf("  free fall, 0.5 s: the patent's eqs 2-3 + BDF2 velocity: speed %.3f x g t\n", ratio);
  TB_CHECK_MSG(fabs(ratio - 2) < 0.02, "patent speed ratio %g", ratio);
}

/* The slab schedule (models/tet_slabs.c) on beams long enough for several
 * slabs: every tet in exactly one task, the tasks of a phase sharing no
 * node, the node numbering a permutation, and a mesh too small for two
 * slabs one task. */
static void slab_schedule_partitions(void) {
  static const int cells[][3] = {{80, 5, 5}, {48, 8, 8}, {4, 2, 2}};
  for (int m = 0; m < 3; m++) {
    tb_mesh mesh;
    tb_error err;
    if (tb_beam(cells[m][0], cells[m][1], cells[m][2], cells[m][0], cells[m][1], cells[m][2], &mesh,
                &err)) {
      TB_CHECK_MSG(0, "%s", err.msg);
      continue;
    }
    tb_tet_slabs sl;
    if (tb_tet_slabs_build(&mesh, TB_SWEEP_SLABS, &sl, &err)) {
      TB_CHECK_MSG(0, "%s", err.msg);
      tb_mesh_free(&mesh);
      continue;
    }
    int nv = mesh.nv, nt = mesh.ntet;
    int *seen = calloc((size_t)nt, sizeof(int)), *owner = malloc(sizeof(int) * (size_t)nv);
    int perm_ok = 1, once = 1, disjoint = 1;
    for (int n = 0; n < nv; n++)
      perm_ok &= sl.old[n] >= 0 && sl.old[n] < nv && sl.nw[sl.old[n]] == n;
    TB_CHECK(sl.task[0] == 0 && sl.task[sl.ntasks] == nt && sl.phase[0] == 0 &&
             sl.phase[4] == sl.ntasks);
    for (int k = 0; k < nt; k++) seen[sl.order[k]]++;
    for (int t = 0; t < nt; t++) once &= seen[t] == 1;
    for (int ph = 0; ph < 4; ph++) {
      for (int n = 0; n < nv; n++) owner[n] = -1;
      for (int q = sl.phase[ph]; q < sl.phase[ph + 1]; q++)
        for (int k = sl.task[q]; k < sl.task[q + 1]; k++)
          for (int j = 0; j < 4; j++) {
            int n = mesh.tet[4 * sl.order[k] + j];
            disjoint &= owner[n] < 0 || owner[n] == q;
            owner[n] = q;
          }
    }
    printf("  beam %dx%dx%d: %d tets, %d slabs, %d tasks, wide %d\n", cells[m][0], cells[m][1],
           cells[m][2], nt, sl.nslabs, sl.ntasks, sl.task[sl.ntasks] - sl.task[sl.phase[3]]);
    TB_CHECK_MSG(perm_ok && once && disjoint, "beam %d: permutation %d, once %d, disjoint %d", m,
                 perm_ok, once, disjoint);
    TB_CHECK_MSG(m == 2 ? sl.nslabs == 1 && sl.ntasks == 1 : sl.nslabs >= 4, "beam %d: %d slabs", m,
                 sl.nslabs);
    free(seen), free(owner);
    tb_tet_slabs_free(&sl);
    tb_mesh_free(&mesh);
  }
}

/* Bit-identical positions and velocities for 1 and 2 threads: on the
 * liver dropped on the ground (the SOFA liver when ../shared/data has it:
 * one slab), on a generated liver of 12.8k tets dropped on the ground (16
 * slabs, the ground projected between sweeps) and on it stretched. */
static void threads_identical(void) {
  const char *models[] = {"pbd-stvk", "xpbd-stvk"};
  char drop[600];
  snprintf(drop, sizeof drop, "%s/drop-generated.ini", tb_test_tmpdir());
  FILE *f = fopen(drop, "w");
  TB_CHECK(f != NULL);
  if (!f) return;
  fprintf(f,
          "[scene]\ndt = 0.005\nduration = 1\ngravity = 9.81\n[mesh]\ngenerate = liver\n"
          "nodes = 2650\nbottom = 0,0,0.05\n[ground]\npoint = 0,0,0\nnormal = 0,0,1\n"
          "mu_s = 0.6\nmu_k = 0.5\n");
  fclose(f);
  const char *scenes[][2] = {{"liver-drop", ""}, {drop, ""}, {"liver-stretch", "nodes=2650"}};
  for (int c = 0; c < 3; c++)
    for (int k = 0; k < 2; k++) {
      tb_sim a, b;
      tb_threads_set(1);
      int ra = run_scene(&a, scenes[c][0], models[k], scenes[c][1], 0.6);
      tb_threads_set(2);
      int rb = run_scene(&b, scenes[c][0], models[k], scenes[c][1], 0.6);
      size_t bytes = sizeof(tb_vec3) * (size_t)a.mesh.nv;
      if (!ra && !rb)
        TB_CHECK_MSG(
            !memcmp(tb_model_positions(&a.model), tb_model_positions(&b.model), bytes) &&
                !memcmp(tb_model_velocities(&a.model), tb_model_velocities(&b.model), bytes),
            "%s on %s: 1 and 2 threads differ", models[k], scenes[c][0]);
      tb_sim_destroy(&a), tb_sim_destroy(&b);
    }
  tb_threads_set(0);
}

/* A run beyond its velocity bound stops and says why. */
static void unstable_reported(void) {
  TB_CHECK(tb_test_cli_run("simulate --scene liver-drop --model pbd-stvk --set vmax=1") == 1);
  TB_CHECK_MSG(strstr(tb_test_out, "status: unstable (pbd-stvk: unstable at t = ") &&
                   strstr(tb_test_out, "beyond bound"),
               "%s", tb_test_out);
}

const tb_test_case tb_tests_pbd[] = {
    {"gradient_matches_finite_differences", gradient_matches_finite_differences},
    {"rest_and_rigid_motion", rest_and_rigid_motion},
    {"projection_lowers_energy", projection_lowers_energy},
    {"inverted_tet_restored", inverted_tet_restored},
    {"ground_holds", ground_holds},
    {"damping_damps", damping_damps},
    {"slope_sticks_and_slides", slope_sticks_and_slides},
    {"integrator_orders", integrator_orders},
    {"slab_schedule_partitions", slab_schedule_partitions},
    {"threads_identical", threads_identical},
    {"unstable_reported", unstable_reported},
    {0, 0},
};
