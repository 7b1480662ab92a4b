/* Tests of meshless shape matching (models/sm.c, models/sm_clusters.c;
 * Müller et al. 2005, thesis §3.4): invariance under rigid motions, exact
 * rigid/affine/quadratic goals, unconditional stability (eq. 3-42), momentum
 * conservation, clusters, prescribed nodes, determinism and point clouds.
 * The tests set a model's state by writing through the arrays that
 * tb_model_positions/velocities return (the model's own arrays). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "tb_test.h"
#include "tb_test_models.h"
#include "core/tb_rng.h"
#include "meshgen/tb_meshgen.h"
#include "models/tb_model.h"
#include "models/tb_sm.h"

static const char *const mode_name[] = {"rigid", "linear", "quadratic"};

/* The 4 x 1 x 1 beam of 8 x 2 x 2 cubes: 81 nodes, 384 tets. */
static tb_mesh beam(void) {
  tb_mesh m;
  tb_error err;
  memset(&m, 0, sizeof m);
  TB_CHECK_MSG(tb_beam(4, 1, 1, 8, 2, 2, &m, &err) == 0, "%s", err.msg);
  return m;
}

/* Settings for the beam: 4 overlapping regions of radius 1.5 (with 1.2 one
 * region shares only 2 nodes with the rest: a hinge, a zero-energy mode). */
static tb_settings beam_def(int mode, int cluster_mode) {
  tb_settings d = tb_test_settings("node_mass=0 clusters=4 radius=1.5"); /* density masses */
  tb_settings_setd(&d, "sm_mode", mode, NULL),
      tb_settings_setd(&d, "cluster_mode", cluster_mode, NULL);
  return d;
}

/* tb_sm_clusters_build with the cluster settings of d. */
static int build(const tb_mesh *mesh, const tb_settings *d, tb_sm_clusters *cl, tb_error *err) {
  double mode = -1, n = 0, r = 0;
  TB_CHECK(tb_model_setting("sm", d, "cluster_mode", &mode) == 0);
  TB_CHECK(tb_model_setting("sm", d, "clusters", &n) == 0);
  TB_CHECK(tb_model_setting("sm", d, "radius", &r) == 0);
  return tb_sm_clusters_build(mesh, (int)mode, (int)n, r, cl, err);
}

static int create(tb_model *m, const tb_mesh *mesh, const tb_settings *d) {
  tb_error err;
  int rc = tb_model_create(m, "sm", mesh, d, &err);
  TB_CHECK_MSG(rc == 0, "create: %s", err.msg);
  return rc;
}

static tb_vec3 *xs(tb_model *m) { return (tb_vec3 *)tb_model_positions(m); }
static tb_vec3 *vs(tb_model *m) { return (tb_vec3 *)tb_model_velocities(m); }

/* Random vectors, drawn in a fixed order (argument evaluation order is not). */
static tb_vec3 normal3(tb_rng *r, double s) {
  double x = tb_rng_normal(r), y = tb_rng_normal(r), z = tb_rng_normal(r);
  return tb_v3(s * x, s * y, s * z);
}
static tb_vec3 box3(tb_rng *r, double h) {
  double x = tb_rng_range(r, -h, h), y = tb_rng_range(r, -h, h), z = tb_rng_range(r, -h, h);
  return tb_v3(x, y, z);
}

static tb_step no_forces(double dt) {
  tb_step s = {0};
  memset(&s, 0, sizeof s);
  s.dt = dt;
  return s;
}

static tb_vec3 centroid(const tb_vec3 *x, int n) {
  tb_vec3 c = tb_v3(0, 0, 0);
  for (int i = 0; i < n; i++) c = tb_add(c, x[i]);
  return tb_scale(c, 1.0 / n);
}

/* RMS distance of x from the best rigid motion of the rest shape (equal
 * weights): the shape error up to a rigid motion. */
static double shape_error(const tb_vec3 *x0, const tb_vec3 *x, int n) {
  tb_vec3 c0 = centroid(x0, n), c = centroid(x, n);
  tb_mat3 a;
  memset(&a, 0, sizeof a);
  for (int i = 0; i < n; i++) {
    tb_vec3 p = tb_sub(x[i], c), q = tb_sub(x0[i], c0);
    for (int r = 0; r < 3; r++)
      for (int k = 0; k < 3; k++) a.m[r][k] += tb_comp(p, r) * tb_comp(q, k);
  }
  tb_mat3 rot = tb_m3_polar(a);
  double e = 0;
  for (int i = 0; i < n; i++) {
    tb_vec3 g = tb_add(c, tb_m3_mulv(rot, tb_sub(x0[i], c0)));
    e += tb_dot(tb_sub(g, x[i]), tb_sub(g, x[i]));
  }
  return sqrt(e / n);
}

/* 1. Rigid motions of the rest shape are rest states in every variant. */
static void rigid_motion_invariance(void) {
  tb_mesh mesh = beam();
  tb_mat3 rot = tb_m3_rotation(tb_v3(0.3, -0.5, 0.8), M_PI / 2);
  tb_vec3 shift = tb_v3(1.5, -2.0, 3.0);
  for (int mode = TB_SM_RIGID; mode <= TB_SM_QUADRATIC; mode++)
    for (int variant = 0; variant < 3; variant++) { /* regions, one cluster, tets */
      tb_settings d = beam_def(mode, variant == 2 ? TB_CLUSTER_TETS : TB_CLUSTER_REGIONS);
      if (variant == 1) tb_settings_setd(&d, "clusters", 1, NULL);
      tb_model m;
      if (create(&m, &mesh, &d)) continue;
      tb_vec3 *x = xs(&m);
      for (int i = 0; i < mesh.nv; i++) x[i] = tb_add(tb_m3_mulv(rot, mesh.x[i]), shift);
      tb_step s = no_forces(0.01);
      tb_test_steps(&m, &s, 20);
      double dx = 0, vmax = 0;
      for (int i = 0; i < mesh.nv; i++) {
        dx = fmax(dx, tb_dist(x[i], tb_add(tb_m3_mulv(rot, mesh.x[i]), shift)));
        vmax = fmax(vmax, tb_len(tb_model_velocities(&m)[i]));
      }
      TB_CHECK_MSG(dx <= 1e-9 && vmax <= 1e-9, "%s, variant %d: moved %g, speed %g",
                   mode_name[mode], variant, dx, vmax);
      tb_model_destroy(&m);
    }
  tb_mesh_free(&mesh);
}

/* 2. alpha = 1, rigid, one cluster: one step snaps a perturbed body onto a
 * rigid motion of its rest shape. */
static void alpha_one_is_rigid(void) {
  tb_mesh mesh = beam();
  tb_settings d = beam_def(TB_SM_RIGID, TB_CLUSTER_REGIONS);
  tb_settings_setd(&d, "clusters", 1, NULL), tb_settings_setd(&d, "alpha", 1.0, NULL);
  tb_model m;
  if (create(&m, &mesh, &d)) return;
  tb_vec3 *x = xs(&m);
  tb_rng r = tb_rng_seed(11);
  for (int i = 0; i < mesh.nv; i++) x[i] = tb_add(mesh.x[i], box3(&r, 0.3));
  double before = 0, after = 0;
  for (int i = 0; i < mesh.nv; i++)
    for (int j = i + 1; j < mesh.nv; j++)
      before = fmax(before, fabs(tb_dist(x[i], x[j]) - tb_dist(mesh.x[i], mesh.x[j])));
  tb_step s = no_forces(0.02);
  tb_test_steps(&m, &s, 1);
  for (int i = 0; i < mesh.nv; i++)
    for (int j = i + 1; j < mesh.nv; j++)
      after = fmax(after, fabs(tb_dist(x[i], x[j]) - tb_dist(mesh.x[i], mesh.x[j])));
  TB_CHECK_MSG(before > 0.05, "the perturbation should change distances (%g)", before);
  TB_CHECK_MSG(after <= 1e-9, "pairwise distance error after one step %g", after);
  tb_model_destroy(&m);
  tb_mesh_free(&mesh);
}

/* Largest distance a model's nodes move in one step from x (no forces). */
static double one_step_motion(const tb_mesh *mesh, const tb_settings *d, const tb_vec3 *x) {
  tb_model m;
  if (create(&m, mesh, d)) return INFINITY;
  memcpy(xs(&m), x, sizeof(tb_vec3) * (size_t)mesh->nv);
  tb_step s = no_forces(0.01);
  tb_test_steps(&m, &s, 1);
  double dx = 0;
  for (int i = 0; i < mesh->nv; i++) dx = fmax(dx, tb_dist(tb_model_positions(&m)[i], x[i]));
  tb_model_destroy(&m);
  return dx;
}

/* 3. beta = 1 reproduces a volume-preserving affine deformation (linear)
 * and a quadratic one (quadratic) exactly: goals = positions. */
static void exact_affine_and_quadratic(void) {
  tb_mesh mesh = beam();
  int nv = mesh.nv;
  tb_vec3 *xa = malloc(sizeof(tb_vec3) * (size_t)nv), *xb = malloc(sizeof(tb_vec3) * (size_t)nv);
  tb_vec3 *xq = malloc(sizeof(tb_vec3) * (size_t)nv);
  tb_mat3 f; /* stretch, squash and shear, det 1, then a rotation */
  double fm[3][3] = {{1.5, 0.3, 0.0}, {0.0, 1.0 / 1.5, 0.2}, {0.1, 0.0, 1.0}};
  memcpy(f.m, fm, sizeof fm);
  double det = tb_m3_det(f);
  f = tb_m3_mul(tb_m3_rotation(tb_v3(1, 1, 0), 0.4), f);
  for (int i = 0; i < nv; i++) {
    tb_vec3 p = mesh.x[i];
    xa[i] = tb_add(tb_m3_mulv(f, tb_scale(p, 1.0 / cbrt(det))), tb_v3(0.2, 0.1, -0.3));
    xb[i] = tb_add(tb_m3_mulv(f, p), tb_v3(0.2, 0.1, -0.3)); /* det != 1 */
    tb_vec3 qq = tb_v3(0.05 * p.x * p.x + 0.1 * p.y * p.z, 0.08 * p.x * p.x - 0.05 * p.x * p.y,
                       0.04 * p.z * p.z + 0.06 * p.z * p.x + 0.03 * p.y * p.y);
    xq[i] = tb_add(p, qq);
  }
  for (int cm = 0; cm < 3; cm++) { /* regions, one cluster, tets */
    tb_settings d = beam_def(TB_SM_LINEAR, cm == 2 ? TB_CLUSTER_TETS : TB_CLUSTER_REGIONS);
    if (cm == 1) tb_settings_setd(&d, "clusters", 1, NULL);
    tb_settings_setd(&d, "beta", 1.0, NULL);
    double e = one_step_motion(&mesh, &d, xa);
    TB_CHECK_MSG(e <= 1e-9, "linear, clusters %d: volume-preserving affine moved %g", cm, e);
    e = one_step_motion(&mesh, &d, xb); /* volume change: A / cbrt(det A) differs */
    TB_CHECK_MSG(e > 1e-3, "linear, clusters %d: a volume change should be resisted (%g)", cm, e);
    tb_settings_setd(&d, "sm_mode", TB_SM_QUADRATIC, NULL);
    e = one_step_motion(&mesh, &d, xq);
    TB_CHECK_MSG(e <= 1e-9, "quadratic, clusters %d: quadratic deformation moved %g", cm, e);
    tb_settings_setd(&d, "beta", 0.5, NULL); /* a blend with R pulls towards the rest shape */
    e = one_step_motion(&mesh, &d, xq);
    TB_CHECK_MSG(e > 1e-3, "quadratic, beta 0.5, clusters %d: moved only %g", cm, e);
  }
  tb_settings d = beam_def(TB_SM_LINEAR, TB_CLUSTER_REGIONS); /* linear cannot bend */
  tb_settings_setd(&d, "clusters", 1, NULL), tb_settings_setd(&d, "beta", 1.0, NULL);
  TB_CHECK(one_step_motion(&mesh, &d, xq) > 1e-3);
  free(xa), free(xb), free(xq);
  tb_mesh_free(&mesh);
}

/* 4. dt = 1 and a tenfold blow-up: no NaN, bounded, back to the rest shape.
 * The bound: momentum is zero and kept, so the centre of mass stays put; a
 * cluster's goals are its current centre plus a rigid image of the rest
 * shape or a least-squares fit of the current cloud (never wider than it);
 * with the goal fixed, eq. 3-42's iteration matrix on (h v, x - g) has
 * sup_n |M^n| = 1.62 for alpha = 0.72 (damping only shrinks it). So nodes
 * stay within about 1.62 * 2 of the starting radius: 4x is a safe bound
 * that a blow-up would pass by orders of magnitude. */
static void unconditional_stability(void) {
  tb_mesh mesh = beam();
  int nv = mesh.nv;
  tb_vec3 c0 = centroid(mesh.x, nv);
  double r0 = 0;
  for (int i = 0; i < nv; i++) r0 = fmax(r0, tb_dist(mesh.x[i], c0));
  for (int mode = TB_SM_RIGID; mode <= TB_SM_QUADRATIC; mode++)
    for (int cm = 0; cm < 2; cm++) {
      tb_settings d = beam_def(mode, cm ? TB_CLUSTER_TETS : TB_CLUSTER_REGIONS);
      tb_settings_setd(&d, "sm_damping", 0.1, NULL);
      tb_model m;
      if (create(&m, &mesh, &d)) continue;
      tb_vec3 *x = xs(&m);
      tb_rng r = tb_rng_seed(3);
      for (int i = 0; i < nv; i++) /* x10 about the centroid, plus noise of the beam's size */
        x[i] = tb_add(tb_add(c0, tb_scale(tb_sub(mesh.x[i], c0), 10.0)), normal3(&r, 1.0));
      tb_vec3 c = centroid(x, nv);
      double rstart = 0, rmax = 0;
      for (int i = 0; i < nv; i++) rstart = fmax(rstart, tb_dist(x[i], c));
      tb_step s = no_forces(1.0);
      int finite = 1;
      for (int k = 0; k < 1000 && finite; k++) {
        if (tb_test_steps(&m, &s, 1)) break;
        for (int i = 0; i < nv; i++) {
          finite &= tb_isfinite3(x[i]);
          rmax = fmax(rmax, tb_dist(x[i], c));
        }
      }
      double err = shape_error(mesh.x, x, nv);
      TB_CHECK_MSG(finite, "%s/%d: NaN", mode_name[mode], cm);
      TB_CHECK_MSG(rmax < 4.0 * rstart, "%s/%d: reached %g from the centre (start %g)",
                   mode_name[mode], cm, rmax, rstart);
      TB_CHECK_MSG(err < 1e-6 * r0, "%s/%d: shape error %g after 1000 steps", mode_name[mode], cm,
                   err);
      tb_model_destroy(&m);
    }
  tb_mesh_free(&mesh);
}

/* Total momentum and centre of mass. */
static void momentum(const tb_mesh *mesh, const tb_model *m, tb_vec3 *p, tb_vec3 *cm,
                     double *mtot) {
  const double *mass = tb_model_masses(m);
  *p = *cm = tb_v3(0, 0, 0), *mtot = 0;
  for (int i = 0; i < mesh->nv; i++) {
    *p = tb_madd(*p, mass[i], tb_model_velocities(m)[i]);
    *cm = tb_madd(*cm, mass[i], tb_model_positions(m)[i]);
    *mtot += mass[i];
  }
  *cm = tb_scale(*cm, 1.0 / *mtot);
}

/* 5. Free fall of a deforming body: the matching forces sum to zero, so the
 * momentum grows by h (M g + sum f) per step and the centre of mass follows
 * symplectic Euler: c_n = c_0 + n h v_0 + h^2 n (n + 1) / 2 a. */
static void free_fall_momentum(void) {
  tb_mesh mesh = beam();
  int nv = mesh.nv;
  tb_vec3 *force = malloc(sizeof(tb_vec3) * (size_t)nv);
  tb_rng r = tb_rng_seed(5);
  tb_vec3 fsum = tb_v3(0, 0, 0);
  for (int i = 0; i < nv; i++) {
    force[i] = normal3(&r, 1.0);
    fsum = tb_add(fsum, force[i]);
  }
  for (int mode = TB_SM_RIGID; mode <= TB_SM_QUADRATIC; mode++)
    for (int cm = 0; cm < 2; cm++) {
      tb_settings d = beam_def(mode, cm ? TB_CLUSTER_TETS : TB_CLUSTER_REGIONS);
      tb_model m;
      if (create(&m, &mesh, &d)) continue;
      tb_vec3 *x = xs(&m), *v = vs(&m), v0 = tb_v3(0.5, 0.2, -0.1);
      for (int i = 0; i < nv; i++) {
        x[i] = tb_add(mesh.x[i], normal3(&r, 0.2));
        v[i] = v0;
      }
      tb_vec3 p0, c0, p, c;
      double mt;
      momentum(&mesh, &m, &p0, &c0, &mt);
      tb_vec3 a = tb_add(tb_v3(0, -9.81, 0), tb_scale(fsum, 1.0 / mt));
      tb_step s = no_forces(0.01);
      s.gravity = tb_v3(0, -9.81, 0), s.force = force;
      int n = 100;
      tb_test_steps(&m, &s, n);
      momentum(&mesh, &m, &p, &c, &mt);
      tb_vec3 pe = tb_scale(tb_madd(v0, n * s.dt, a), mt);
      tb_vec3 ce = tb_madd(tb_madd(c0, n * s.dt, v0), s.dt * s.dt * n * (n + 1) / 2.0, a);
      TB_CHECK_MSG(tb_dist(p, pe) <= 1e-9 * tb_len(pe), "%s/%d: momentum off by %g",
                   mode_name[mode], cm, tb_dist(p, pe));
      TB_CHECK_MSG(tb_dist(c, ce) <= 1e-9, "%s/%d: centre of mass off by %g", mode_name[mode], cm,
                   tb_dist(c, ce));
      TB_CHECK_MSG(shape_error(mesh.x, x, nv) > 1e-4, "%s/%d: the body should be deforming",
                   mode_name[mode], cm);
      tb_model_destroy(&m);
    }
  free(force);
  tb_mesh_free(&mesh);
}

/* Every node in some cluster, members ascending and in range. */
static void check_cover(const tb_sm_clusters *cl, int nv) {
  char *seen = calloc((size_t)nv, 1);
  int bad = 0;
  for (int c = 0; c < cl->n; c++) {
    bad += cl->start[c + 1] <= cl->start[c];
    for (int k = cl->start[c]; k < cl->start[c + 1]; k++) {
      int i = cl->node[k];
      if (i < 0 || i >= nv || (k > cl->start[c] && i <= cl->node[k - 1]))
        bad++;
      else
        seen[i] = 1;
    }
  }
  int missing = 0;
  for (int i = 0; i < nv; i++) missing += !seen[i];
  TB_CHECK_MSG(!bad && !missing, "%d bad entries or empty clusters, %d nodes in no cluster", bad,
               missing);
  free(seen);
}

/* 6. Clusters: regions, one cluster, tets, and the liver with the defaults. */
static void clusters(void) {
  tb_mesh mesh = beam();
  tb_error err;
  tb_sm_clusters cl;
  tb_settings d = beam_def(TB_SM_QUADRATIC, TB_CLUSTER_REGIONS);
  TB_CHECK(build(&mesh, &d, &cl, &err) == 0);
  TB_CHECK(cl.n == 4);
  check_cover(&cl, mesh.nv);
  int overlap = cl.start[cl.n] > mesh.nv;
  TB_CHECK_MSG(overlap, "radius 1.5 regions should overlap (%d members)", cl.start[cl.n]);
  tb_sm_clusters_free(&cl);
  tb_settings_setd(&d, "radius", 0.01,
                   NULL); /* regions hold only their centres: the rest join the nearest */
  TB_CHECK(build(&mesh, &d, &cl, &err) == 0);
  TB_CHECK(cl.n == 4 && cl.start[cl.n] == mesh.nv);
  check_cover(&cl, mesh.nv);
  tb_sm_clusters_free(&cl);
  tb_settings_setd(&d, "clusters", 1, NULL),
      tb_settings_setd(&d, "radius", 0.01, NULL); /* one cluster: all nodes, radius ignored */
  TB_CHECK(build(&mesh, &d, &cl, &err) == 0);
  TB_CHECK(cl.n == 1 && cl.start[1] == mesh.nv);
  tb_sm_clusters_free(&cl);
  tb_settings_setd(&d, "clusters", 1000, NULL); /* more clusters than nodes: one per node */
  TB_CHECK(build(&mesh, &d, &cl, &err) == 0);
  TB_CHECK(cl.n == mesh.nv);
  check_cover(&cl, mesh.nv);
  tb_sm_clusters_free(&cl);
  tb_settings_setd(&d, "cluster_mode", TB_CLUSTER_TETS, NULL); /* node + tet neighbours */
  TB_CHECK(build(&mesh, &d, &cl, &err) == 0);
  TB_CHECK(cl.n == mesh.nv);
  check_cover(&cl, mesh.nv);
  int *edges = NULL, ne = tb_mesh_edges(&mesh, &edges), *deg = calloc((size_t)mesh.nv, sizeof(int));
  for (int e = 0; e < 2 * ne; e++) deg[edges[e]]++;
  int wrong = 0;
  for (int i = 0; i < mesh.nv; i++) {
    int has_self = 0;
    for (int k = cl.start[i]; k < cl.start[i + 1]; k++) has_self |= cl.node[k] == i;
    wrong += !has_self || cl.start[i + 1] - cl.start[i] != deg[i] + 1;
  }
  TB_CHECK_MSG(!wrong, "%d tet clusters are not node + neighbours", wrong);
  free(edges), free(deg);
  tb_sm_clusters_free(&cl);
  tb_mesh cloud = mesh; /* tets mode on a point cloud is an error */
  cloud.ntet = 0, cloud.ntri = 0;
  tb_settings_setd(&d, "node_mass", 1, NULL);
  TB_CHECK(build(&cloud, &d, &cl, &err) != 0 && strstr(err.msg, "tets"));
  tb_model m;
  TB_CHECK(tb_model_create(&m, "sm", &cloud, &d, &err) != 0 && strstr(err.msg, "tets"));
  int keep = mesh.tet[5]; /* bad input is an error, not a crash */
  mesh.tet[5] = mesh.nv;
  TB_CHECK(tb_model_create(&m, "sm", &mesh, &d, &err) != 0 && strstr(err.msg, "outside"));
  mesh.tet[5] = keep, mesh.x[7].y = NAN;
  TB_CHECK(tb_model_create(&m, "sm", &mesh, &d, &err) != 0 && strstr(err.msg, "non-finite"));
  tb_mesh_free(&mesh);

  /* the liver with the thesis's settings */
  tb_liver_def ld = tb_liver_default_def();
  tb_mesh surf, tets;
  memset(&surf, 0, sizeof surf), memset(&tets, 0, sizeof tets);
  TB_CHECK_MSG(tb_liver_surface(&ld, &surf, &err) == 0, "%s", err.msg);
  TB_CHECK_MSG(tb_liver_tets(&ld, &surf, &tets, &err) == 0, "%s", err.msg);
  tb_settings dl = tb_test_settings("node_mass=0");
  if (create(&m, &tets, &dl) == 0) {
    int n = 0;
    double mean = 0;
    TB_CHECK(tb_sm_cluster_stats(&m, &n, &mean) == 0);
    TB_CHECK_MSG(n == 50 && mean >= 25 && mean <= 200, "liver: %d clusters, %g members", n, mean);
    printf("sm liver (%d nodes), defaults: %d clusters, %.1f members per cluster (thesis: 96)\n",
           tets.nv, n, mean);
    TB_CHECK(isnan(tb_model_energy(&m)));
    tb_model_destroy(&m);
  }
  TB_CHECK(build(&tets, &dl, &cl, &err) == 0);
  check_cover(&cl, tets.nv);
  tb_sm_clusters_free(&cl);
  tb_model other; /* not an sm model */
  memset(&other, 0, sizeof other);
  TB_CHECK(tb_sm_cluster_stats(&other, NULL, NULL) == -1);
  other.cls = tb_model_find("fem"), other.self = &dl;
  TB_CHECK(tb_sm_cluster_stats(&other, NULL, NULL) == -1);
  tb_mesh_free(&surf), tb_mesh_free(&tets);
}

/* 7. Prescribed nodes end exactly at fixed_x with velocity (fixed_x - x_old)
 * / dt; the set may change between steps; bad lists are errors. */
static void prescribed_nodes(void) {
  tb_mesh mesh = beam();
  tb_settings d = beam_def(TB_SM_QUADRATIC, TB_CLUSTER_REGIONS);
  tb_model m;
  if (create(&m, &mesh, &d)) return;
  tb_vec3 *x = xs(&m);
  tb_error err;
  int sets[3][4] = {{0, 1, 2, 80}, {5, 40, 0, 0}, {0}};
  int counts[3] = {4, 2, 0};
  tb_vec3 fx[4], xold[81];
  tb_step s = no_forces(0.01);
  s.gravity = tb_v3(0, -9.81, 0);
  for (int round = 0; round < 9; round++) {
    int k = round % 3;
    s.nfixed = counts[k], s.fixed = sets[k], s.fixed_x = fx;
    for (int j = 0; j < s.nfixed; j++)
      fx[j] = tb_add(mesh.x[sets[k][j]], tb_v3(0.05 * round, 0.02 * j, -0.01 * round));
    memcpy(xold, x, sizeof xold);
    TB_CHECK(tb_model_step(&m, &s, &err) == 0);
    for (int j = 0; j < s.nfixed; j++) {
      int i = sets[k][j];
      TB_CHECK(x[i].x == fx[j].x && x[i].y == fx[j].y && x[i].z == fx[j].z);
      tb_vec3 ve = tb_scale(tb_sub(fx[j], xold[i]), 1.0 / s.dt);
      TB_CHECK_NEAR(tb_dist(tb_model_velocities(&m)[i], ve), 0, 1e-12 * (1 + tb_len(ve)));
    }
  }
  TB_CHECK(x[50].y < mesh.x[50].y); /* a free node fell */
  int unsorted[2] = {3, 2}, dup[2] = {4, 4}, out[1] = {81};
  s.fixed_x = fx, s.nfixed = 2, s.fixed = unsorted;
  TB_CHECK(tb_model_step(&m, &s, &err) != 0);
  s.fixed = dup;
  TB_CHECK(tb_model_step(&m, &s, &err) != 0);
  s.nfixed = 1, s.fixed = out;
  TB_CHECK(tb_model_step(&m, &s, &err) != 0 && strstr(err.msg, "ascending"));
  tb_model_destroy(&m);
  tb_mesh_free(&mesh);
}

/* A random point cloud in [0,2]x[0,1]x[0,1] (z = 0 when flat). */
static tb_mesh cloud(int n, int flat, uint64_t seed) {
  tb_mesh m;
  memset(&m, 0, sizeof m);
  m.nv = n;
  m.x = malloc(sizeof(tb_vec3) * (size_t)n);
  tb_rng r = tb_rng_seed(seed);
  for (int i = 0; i < n; i++) {
    double x = tb_rng_range(&r, 0, 2), y = tb_rng_range(&r, 0, 1);
    m.x[i] = tb_v3(x, y, flat ? 0.0 : tb_rng_range(&r, 0, 1));
  }
  return m;
}

/* Perturbs, then runs n steps with gravity, forces and a prescribed node. */
static void shake(tb_model *m, const tb_mesh *mesh, int n) {
  tb_vec3 *x = xs(m);
  tb_rng r = tb_rng_seed(9);
  for (int i = 0; i < mesh->nv; i++) x[i] = tb_add(x[i], normal3(&r, 0.1));
  tb_vec3 *f = calloc((size_t)mesh->nv, sizeof(tb_vec3));
  f[mesh->nv - 1] = tb_v3(3, 0, 1);
  int fixed[1] = {0};
  tb_vec3 fx[1] = {mesh->x[0]};
  tb_step s = no_forces(0.01);
  s.gravity = tb_v3(0, 0, -9.81), s.force = f, s.nfixed = 1, s.fixed = fixed, s.fixed_x = fx;
  tb_test_steps(m, &s, n);
  free(f);
}

/* 8. Same input, byte-identical output; point clouds with node_mass. */
static void determinism_and_point_clouds(void) {
  tb_mesh mesh = beam();
  for (int mode = TB_SM_RIGID; mode <= TB_SM_QUADRATIC; mode++) {
    tb_settings d = beam_def(mode, TB_CLUSTER_REGIONS);
    tb_model a, b;
    if (create(&a, &mesh, &d) || create(&b, &mesh, &d)) return;
    shake(&a, &mesh, 100), shake(&b, &mesh, 100);
    size_t bytes = sizeof(tb_vec3) * (size_t)mesh.nv;
    TB_CHECK(!memcmp(tb_model_positions(&a), tb_model_positions(&b), bytes));
    TB_CHECK(!memcmp(tb_model_velocities(&a), tb_model_velocities(&b), bytes));
    TB_CHECK(memcmp(tb_model_positions(&a), mesh.x, bytes)); /* it did move */
    tb_model_destroy(&a), tb_model_destroy(&b);
  }
  tb_mesh_free(&mesh);

  tb_error err;
  for (int flat = 0; flat < 2; flat++) { /* flat: coplanar particles, singular A_qq */
    tb_mesh pc = cloud(300, flat, 21 + (uint64_t)flat);
    for (int mode = TB_SM_RIGID; mode <= TB_SM_QUADRATIC; mode++) {
      tb_settings d = tb_test_settings("node_mass=0 clusters=8 radius=0.5");
      tb_settings_setd(&d, "sm_mode", mode, NULL);
      tb_model m;
      TB_CHECK(tb_model_create(&m, "sm", &pc, &d, &err) != 0 && strstr(err.msg, "node_mass"));
      tb_settings_setd(&d, "node_mass", 1, NULL);
      if (create(&m, &pc, &d)) continue;
      int n;
      double mean;
      TB_CHECK(tb_sm_cluster_stats(&m, &n, &mean) == 0 && n == 8 && mean >= 300.0 / 8);
      tb_mat3 rot = tb_m3_rotation(tb_v3(2, -1, 0.5), M_PI / 2); /* rigid motion: at rest */
      tb_vec3 *x = xs(&m);
      for (int i = 0; i < pc.nv; i++) x[i] = tb_add(tb_m3_mulv(rot, pc.x[i]), tb_v3(1, 2, 3));
      tb_step s = no_forces(0.01);
      tb_test_steps(&m, &s, 10);
      double dx = 0;
      for (int i = 0; i < pc.nv; i++)
        dx = fmax(dx, tb_dist(x[i], tb_add(tb_m3_mulv(rot, pc.x[i]), tb_v3(1, 2, 3))));
      TB_CHECK_MSG(dx <= 1e-9, "cloud flat=%d %s: rigid motion moved %g", flat, mode_name[mode],
                   dx);
      shake(&m, &pc, 200);
      tb_health h = tb_model_health(&pc, x, tb_model_velocities(&m), 1e3, 0);
      TB_CHECK_MSG(h.ok, "cloud flat=%d %s: %s", flat, mode_name[mode], h.reason);
      tb_model_destroy(&m);
    }
    tb_mesh_free(&pc);
  }
}

const tb_test_case tb_tests_sm[] = {
    {"rigid_motion_invariance", rigid_motion_invariance},
    {"alpha_one_is_rigid", alpha_one_is_rigid},
    {"exact_affine_and_quadratic", exact_affine_and_quadratic},
    {"unconditional_stability", unconditional_stability},
    {"free_fall_momentum", free_fall_momentum},
    {"clusters", clusters},
    {"prescribed_nodes", prescribed_nodes},
    {"determinism_and_point_clouds", determinism_and_point_clouds},
    {0, 0},
};
