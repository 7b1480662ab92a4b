/* Metaballs (models/metaball.c): a box filled with a grid of overlapping
 * spheres and skinned by a box surface around them. At rest nothing
 * moves; a rigid motion carries spheres and skin rigidly; a deformed body
 * recovers its rest shape (the unit constraints); fixed spheres hold a
 * body that sags to rest under gravity; the binding follows the patent's
 * rule; a removed sphere leaves the others linked without it. */
#define _GNU_SOURCE
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "tb_test.h"
#include "core/tb_rng.h"
#include "models/tb_metaball.h"
#include "models/tb_model.h"

enum { NX = 9, NY = 5, NZ = 5 };
#define H 0.25 /* grid spacing */
#define R 0.2  /* radius: neighbours along an axis overlap */

static tb_vec3 corner[8];
static int box_tri[36] = {0, 2, 1, 0, 3, 2, 4, 5, 6, 4, 6, 7, 0, 1, 5, 0, 5, 4,
                          2, 3, 7, 2, 7, 6, 1, 2, 6, 1, 6, 5, 0, 4, 7, 0, 7, 3};

/* The spheres on the grid [0, 2] x [0, 1] x [0, 1] and the box 0.15 beyond
 * their centres (k = d / r = 1.3 from a corner sphere). */
static tb_metaball *box(const tb_metaball_settings *set) {
  static tb_vec3 c[NX * NY * NZ];
  static double r[NX * NY * NZ];
  int n = 0;
  for (int i = 0; i < NX; i++)
    for (int j = 0; j < NY; j++)
      for (int k = 0; k < NZ; k++) c[n] = tb_v3(i * H, j * H, k * H), r[n++] = R;
  double lo = -0.15, hx = (NX - 1) * H + 0.15, hy = (NY - 1) * H + 0.15, hz = (NZ - 1) * H + 0.15;
  for (int q = 0; q < 8; q++)
    corner[q] = tb_v3((q == 1 || q == 2 || q == 5 || q == 6) ? hx : lo,
                      (q == 2 || q == 3 || q == 6 || q == 7) ? hy : lo, q >= 4 ? hz : lo);
  tb_mesh s = {0};
  s.nv = 8, s.x = corner, s.ntri = 12, s.tri = box_tri;
  tb_error err;
  tb_metaball *m = tb_metaball_create(n, c, r, &s, set, &err);
  TB_CHECK_MSG(m != NULL, "%s", err.msg);
  return m;
}

static void rest_stays(void) {
  tb_metaball_settings set;
  tb_metaball_settings_default(&set);
  tb_metaball *m = box(&set);
  if (!m) return;
  int n = tb_metaball_count(m);
  tb_vec3 *c0 = malloc(sizeof(tb_vec3) * (size_t)n);
  memcpy(c0, tb_metaball_centres(m), sizeof(tb_vec3) * (size_t)n);
  for (int k = 0; k < 10; k++) tb_metaball_step(m, 0.01, tb_v3(0, 0, 0), NULL);
  double worst = 0, skin = 0;
  for (int i = 0; i < n; i++) worst = fmax(worst, tb_dist(c0[i], tb_metaball_centres(m)[i]));
  for (int v = 0; v < 8; v++) skin = fmax(skin, tb_dist(corner[v], tb_metaball_skin(m)[v]));
  TB_CHECK_MSG(worst < 1e-12 && skin < 1e-12, "moved %g, skin %g at rest", worst, skin);
  free(c0);
  tb_metaball_destroy(m);
}

static void rigid_follows(void) {
  tb_metaball_settings set;
  tb_metaball_settings_default(&set);
  tb_metaball *m = box(&set);
  if (!m) return;
  tb_mat3 rot = tb_m3_rotation(tb_v3(1, 2, 3), 0.5);
  double Rm[9];
  for (int a = 0; a < 3; a++)
    for (int b = 0; b < 3; b++) Rm[3 * a + b] = rot.m[a][b];
  tb_vec3 t = tb_v3(0.3, -1, 2);
  tb_metaball_transform(m, Rm, t);
  for (int k = 0; k < 5; k++) tb_metaball_step(m, 0.01, tb_v3(0, 0, 0), NULL);
  double skin = 0;
  for (int v = 0; v < 8; v++)
    skin = fmax(skin, tb_dist(tb_add(tb_m3_mulv(rot, corner[v]), t), tb_metaball_skin(m)[v]));
  TB_CHECK_MSG(skin < 1e-9, "the skin is %g from the rigid image", skin);
  tb_metaball_destroy(m);
}

/* Largest relative change of a link's length from rest. */
static double link_strain(const tb_metaball *m, const tb_vec3 *c0) {
  const int *pairs;
  int nl = tb_metaball_links(m, &pairs);
  const tb_vec3 *c = tb_metaball_centres(m);
  double worst = 0;
  for (int e = 0; e < nl; e++) {
    int a = pairs[2 * e], b = pairs[2 * e + 1];
    double l0 = tb_dist(c0[a], c0[b]);
    worst = fmax(worst, fabs(tb_dist(c[a], c[b]) - l0) / l0);
  }
  return worst;
}

/* Pushed out of shape and let go, the body comes back to its rest shape:
 * with the links and unit constraints (the defaults), and with the unit
 * constraints alone (stretch 0), which the patent says recover the state. */
static void recovers_with(double stretch) {
  tb_metaball_settings set;
  tb_metaball_settings_default(&set);
  set.stretch = stretch;
  tb_metaball *m = box(&set);
  if (!m) return;
  int n = tb_metaball_count(m);
  tb_vec3 *c0 = malloc(sizeof(tb_vec3) * (size_t)n), *f = malloc(sizeof(tb_vec3) * (size_t)n);
  memcpy(c0, tb_metaball_centres(m), sizeof(tb_vec3) * (size_t)n);
  tb_rng rng = tb_rng_seed(3);
  for (int i = 0; i < n; i++) /* a random push */
    f[i] = tb_v3(tb_rng_range(&rng, -50, 50), tb_rng_range(&rng, -50, 50),
                 tb_rng_range(&rng, -50, 50));
  for (int k = 0; k < 20; k++) tb_metaball_step(m, 0.01, tb_v3(0, 0, 0), f);
  double pushed = link_strain(m, c0);
  for (int k = 0; k < 1000; k++) tb_metaball_step(m, 0.01, tb_v3(0, 0, 0), NULL);
  double left = link_strain(m, c0);
  TB_CHECK_MSG(pushed > 1e-3 && left < 1e-4, "stretch %g: link strain %g pushed, %g after 10 s",
               stretch, pushed, left);
  free(c0), free(f);
  tb_metaball_destroy(m);
}

static void recovers(void) {
  recovers_with(1);
  recovers_with(0);
}

static void fixed_sag_rest(void) {
  tb_metaball_settings set;
  tb_metaball_settings_default(&set);
  tb_metaball *m = box(&set);
  if (!m) return;
  int n = tb_metaball_count(m);
  for (int i = 0; i < NY * NZ; i++) tb_metaball_fix(m, i, 1); /* the x = 0 end */
  tb_vec3 fixed0 = tb_metaball_centres(m)[0], tip0 = tb_metaball_centres(m)[n - 1];
  for (int k = 0; k < 500; k++) tb_metaball_step(m, 0.01, tb_v3(0, 0, -9.81), NULL);
  double vmax = 0;
  for (int i = 0; i < n; i++) vmax = fmax(vmax, tb_len(tb_metaball_velocities(m)[i]));
  double sag = tip0.z - tb_metaball_centres(m)[n - 1].z;
  TB_CHECK_MSG(tb_dist(fixed0, tb_metaball_centres(m)[0]) == 0, "a fixed sphere moved");
  TB_CHECK_MSG(sag > 1e-3 && sag < 0.5 && vmax < 1e-2, "sag %g, largest speed %g after 5 s", sag,
               vmax);
  tb_metaball_destroy(m);
}

/* Each vertex: 1-3 spheres with weights summing to 1, the smallest k in
 * [1, 2] (brute force), unless it fell back. */
static void binding_rule(void) {
  tb_metaball_settings set;
  tb_metaball_settings_default(&set);
  tb_metaball *m = box(&set);
  if (!m) return;
  const tb_vec3 *c = tb_metaball_centres(m);
  int n = tb_metaball_count(m);
  for (int v = 0; v < 8; v++) {
    int s[3];
    double w[3], sum = 0;
    int k = tb_metaball_binding(m, v, s, w);
    for (int q = 0; q < k; q++) sum += w[q];
    TB_CHECK_MSG(k >= 1 && k <= 3 && fabs(sum - 1) < 1e-12, "vertex %d: %d spheres, sum %g", v, k,
                 sum);
    double kmax = 0; /* the chosen ones' largest k; none unchosen in range below it */
    for (int q = 0; q < k; q++) kmax = fmax(kmax, tb_dist(corner[v], c[s[q]]) / R);
    int below = 0;
    for (int i = 0; i < n; i++) {
      double ki = tb_dist(corner[v], c[i]) / R;
      below += ki >= 1 && ki < kmax - 1e-12;
    }
    TB_CHECK_MSG(kmax >= 1 && kmax <= 2 && below <= k - 1, "vertex %d: k up to %g, %d below", v,
                 kmax, below);
  }
  TB_CHECK(tb_metaball_fallbacks(m) == 0);
  tb_metaball_destroy(m);
}

static void remove_unlinks(void) {
  tb_metaball_settings set;
  tb_metaball_settings_default(&set);
  tb_metaball *m = box(&set);
  if (!m) return;
  const int *pairs;
  int before = tb_metaball_links(m, &pairs), gone = NY * NZ * (NX / 2) + NZ * (NY / 2) + NZ / 2;
  int deg = 0;
  for (int e = 0; e < before; e++) deg += pairs[2 * e] == gone || pairs[2 * e + 1] == gone;
  tb_vec3 at = tb_metaball_centres(m)[gone];
  tb_metaball_remove(m, gone);
  int after = tb_metaball_links(m, &pairs);
  TB_CHECK_MSG(after == before - deg && deg >= 6, "%d links, %d after removing one of degree %d",
               before, after, deg);
  for (int e = 0; e < after; e++) TB_CHECK(pairs[2 * e] != gone && pairs[2 * e + 1] != gone);
  for (int k = 0; k < 50; k++) tb_metaball_step(m, 0.01, tb_v3(0, 0, -9.81), NULL);
  TB_CHECK(tb_dist(at, tb_metaball_centres(m)[gone]) == 0);
  tb_metaball_destroy(m);
}

static void bad_input(void) {
  tb_metaball_settings set;
  tb_metaball_settings_default(&set);
  tb_error err;
  tb_vec3 c[2] = {{0, 0, 0}, {1, 0, 0}};
  double r[2] = {1, 0};
  TB_CHECK(tb_metaball_create(2, c, r, NULL, &set, &err) == NULL);
  TB_CHECK_MSG(strstr(err.msg, "sphere 1") != NULL, "%s", err.msg);
  TB_CHECK(tb_metaball_create(0, c, r, NULL, &set, &err) == NULL);
}

const tb_test_case tb_tests_metaball[] = {
    {"rest_stays", rest_stays},     {"rigid_follows", rigid_follows},
    {"recovers", recovers},         {"fixed_sag_rest", fixed_sag_rest},
    {"binding_rule", binding_rule}, {"remove_unlinks", remove_unlinks},
    {"bad_input", bad_input},       {0, 0},
};
