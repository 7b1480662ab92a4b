/* Tests of the patent's simplified meshless point set (models/meshless.c;
 * patent step 3 (2), eqs 4-8; Müller et al. 2004): linear fields
 * reproduced, rigid motion strain-free, momentum conserved, forces the
 * energy's gradient, an oscillating bar, a sagging block, a cut that
 * separates, degenerate stencils, determinism, timings. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "tb_test.h"
#include "core/tb_rng.h"
#include "core/tb_threads.h"
#include "core/tb_timer.h"
#include "models/tb_meshless.h"

#define S 0.01 /* sample spacing (m) */

/* An nx x ny x nz lattice of spacing S, each point moved by up to
 * jitter * S per axis (seeded). */
static tb_vec3 *lattice(int nx, int ny, int nz, double jitter, uint64_t seed) {
  tb_rng r = tb_rng_seed(seed);
  tb_vec3 *x = malloc(sizeof(tb_vec3) * (size_t)(nx * ny * nz));
  for (int k = 0, i = 0; k < nz; k++)
    for (int j = 0; j < ny; j++)
      for (int l = 0; l < nx; l++, i++) {
        double a = tb_rng_range(&r, -jitter, jitter), b = tb_rng_range(&r, -jitter, jitter);
        x[i] = tb_v3((l + a) * S, (j + b) * S, (k + tb_rng_range(&r, -jitter, jitter)) * S);
      }
  return x;
}

static tb_meshless *make(int n, const tb_vec3 *x, double E, tb_meshless_crosses c, void *ctx) {
  tb_error err = {{0}};
  tb_meshless *m = tb_meshless_create(n, x, NULL, E, 0.3, 1000, c, ctx, &err);
  TB_CHECK_MSG(m != NULL, "create: %s", err.msg);
  return m;
}

static double max_abs3(tb_mat3 a) {
  double r = 0;
  for (int i = 0; i < 3; i++)
    for (int j = 0; j < 3; j++) r = fmax(r, fabs(a.m[i][j]));
  return r;
}

static double max_len(const tb_vec3 *f, int n) {
  double r = 0;
  for (int i = 0; i < n; i++) r = fmax(r, tb_len(f[i]));
  return r;
}

/* The cut: the plane x = *(double *)ctx. */
static int plane_x(void *ctx, tb_vec3 a, tb_vec3 b) {
  double p = *(double *)ctx;
  return (a.x - p) * (b.x - p) < 0;
}

/* u = G X + t gives J - I = G (J[a][b] = dx_a/dX_b) at every active point,
 * and every interior point of the jittered lattice is active. */
static void linear_field_reproduced(void) {
  int nx = 7, n = nx * nx * nx;
  tb_vec3 *X = lattice(nx, nx, nx, 0.25, 1), *x = malloc(sizeof(tb_vec3) * (size_t)n);
  tb_meshless *m = make(n, X, 1e5, NULL, NULL);
  if (!m) return;
  tb_rng r = tb_rng_seed(2);
  tb_mat3 G;
  for (int a = 0; a < 3; a++)
    for (int b = 0; b < 3; b++) G.m[a][b] = 0.3 * tb_rng_normal(&r);
  tb_vec3 t = tb_v3(0.1, -0.2, 0.05);
  for (int i = 0; i < n; i++) x[i] = tb_add(tb_add(X[i], tb_m3_mulv(G, X[i])), t);
  tb_meshless_set_positions(m, x);
  double worst = 0;
  int active = 0, interior_inactive = 0;
  for (int i = 0; i < n; i++) {
    int l = i % nx, j = i / nx % nx, k = i / (nx * nx);
    int interior = l > 0 && j > 0 && k > 0 && l < nx - 1 && j < nx - 1 && k < nx - 1;
    if (!tb_meshless_active(m, i)) {
      interior_inactive += interior;
      continue;
    }
    active++;
    tb_mat3 D = tb_meshless_jacobian(m, i);
    for (int a = 0; a < 3; a++)
      for (int b = 0; b < 3; b++) worst = fmax(worst, fabs(D.m[a][b] - (a == b) - G.m[a][b]));
  }
  printf("linear field: %d/%d points active, max |J - I - G| = %.3g (|G| max %.3g)\n", active, n,
         worst, max_abs3(G));
  TB_CHECK_MSG(worst <= 1e-10 * max_abs3(G), "max |J - I - G| = %g", worst);
  TB_CHECK(interior_inactive == 0);
  TB_CHECK(active == n);
  tb_meshless_destroy(m);
  free(X), free(x);
}

/* x = R X + t: zero strain, energy and forces (relative to a 10% stretch). */
static void rigid_motion_strain_free(void) {
  int n = 6 * 5 * 4;
  tb_vec3 *X = lattice(6, 5, 4, 0.2, 3), *x = malloc(sizeof(tb_vec3) * (size_t)n);
  tb_vec3 *f = malloc(sizeof(tb_vec3) * (size_t)n);
  tb_meshless *m = make(n, X, 1e5, NULL, NULL);
  if (!m) return;
  for (int i = 0; i < n; i++) x[i] = tb_v3(1.1 * X[i].x, X[i].y, X[i].z);
  tb_meshless_set_positions(m, x);
  tb_meshless_forces(m, f);
  double fref = max_len(f, n), eref = tb_meshless_energy(m);
  tb_mat3 R = tb_m3_rotation(tb_v3(1, 2, -0.5), 1.3);
  for (int i = 0; i < n; i++) x[i] = tb_add(tb_m3_mulv(R, X[i]), tb_v3(0.3, -1, 2));
  tb_meshless_set_positions(m, x);
  tb_meshless_forces(m, f);
  double eps = 0;
  for (int i = 0; i < n; i++) eps = fmax(eps, max_abs3(tb_meshless_strain(m, i)));
  printf("rigid: max |eps| = %.3g, max |f| = %.3g (10%% stretch: %.3g), energy %.3g (%.3g)\n", eps,
         max_len(f, n), fref, tb_meshless_energy(m), eref);
  TB_CHECK(fref > 0 && eref > 0);
  TB_CHECK_MSG(eps <= 1e-10, "max |eps| = %g", eps);
  TB_CHECK_MSG(max_len(f, n) <= 1e-10 * fref, "max |f| = %g", max_len(f, n));
  TB_CHECK(tb_meshless_energy(m) <= 1e-10 * eref);
  tb_meshless_destroy(m);
  free(X), free(x), free(f);
}

/* After a random deformation the internal forces sum to zero, and so do
 * their moments (the energy is rotation invariant and f = -grad). */
static void momentum_conserved(void) {
  int n = 6 * 6 * 6;
  double cut = 2.5 * S;
  tb_vec3 *X = lattice(6, 6, 6, 0.2, 4), *x = lattice(6, 6, 6, 0.2, 4);
  tb_vec3 *f = malloc(sizeof(tb_vec3) * (size_t)n);
  tb_rng r = tb_rng_seed(5);
  for (int i = 0; i < n; i++)
    x[i] = tb_add(
        x[i], tb_scale(tb_v3(tb_rng_normal(&r), tb_rng_normal(&r), tb_rng_normal(&r)), 0.2 * S));
  for (int pass = 0; pass < 2; pass++) {
    tb_meshless *m = make(n, X, 1e5, pass ? plane_x : NULL, &cut);
    if (!m) break;
    tb_meshless_set_positions(m, x);
    tb_meshless_forces(m, f);
    tb_vec3 sum = tb_v3(0, 0, 0), torque = tb_v3(0, 0, 0);
    double mag = 0, tmag = 0;
    for (int i = 0; i < n; i++) {
      sum = tb_add(sum, f[i]), mag += tb_len(f[i]);
      torque = tb_add(torque, tb_cross(x[i], f[i])), tmag += tb_len(x[i]) * tb_len(f[i]);
    }
    printf("momentum (%s): |sum f| / sum |f| = %.3g, |sum x*f| / sum |x||f| = %.3g\n",
           pass ? "cut" : "whole", tb_len(sum) / mag, tb_len(torque) / tmag);
    TB_CHECK(mag > 0);
    TB_CHECK_MSG(tb_len(sum) <= 1e-12 * mag, "|sum f| = %g of %g", tb_len(sum), mag);
    TB_CHECK_MSG(tb_len(torque) <= 1e-12 * tmag, "|torque| = %g of %g", tb_len(torque), tmag);
    tb_meshless_destroy(m);
  }
  free(X), free(x), free(f);
}

/* f = -dE/dx by central differences on every coordinate, whole and cut. */
static void forces_are_energy_gradient(void) {
  int n = 5 * 5 * 5;
  double cut = 2.5 * S, h = 1e-7;
  tb_vec3 *X = lattice(5, 5, 5, 0.2, 6), *x = lattice(5, 5, 5, 0.2, 6);
  tb_vec3 *f = malloc(sizeof(tb_vec3) * (size_t)n);
  tb_rng r = tb_rng_seed(7);
  for (int i = 0; i < n; i++)
    x[i] = tb_add(
        x[i], tb_scale(tb_v3(tb_rng_normal(&r), tb_rng_normal(&r), tb_rng_normal(&r)), 0.15 * S));
  for (int pass = 0; pass < 2; pass++) {
    tb_meshless *m = make(n, X, 1e5, pass ? plane_x : NULL, &cut);
    if (!m) break;
    tb_meshless_set_positions(m, x);
    tb_meshless_forces(m, f);
    double worst = 0;
    for (int i = 0; i < n; i++)
      for (int c = 0; c < 3; c++) {
        double *p = c == 0 ? &x[i].x : (c == 1 ? &x[i].y : &x[i].z), p0 = *p;
        *p = p0 + h;
        tb_meshless_set_positions(m, x);
        double ep = tb_meshless_energy(m);
        *p = p0 - h;
        tb_meshless_set_positions(m, x);
        double em = tb_meshless_energy(m);
        *p = p0;
        worst = fmax(worst, fabs(-(ep - em) / (2 * h) - tb_comp(f[i], c)));
      }
    printf("gradient (%s): max |f + dE/dx| = %.3g, max |f| = %.3g\n", pass ? "cut" : "whole", worst,
           max_len(f, n));
    TB_CHECK_MSG(worst <= 1e-6 * max_len(f, n), "max |f + dE/dx| = %g of %g", worst, max_len(f, n));
    tb_meshless_destroy(m);
  }
  free(X), free(x), free(f);
}

/* Runs the bar of 12x3x3 points stretched 5% along x, free, for `steps`
 * steps of dt; returns the relative total-energy drift (max |E - E0| / E0),
 * -1 when a step fails, and the number of times its length crosses rest. */
static double bar_run(int integrator, double dt, int steps, int *crossings) {
  int n = 12 * 3 * 3;
  tb_vec3 *X = lattice(12, 3, 3, 0, 0), *x = malloc(sizeof(tb_vec3) * (size_t)n);
  tb_meshless *m = make(n, X, 1e5, NULL, NULL);
  if (!m) return free(X), free(x), -1;
  tb_meshless_set_integrator(m, integrator);
  for (int i = 0; i < n; i++) x[i] = tb_v3(1.05 * X[i].x, X[i].y, X[i].z);
  tb_meshless_set_positions(m, x);
  double e0 = tb_meshless_energy(m), drift = 0, L0 = 11 * S, prev = 1;
  *crossings = 0;
  for (int s = 0; s < steps; s++) {
    tb_error err;
    if (tb_meshless_step(m, dt, tb_v3(0, 0, 0), 0, NULL, NULL, &err)) {
      drift = -1;
      break;
    }
    const tb_vec3 *p = tb_meshless_positions(m);
    double L = 0;
    for (int k = 0; k < 9; k++) L += (p[12 * k + 11].x - p[12 * k].x) / 9;
    if ((L - L0) * prev < 0) ++*crossings, prev = L - L0;
    double e = tb_meshless_energy(m) + tb_meshless_kinetic(m);
    drift = fmax(drift, fabs(e - e0) / e0);
    if (!(drift < 1e3)) break;
  }
  tb_meshless_destroy(m);
  free(X), free(x);
  return drift;
}

/* A stretched bar (E 1e5 Pa, rho 1000, S 1 cm: c = 10 m/s) let go oscillates
 * (length through rest both ways, ~12 periods in 0.3 s) with bounded energy
 * at dt = 2e-4 s. Measured (max |E - E0| / E0 over 0.3 s): alternating
 * 0.3% at 1e-4, 1.25% at 2e-4, 19% at 8e-4, blows up at 1e-3; symplectic
 * Euler 3.8%, 8.5%, blows up at 8e-4. At 1.5e-3 s it blows up. */
static void bar_oscillates_stably(void) {
  int cross;
  double d = bar_run(TB_MESHLESS_ALTERNATING, 2e-4, 1500, &cross);
  printf("bar, alternating, dt 2e-4: energy drift %.3g, %d crossings of rest length\n", d, cross);
  TB_CHECK_MSG(d >= 0 && d < 0.02, "drift %g", d);
  TB_CHECK_MSG(cross >= 6, "%d crossings", cross);
  d = bar_run(TB_MESHLESS_SYMPLECTIC_EULER, 2e-4, 1500, &cross);
  printf("bar, symplectic Euler, dt 2e-4: energy drift %.3g, %d crossings\n", d, cross);
  TB_CHECK_MSG(d >= 0 && d < 0.12, "drift %g", d);
  TB_CHECK(cross >= 6);
  d = bar_run(TB_MESHLESS_ALTERNATING, 1.5e-3, 1500, &cross);
  printf("bar, alternating, dt 1.5e-3: energy drift %.3g\n", d);
  TB_CHECK_MSG(d < 0 || d > 1, "dt 1.5e-3 should be unstable: drift %g", d);
}

/* Driven ids and rest positions of the points with z < zmax. */
static int bottom(const tb_vec3 *X, int n, double zmax, int *ids, tb_vec3 *fx) {
  int k = 0;
  for (int i = 0; i < n; i++)
    if (X[i].z < zmax) ids[k] = i, fx[k++] = X[i];
  return k;
}

/* Runs `steps` steps holding the points below zmax at rest, under gravity. */
static int run_held(tb_meshless *m, double zmax, double dt, int steps) {
  int n = tb_meshless_count(m), *ids = malloc(sizeof(int) * (size_t)n), rc = 0;
  tb_vec3 *fx = malloc(sizeof(tb_vec3) * (size_t)n);
  int nf = bottom(tb_meshless_rest(m), n, zmax, ids, fx);
  for (int s = 0; s < steps && !rc; s++) {
    tb_error err;
    rc = tb_meshless_step(m, dt, tb_v3(0, 0, -9.81), nf, ids, fx, &err);
    TB_CHECK_MSG(rc == 0, "step %d: %s", s, err.msg);
  }
  free(ids), free(fx);
  return rc;
}

static double mean_z_above(const tb_meshless *m, double zmin) {
  const tb_vec3 *X = tb_meshless_rest(m), *x = tb_meshless_positions(m);
  double dz = 0;
  int k = 0;
  for (int i = 0; i < tb_meshless_count(m); i++)
    if (X[i].z > zmin) dz += x[i].z - X[i].z, k++;
  return dz / k;
}

/* A 6x6x5 block (E 1e4 Pa) on its held bottom layer sags under gravity and
 * comes to rest with damping 60/s: top-layer sag within 25% of a free
 * column's rho g H^2 / (2 E) = 0.785 mm (measured 0.80 mm: the held base
 * restrains lateral expansion, the free surfaces are softer; the patent's
 * strain, twice Green's, would give a quarter); speeds below 1e-6 m/s after
 * 1 s. */
static void block_sags_and_rests(void) {
  int n = 6 * 6 * 5;
  tb_vec3 *X = lattice(6, 6, 5, 0, 0);
  tb_meshless *m = make(n, X, 1e4, NULL, NULL);
  if (!m) return;
  tb_meshless_set_damping(m, 60);
  run_held(m, 0.5 * S, 5e-4, 1800);
  double sag1 = mean_z_above(m, 3.5 * S);
  run_held(m, 0.5 * S, 5e-4, 200);
  double sag = mean_z_above(m, 3.5 * S), ref = 1000 * 9.81 * (4 * S) * (4 * S) / (2 * 1e4);
  double vmax = max_len(tb_meshless_velocities(m), n);
  int held_moved = 0; /* driven points sit exactly at their prescribed positions */
  for (int i = 0; i < n; i++)
    if (X[i].z < 0.5 * S)
      held_moved += memcmp(&tb_meshless_positions(m)[i], &X[i], sizeof(tb_vec3)) != 0 ||
                    tb_len(tb_meshless_velocities(m)[i]) != 0;
  TB_CHECK(held_moved == 0);
  printf(
      "block: top sag %.4g mm (column formula %.4g mm), change over last 0.1 s %.3g mm, "
      "max speed %.3g m/s\n",
      -sag * 1e3, ref * 1e3, (sag - sag1) * 1e3, vmax);
  TB_CHECK_MSG(-sag > 0.75 * ref && -sag < 1.25 * ref, "sag %g, ref %g", -sag, ref);
  TB_CHECK_MSG(fabs(sag - sag1) < 1e-4 * ref, "still moving: %g", sag - sag1);
  TB_CHECK_MSG(vmax < 1e-6, "max speed %g", vmax);
  tb_meshless_destroy(m);
  free(X);
}

/* A cut through the middle of an 8x4x4 block: no link crosses it (at
 * creation, and by relink of the whole block: the same lists); with the
 * left half held the right half falls freely: its centre of mass drops
 * g T^2 / 2 (velocity Verlet is exact under constant acceleration) and it
 * stays undeformed. Without the cut it hangs on. */
static void cut_separates(void) {
  int n = 8 * 4 * 4;
  double cut = 3.5 * S, T = 0.1, fall = 0.5 * 9.81 * T * T;
  tb_vec3 *X = lattice(8, 4, 4, 0.1, 8);
  tb_meshless *a = make(n, X, 1e5, plane_x, &cut), *b = make(n, X, 1e5, NULL, NULL);
  if (!a || !b) return;
  int crossing = 0, crossing_whole = 0, same = 1;
  for (int i = 0; i < n; i++) {
    const int *l;
    int k = tb_meshless_neighbours(a, i, &l);
    for (int q = 0; q < k; q++) crossing += plane_x(&cut, X[i], X[l[q]]);
    k = tb_meshless_neighbours(b, i, &l);
    for (int q = 0; q < k; q++) crossing_whole += plane_x(&cut, X[i], X[l[q]]);
  }
  tb_meshless *c = make(n, X, 1e5, NULL, NULL);
  if (!c) return;
  tb_meshless_relink(c, plane_x, &cut, NULL);
  for (int i = 0; i < n; i++) {
    const int *la, *lc;
    int ka = tb_meshless_neighbours(a, i, &la), kc = tb_meshless_neighbours(c, i, &lc);
    same &= ka == kc && memcmp(la, lc, sizeof(int) * (size_t)ka) == 0;
  }
  tb_meshless_destroy(c);
  TB_CHECK(crossing == 0);
  TB_CHECK(crossing_whole > 0);
  TB_CHECK(same);
  /* Hold the left half: ids of x < cut. */
  int *ids = malloc(sizeof(int) * (size_t)n), nf = 0;
  tb_vec3 *fx = malloc(sizeof(tb_vec3) * (size_t)n);
  for (int i = 0; i < n; i++)
    if (X[i].x < cut) ids[nf] = i, fx[nf++] = X[i];
  double drop[2];
  for (int pass = 0; pass < 2; pass++) {
    tb_meshless *m = pass ? b : a;
    for (int s = 0; s < 200; s++) {
      tb_error err;
      if (tb_meshless_step(m, T / 200, tb_v3(0, 0, -9.81), nf, ids, fx, &err)) {
        tb_test_fail(__FILE__, __LINE__, "step: %s", err.msg);
        break;
      }
    }
    const tb_vec3 *x = tb_meshless_positions(m), *v = tb_meshless_velocities(m);
    double dz = 0, vdev = 0;
    int k = 0;
    for (int i = 0; i < n; i++)
      if (X[i].x > cut) {
        dz += x[i].z - X[i].z, k++;
        vdev = fmax(vdev, tb_len(tb_sub(v[i], tb_v3(0, 0, -9.81 * T))));
      }
    drop[pass] = -dz / k;
    if (!pass) {
      printf("cut: right half dropped %.9g m (g T^2 / 2 = %.9g), max |v - g T| %.3g\n", drop[0],
             fall, vdev);
      TB_CHECK_MSG(fabs(drop[0] - fall) <= 1e-9 * fall, "drop %.12g, free fall %.12g", drop[0],
                   fall);
      TB_CHECK_MSG(vdev < 1e-9, "max |v - g T| = %g", vdev);
    }
  }
  printf("uncut: right half dropped %.4g m\n", drop[1]);
  TB_CHECK_MSG(drop[1] < 0.1 * fall, "uncut drop %g", drop[1]);
  tb_meshless_destroy(a), tb_meshless_destroy(b);
  free(X), free(ids), free(fx);
}

/* Stencils without 3 non-coplanar neighbours: a planar one-layer sheet and
 * two points are inactive, exert no force and fall freely, never NaN. */
static void degenerate_points_finite(void) {
  tb_vec3 *X = lattice(5, 5, 1, 0.1, 9), *f = malloc(sizeof(tb_vec3) * 25);
  for (int i = 0; i < 25; i++) X[i].z = 0; /* exactly planar */
  for (int pass = 0; pass < 2; pass++) {
    int n = pass ? 2 : 25;
    tb_meshless *m = make(n, X, 1e5, NULL, NULL);
    if (!m) break;
    int active = 0;
    for (int i = 0; i < n; i++) active += tb_meshless_active(m, i);
    TB_CHECK(active == 0);
    tb_vec3 *x = malloc(sizeof(tb_vec3) * (size_t)n);
    for (int i = 0; i < n; i++) x[i] = tb_add(X[i], tb_v3(0.001 * i, 0, 0.002 * (i % 3)));
    tb_meshless_set_positions(m, x);
    tb_meshless_forces(m, f);
    TB_CHECK(max_len(f, n) == 0);
    tb_error err;
    for (int s = 0; s < 10; s++)
      TB_CHECK(tb_meshless_step(m, 1e-3, tb_v3(0, 0, -9.81), 0, NULL, NULL, &err) == 0);
    const tb_vec3 *p = tb_meshless_positions(m);
    for (int i = 0; i < n; i++) {
      TB_CHECK(tb_isfinite3(p[i]));
      TB_CHECK_NEAR(p[i].z - x[i].z, -0.5 * 9.81 * 1e-4, 1e-12);
    }
    free(x);
    tb_meshless_destroy(m);
  }
  free(X), free(f);
}

/* Bad input is refused with a message; bad steps too. */
static void bad_input(void) {
  tb_vec3 *X = lattice(3, 3, 3, 0, 0), same[3] = {{0, 0, 0}, {0, 0, 0}, {0, 0, 0}};
  tb_error err = {{0}};
  TB_CHECK(!tb_meshless_create(1, X, NULL, 1e5, 0.3, 1000, NULL, NULL, &err));
  TB_CHECK(!tb_meshless_create(27, X, NULL, 0, 0.3, 1000, NULL, NULL, &err));
  TB_CHECK(!tb_meshless_create(27, X, NULL, 1e5, 0.5, 1000, NULL, NULL, &err));
  TB_CHECK(!tb_meshless_create(3, same, NULL, 1e5, 0.3, 1000, NULL, NULL, &err));
  TB_CHECK(strstr(err.msg, "coincide") != NULL);
  tb_meshless *m = make(27, X, 1e5, NULL, NULL);
  if (m) {
    int bad = 27;
    TB_CHECK(tb_meshless_step(m, 1e-3, tb_v3(0, 0, 0), 1, &bad, X, &err) != 0);
    TB_CHECK(strstr(err.msg, "out of range") != NULL);
    TB_CHECK(tb_meshless_step(m, 0, tb_v3(0, 0, 0), 0, NULL, NULL, &err) != 0);
    tb_meshless_destroy(m);
  }
  free(X);
}

/* Same inputs, bit-identical positions and velocities, both integrators,
 * on one thread and on two (the forces are gathered per point). */
static void deterministic(void) {
  int n = 9 * 7 * 6, threads = tb_threads();
  tb_vec3 *X = lattice(9, 7, 6, 0.2, 10), *r[2][2];
  double cut = 3.5 * S;
  for (int integ = 0; integ < 2; integ++)
    for (int run = 0; run < 2; run++) {
      tb_threads_set(run ? 2 : 1); /* the second run on two threads: the same bits */
      tb_meshless *m = make(n, X, 1e4, plane_x, &cut);
      if (!m) return;
      tb_meshless_set_integrator(m, integ);
      tb_meshless_set_damping(m, 5);
      run_held(m, 0.5 * S, 5e-4, 300);
      r[run][0] = malloc(sizeof(tb_vec3) * (size_t)n),
      r[run][1] = malloc(sizeof(tb_vec3) * (size_t)n);
      memcpy(r[run][0], tb_meshless_positions(m), sizeof(tb_vec3) * (size_t)n);
      memcpy(r[run][1], tb_meshless_velocities(m), sizeof(tb_vec3) * (size_t)n);
      tb_meshless_destroy(m);
      if (run == 1) {
        TB_CHECK(memcmp(r[0][0], r[1][0], sizeof(tb_vec3) * (size_t)n) == 0);
        TB_CHECK(memcmp(r[0][1], r[1][1], sizeof(tb_vec3) * (size_t)n) == 0);
        for (int k = 0; k < 2; k++) free(r[0][k]), free(r[1][k]);
      }
    }
  tb_threads_set(threads);
  free(X);
}

/* Milliseconds per step (alternating: one force pass) for ~2000 and ~10000
 * points, bottom held, gravity; printed, not asserted beyond finiteness. */
static void timing(void) {
  int dims[2][3] = {{13, 13, 12}, {22, 22, 21}};
  for (int c = 0; c < 2; c++) {
    int n = dims[c][0] * dims[c][1] * dims[c][2];
    tb_vec3 *X = lattice(dims[c][0], dims[c][1], dims[c][2], 0.1, 11);
    uint64_t t0 = tb_time_ns();
    tb_meshless *m = make(n, X, 1e4, NULL, NULL);
    if (!m) return;
    uint64_t t1 = tb_time_ns();
    run_held(m, 0.5 * S, 5e-4, 2);
    uint64_t t2 = tb_time_ns();
    run_held(m, 0.5 * S, 5e-4, 20);
    uint64_t t3 = tb_time_ns();
    int links = 0;
    for (int i = 0; i < n; i++) links += tb_meshless_neighbours(m, i, NULL);
    printf("timing: %d points, %.1f links/point: create %.1f ms, step %.3f ms\n", n,
           (double)links / n, (t1 - t0) * 1e-6, (t3 - t2) * 1e-6 / 20);
    TB_CHECK(tb_isfinite3(tb_meshless_positions(m)[n - 1]));
    tb_meshless_destroy(m);
    free(X);
  }
}

/* The stability bound without iteration (tb_meshless_frequency_bound) lies
 * above the largest free frequency that power iteration on finite
 * differences of the forces finds (the bottom layer driven), within a
 * factor 1.25 (1.05 measured; block Gershgorin gave 1.65); steps at 0.9 x 2 / bound stay bounded;
 * dropping flat stencils (a larger flatness) never raises it. */
static void frequency_bound_holds(void) {
  int nx = 6, n = nx * nx * nx;
  tb_vec3 *X = lattice(nx, nx, nx, 0.3, 5);
  tb_meshless *m = make(n, X, 1e5, NULL, NULL);
  unsigned char *drv = calloc((size_t)n, 1);
  double *row = malloc(sizeof(double) * 2 * (size_t)n);
  tb_vec3 *u = malloc(sizeof(tb_vec3) * (size_t)n), *f0 = malloc(sizeof(tb_vec3) * (size_t)n),
          *f1 = malloc(sizeof(tb_vec3) * (size_t)n), *xs = malloc(sizeof(tb_vec3) * (size_t)n);
  if (!m) goto done;
  for (int i = 0; i < nx * nx; i++) drv[i] = 1;
  double bound = tb_meshless_frequency_bound(m, drv, row), eps = 1e-7 * S, lam = 0;
  tb_meshless_forces(m, f0);
  for (int i = 0; i < n; i++) u[i] = drv[i] ? tb_v3(0, 0, 0) : tb_v3(1 + i % 3, 2 - i % 5, i % 2);
  for (int it = 0; it < 200; it++) {
    double un = 0, an = 0;
    for (int i = 0; i < n; i++) un += tb_dot(u[i], u[i]);
    un = sqrt(un);
    for (int i = 0; i < n; i++) xs[i] = tb_madd(X[i], eps / un, u[i]);
    tb_meshless_set_positions(m, xs);
    tb_meshless_forces(m, f1);
    for (int i = 0; i < n; i++) {
      u[i] = drv[i] ? tb_v3(0, 0, 0) : tb_scale(tb_sub(f1[i], f0[i]), -1 / tb_meshless_mass(m, i));
      an += tb_dot(u[i], u[i]);
    }
    lam = sqrt(an) / eps;
  }
  double omega = sqrt(lam);
  printf("frequency: power iteration %.4g rad/s, bound %.4g (%.2fx)\n", omega, bound,
         bound / omega);
  TB_CHECK_MSG(bound >= omega * (1 - 1e-6), "bound %g below %g", bound, omega);
  TB_CHECK_MSG(bound <= 1.25 * omega, "bound %g, 1.25x over %g", bound, omega);
  tb_meshless_set_positions(m, X);
  tb_meshless_set_damping(m, 0);
  int ids[36];
  for (int i = 0; i < nx * nx; i++) ids[i] = i;
  double dt = 0.9 * 2 / bound, e0 = 0, e = 0;
  tb_error err = {{0}};
  int ok = 1;
  for (int k = 0; k < 2000 && ok; k++) {
    ok = tb_meshless_step(m, dt, tb_v3(0, 0, -9.81), nx * nx, ids, X, &err) == 0;
    e = tb_meshless_energy(m) + tb_meshless_kinetic(m);
    if (k == 100) e0 = e;
  }
  TB_CHECK_MSG(ok, "%s", err.msg);
  TB_CHECK_MSG(isfinite(e) && e < 10 * e0 + 1e-30, "energy %g after %g at step 100", e, e0);
  tb_meshless_set_positions(m, X);
  tb_meshless_set_flatness(m, 0.3);
  int active = 0;
  for (int i = 0; i < n; i++) active += tb_meshless_active(m, i);
  TB_CHECK(active < n);
  TB_CHECK(tb_meshless_frequency_bound(m, drv, row) <= bound);
done:
  tb_meshless_destroy(m);
  free(X), free(drv), free(row), free(u), free(f0), free(f1), free(xs);
}

/* tb_meshless_group_stiffness bounds the curvature of the energy when a
 * group's points translate together (2 dU / eps^2 along several
 * directions), within a factor 2 (1.09 and 1.53 measured); points outside any group count nothing.
 */
static void group_stiffness_bounds(void) {
  int nx = 6, n = nx * nx * nx;
  tb_vec3 *X = lattice(nx, nx, nx, 0.3, 6), *x = malloc(sizeof(tb_vec3) * (size_t)n);
  tb_meshless *m = make(n, X, 1e5, NULL, NULL);
  int *group = malloc(sizeof(int) * (size_t)n);
  if (!m) goto done;
  for (int i = 0; i < n; i++) group[i] = X[i].x < 2.5 * S ? 0 : (X[i].z < 2.5 * S ? 1 : -1);
  double k[3] = {-1, -1, -1};
  tb_vec3 scratch[2];
  tb_meshless_group_stiffness(m, group, 2, k, scratch);
  TB_CHECK(k[2] == -1 && k[0] > 0 && k[1] > 0);
  static const tb_vec3 dirs[4] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {0.6, 0, 0.8}};
  double eps = 1e-6 * S;
  for (int g = 0; g < 2; g++) {
    double most = 0;
    for (int d = 0; d < 4; d++) {
      for (int i = 0; i < n; i++) x[i] = group[i] == g ? tb_madd(X[i], eps, dirs[d]) : X[i];
      tb_meshless_set_positions(m, x);
      double curv = 2 * tb_meshless_energy(m) / (eps * eps);
      TB_CHECK_MSG(curv <= k[g] * (1 + 1e-4), "group %d: curvature %g over the bound %g", g, curv,
                   k[g]);
      most = fmax(most, curv);
    }
    printf("group %d: stiffness bound %.4g, largest measured %.4g\n", g, k[g], most);
    TB_CHECK_MSG(most >= k[g] / 2, "group %d: bound %g, 2x over %g", g, k[g], most);
  }
  for (int i = 0; i < n; i++) x[i] = tb_v3(0.1 * i, -0.2, 0.05 * (i % 3));
  tb_meshless_set_velocities(m, x);
  double kin = 0;
  for (int i = 0; i < n; i++) kin += 0.5 * tb_meshless_mass(m, i) * tb_dot(x[i], x[i]);
  TB_CHECK(fabs(tb_meshless_kinetic(m) - kin) <= 1e-12 * kin);
  TB_CHECK(!memcmp(tb_meshless_velocities(m), x, sizeof(tb_vec3) * (size_t)n));
done:
  tb_meshless_destroy(m);
  free(X), free(x), free(group);
}

/* tb_meshless_add: a body created from the lower layers of a lattice
 * (spacing a power of two, so both spacings are exact and equal), then
 * given the upper layers, is the body created from all of them at once,
 * bit for bit: lists, active flags, forces after a deformation, with and
 * without a cut; velocities given are kept; bad input leaves it as it was. */
static void add_equals_create(void) {
  const double a = 1.0 / 128;
  enum { NX = 7, NY = 6, NZ = 6, N = NX * NY * NZ, N0 = NX * NY * 2 };
  tb_vec3 X[N], x[N], v[N], fa[N], fb[N];
  for (int k = 0, i = 0; k < NZ; k++)
    for (int j = 0; j < NY; j++)
      for (int l = 0; l < NX; l++, i++) X[i] = tb_v3(l * a, j * a, k * a), v[i] = tb_v3(0, 0, i);
  double px = 2.5 * a;
  for (int cut = 0; cut < 2; cut++) {
    tb_meshless_crosses cr = cut ? plane_x : NULL;
    tb_meshless *all = make(N, X, 1e5, cr, &px), *inc = make(N0, X, 1e5, cr, &px);
    if (!all || !inc) {
      tb_meshless_destroy(all), tb_meshless_destroy(inc);
      return;
    }
    tb_error err = {{0}};
    int gained = tb_meshless_neighbours(inc, N0 - 1, NULL);
    TB_CHECK_MSG(tb_meshless_add(inc, N - N0, X + N0, X + N0, v + N0, NULL, cr, &px, &err) == 0,
                 "add: %s", err.msg);
    TB_CHECK(tb_meshless_count(inc) == N);
    TB_CHECK(tb_meshless_neighbours(inc, N0 - 1, NULL) > gained);
    TB_CHECK(tb_meshless_spacing(inc) == tb_meshless_spacing(all));
    TB_CHECK(tb_meshless_support(inc) == tb_meshless_support(all));
    int same = 1, cross = 0;
    for (int i = 0; i < N && same; i++) {
      const int *la, *lb;
      int na = tb_meshless_neighbours(all, i, &la), nb = tb_meshless_neighbours(inc, i, &lb);
      same = na == nb && !memcmp(la, lb, sizeof(int) * (size_t)na) &&
             tb_meshless_active(all, i) == tb_meshless_active(inc, i) &&
             tb_meshless_mass(all, i) == tb_meshless_mass(inc, i);
      for (int k = 0; k < nb; k++) cross |= plane_x(&px, X[i], X[lb[k]]);
    }
    TB_CHECK_MSG(same, "cut %d: the stencils differ", cut);
    TB_CHECK_MSG(!cross || !cut, "a link crosses the cut");
    for (int i = 0; i < N; i++)
      x[i] = tb_add(X[i],
                    tb_v3(0.1 * X[i].y * X[i].z / a, 0.05 * X[i].x, -0.08 * X[i].x * X[i].x / a));
    tb_meshless_set_positions(all, x), tb_meshless_set_positions(inc, x);
    tb_meshless_forces(all, fa), tb_meshless_forces(inc, fb);
    TB_CHECK(max_len(fa, N) > 0);
    TB_CHECK_MSG(!memcmp(fa, fb, sizeof fa), "cut %d: the forces differ", cut);
    TB_CHECK(!memcmp(tb_meshless_velocities(inc) + N0, v + N0, sizeof(tb_vec3) * (N - N0)));
    tb_vec3 nan = tb_v3(NAN, 0, 0);
    TB_CHECK(tb_meshless_add(inc, 1, &nan, &nan, NULL, NULL, NULL, NULL, &err) != 0);
    TB_CHECK(tb_meshless_add(inc, -1, X, X, NULL, NULL, NULL, NULL, &err) != 0);
    TB_CHECK(tb_meshless_count(inc) == N);
    tb_meshless_destroy(all), tb_meshless_destroy(inc);
  }
}

const tb_test_case tb_tests_meshless[] = {
    {"linear_field_reproduced", linear_field_reproduced},
    {"rigid_motion_strain_free", rigid_motion_strain_free},
    {"momentum_conserved", momentum_conserved},
    {"forces_are_energy_gradient", forces_are_energy_gradient},
    {"bar_oscillates_stably", bar_oscillates_stably},
    {"block_sags_and_rests", block_sags_and_rests},
    {"cut_separates", cut_separates},
    {"degenerate_points_finite", degenerate_points_finite},
    {"bad_input", bad_input},
    {"deterministic", deterministic},
    {"timing", timing},
    {"frequency_bound_holds", frequency_bound_holds},
    {"group_stiffness_bounds", group_stiffness_bounds},
    {"add_equals_create", add_equals_create},
    {0, 0},
};
