/* `figure cuts`: the cut torture suite. The metaball model (the metaball
 * patent's hybrid cut) on the patent's four organs and SOFA's liver-smooth
 * with liver.sph (when ../shared/data is present), one end held, under
 * gravity: designed cuts (straight, oblique, folded, grazing, a thin end,
 * partial, a miss, a tilted blade, two crossing cuts, a second cut through
 * the first crack) and seeded random paths, each judged by what a cut must
 * leave (measure/tb_cut_trial.h): closed, oriented pieces free of
 * self-intersections at the cut's end and a second later, the sphere graph
 * split into the same pieces, each piece's volume within 3% over that
 * second; and the CPU time of a cut frame. Failures are listed, never
 * left out. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "tb_suites.h"
#include "core/tb_mesh_io.h"
#include "core/tb_rng.h"
#include "core/tb_spheres.h"
#include "core/tb_threads.h"
#include "measure/tb_cut_trial.h"
#include "meshgen/tb_meshgen.h"
#include "meshgen/tb_sphpack.h"
#include "report/tb_results.h"

#define MAX_DRIFT 0.03 /* a piece's volume over the second after the cut */
#define GOAL_MS 2.0    /* a cut frame on the 8128-vertex liver, CPU time, one thread */
#define SHALLOW 0.01   /* a crossing this many mean edges deep is counted apart in the notes */
#define HOLD 0.08      /* the held end: this share of the long extent */
#define NORGANS_MAX 6
#define SOFA_SURF TB_SHARED_DATA_FILE("sofa/liver-smooth.obj")
#define SOFA_SPH TB_SHARED_DATA_FILE("sofa/liver.sph")

/* An organ as files, and its box. */
typedef struct organ {
  char name[32], mesh[512], spheres[512];
  tb_vec3 lo, hi;
  int ax; /* the long horizontal axis: 0 x, 1 y */
} organ;

static double comp(tb_vec3 v, int a) { return a == 0 ? v.x : a == 1 ? v.y : v.z; }
static tb_vec3 along(int ax, double a, double b, double z) { /* (long, across, up) to xyz */
  return ax == 0 ? tb_v3(a, b, z) : tb_v3(b, a, z);
}

/* The organ's surface and spheres written to dir. */
static int organ_files(organ *g, const char *dir, const tb_mesh *surf, const tb_spheres *sp,
                       tb_error *err) {
  snprintf(g->mesh, sizeof g->mesh, "%s/%s.obj", dir, g->name);
  snprintf(g->spheres, sizeof g->spheres, "%s/%s.sph", dir, g->name);
  for (char *c = g->mesh + strlen(dir); *c; c++)
    if (*c == ' ') *c = '-';
  for (char *c = g->spheres + strlen(dir); *c; c++)
    if (*c == ' ') *c = '-';
  if (tb_mesh_write(g->mesh, surf, err) || tb_spheres_write(g->spheres, sp, err)) return -1;
  tb_mesh_bbox(surf, &g->lo, &g->hi);
  g->ax = g->hi.x - g->lo.x >= g->hi.y - g->lo.y ? 0 : 1;
  return 0;
}

/* Ours (packed as the patent's counts), then SOFA's when present. */
static int make_organs(const char *dir, uint64_t seed, organ *o, char *sofa_why, size_t cap) {
  int n = 0;
  tb_error err;
  for (int k = 0; k < TB_NORGANS; k++) {
    const tb_organ_info *in = &tb_organs[k];
    tb_mesh surf;
    tb_spheres sp = {0};
    tb_sphpack_def pd = tb_sphpack_default_def(in->spheres);
    organ *g = &o[n];
    memset(g, 0, sizeof *g);
    snprintf(g->name, sizeof g->name, "%s", in->name);
    if (tb_organ_surface(in->name, 0, seed, &surf, &err) ||
        tb_sphere_pack(&surf, in->name, &pd, &sp, NULL, &err) ||
        organ_files(g, dir, &surf, &sp, &err))
      fprintf(stderr, "cuts: %s: %s\n", in->name, err.msg);
    else
      n++;
    tb_mesh_free(&surf), tb_spheres_free(&sp);
  }
  tb_mesh surf;
  tb_spheres sp = {0};
  if (tb_mesh_read(SOFA_SURF, &surf, &err) || tb_spheres_read(SOFA_SPH, &sp, &err)) {
    snprintf(sofa_why, cap, "not run: %.150s", err.msg);
    return n;
  }
  for (int i = 0; i < surf.nv; i++) /* SOFA's up, y, to z */
    surf.x[i] = tb_v3(surf.x[i].x, -surf.x[i].z, surf.x[i].y);
  for (int i = 0; i < sp.n; i++) sp.c[i] = tb_v3(sp.c[i].x, -sp.c[i].z, sp.c[i].y);
  organ *g = &o[n];
  memset(g, 0, sizeof *g);
  snprintf(g->name, sizeof g->name, "sofa-liver");
  if (organ_files(g, dir, &surf, &sp, &err))
    snprintf(sofa_why, cap, "not run: %.150s", err.msg);
  else
    n++, sofa_why[0] = 0;
  tb_mesh_free(&surf), tb_spheres_free(&sp);
  return n;
}

/* A blade from above: its edge along the path a tenth of the height over
 * the top, its depth reaching `reach` of the way down (1: through, with
 * room for the organ's sag under gravity before the blade comes: 0.4 of
 * the height past the bottom), tilted by `tilt` radians towards +across. */
static tb_cut_blade blade(const organ *g, int n, const double (*ab)[2], double reach, double tilt,
                          double start, double stop) {
  tb_cut_blade b;
  memset(&b, 0, sizeof b);
  double h = g->hi.z - g->lo.z, top = g->hi.z + 0.1 * h;
  double down = reach * 1.4 * h + 0.1 * h;
  b.n = n;
  for (int i = 0; i < n; i++) b.p[i] = along(g->ax, ab[i][0], ab[i][1], top);
  b.depth = tb_scale(along(g->ax, 0, sin(tilt), -cos(tilt)), down);
  b.start = start, b.stop = stop;
  return b;
}

typedef struct spec {
  char name[48];
  int expect; /* pieces expected (0: not stated) */
  tb_cut_trial t;
} spec;

/* The designed cases on organ g; returns how many (at most max). */
static int designed(const organ *g, spec *s, int max) {
  double a0 = comp(g->lo, g->ax), a1 = comp(g->hi, g->ax), b0 = comp(g->lo, 1 - g->ax),
         b1 = comp(g->hi, 1 - g->ax), L = a1 - a0, W = b1 - b0, m = 0.15 * W;
  double mid = a0 + 0.55 * L, far = a0 + 0.93 * L, h = g->hi.z - g->lo.z;
  int n = 0;
#define ADD(nm, ex)                                  \
  if (n < max) {                                     \
    memset(&s[n], 0, sizeof s[n]);                   \
    snprintf(s[n].name, sizeof s[n].name, "%s", nm); \
    s[n].expect = ex;                                \
    s[n].t.nblade = 1;                               \
  }                                                  \
  if (n < max)
  const double straight[2][2] = {{mid, b0 - m}, {mid, b1 + m}};
  ADD("straight", 2) s[n++].t.blade[0] = blade(g, 2, straight, 1, 0, 0.1, 0.3);
  const double oblique[2][2] = {{mid - 0.2 * L, b0 - m}, {mid + 0.2 * L, b1 + m}};
  ADD("oblique", 2) s[n++].t.blade[0] = blade(g, 2, oblique, 1, 0, 0.1, 0.3);
  const double folded[3][2] = {{mid, b0 - m}, {mid + 0.12 * L, 0.5 * (b0 + b1)}, {mid, b1 + m}};
  ADD("folded", 2) s[n++].t.blade[0] = blade(g, 3, folded, 1, 0, 0.1, 0.3);
  ADD("grazing", 1) s[n++].t.blade[0] = blade(g, 2, straight, 0.2, 0, 0.1, 0.3);
  const double thin[2][2] = {{far, b0 - m}, {far, b1 + m}};
  ADD("thin end", 2) s[n++].t.blade[0] = blade(g, 2, thin, 1, 0, 0.1, 0.3);
  const double partial[2][2] = {{mid, b0 - m}, {mid, 0.5 * (b0 + b1)}};
  ADD("partial", 1) s[n++].t.blade[0] = blade(g, 2, partial, 1, 0, 0.1, 0.3);
  const double miss[2][2] = {{a1 + 0.3 * L, b0 - m}, {a1 + 0.3 * L, b1 + m}};
  ADD("miss", 1) s[n++].t.blade[0] = blade(g, 2, miss, 1, 0, 0.1, 0.3);
  const double wide[2][2] = {{mid, b0 - m - 1.5 * h},
                             {mid, b1 + m + 1.5 * h}}; /* the tilt's reach */
  ADD("tilted blade", 2) s[n++].t.blade[0] = blade(g, 2, wide, 1, 0.5, 0.1, 0.3);
  const double lengthwise[2][2] = {{a0 + 0.3 * L, 0.5 * (b0 + b1)},
                                   {a1 + 0.1 * L, 0.5 * (b0 + b1)}};
  ADD("crossing", 0) {
    s[n].t.blade[0] = blade(g, 2, straight, 1, 0, 0.1, 0.3);
    s[n].t.blade[1] = blade(g, 2, lengthwise, 1, 0, 0.35, 0.55);
    s[n++].t.nblade = 2;
  }
  const double through[2][2] = {{mid - 0.15 * L, b0 - m}, {mid + 0.25 * L, b1 + m}};
  ADD("through the crack", 0) {
    s[n].t.blade[0] = blade(g, 2, straight, 1, 0, 0.1, 0.3);
    s[n].t.blade[1] = blade(g, 2, through, 1, 0, 0.35, 0.55);
    s[n++].t.nblade = 2;
  }
#undef ADD
  return n;
}

/* A seeded random cut of organ g: a path of 2 to 4 points crossing a point
 * of the middle of the box in a random direction, bending by up to 30
 * degrees at each point; the blade through the organ or half-way, tilted up
 * to 0.4 rad. */
static void random_case(const organ *g, tb_rng *r, int k, spec *s) {
  memset(s, 0, sizeof *s);
  snprintf(s->name, sizeof s->name, "random %d", k);
  double a0 = comp(g->lo, g->ax), a1 = comp(g->hi, g->ax), b0 = comp(g->lo, 1 - g->ax),
         b1 = comp(g->hi, 1 - g->ax);
  double ca = a0 + (0.2 + 0.6 * tb_rng_uniform(r)) * (a1 - a0);
  double cb = b0 + (0.2 + 0.6 * tb_rng_uniform(r)) * (b1 - b0);
  double ang = M_PI * tb_rng_uniform(r), reach = 1.5 * hypot(a1 - a0, b1 - b0);
  int n = 2 + (int)(3 * tb_rng_uniform(r));
  double ab[TB_CUT_TRIAL_POINTS][2];
  double step = 2 * reach / (n - 1), a = ca - reach * cos(ang), b = cb - reach * sin(ang);
  for (int i = 0; i < n; i++) {
    ab[i][0] = a, ab[i][1] = b;
    ang += (tb_rng_uniform(r) - 0.5) * M_PI / 3;
    a += step * cos(ang), b += step * sin(ang);
  }
  double depth = tb_rng_uniform(r) < 0.75 ? 1 : 0.5, tilt = 0.4 * (2 * tb_rng_uniform(r) - 1);
  s->t.nblade = 1;
  s->t.blade[0] = blade(g, n, (const double(*)[2])ab, depth, tilt, 0.1, 0.3);
}

int tb_suite_cuts(const tb_suite_opts *o) {
  char dir[900];
  tb_error err;
  if (snprintf(dir, sizeof dir, "%s/cuts", o->results) >= (int)sizeof dir) return 1;
  tb_suite *su = tb_suite_begin(dir, "cuts",
                                "Cut torture: the metaball model's hybrid cut on five organs, "
                                "designed and random cuts",
                                o->seed, &err);
  if (!su) return fprintf(stderr, "cuts: %s\n", err.msg), 1;
  int threads = tb_threads_setting();
  tb_threads_set(1);
  char tmp[600], sofa_why[200] = "";
  snprintf(tmp, sizeof tmp, "%s/tb-cuts-XXXXXX", getenv("TMPDIR") ? getenv("TMPDIR") : "/tmp");
  organ g[NORGANS_MAX];
  int ng = mkdtemp(tmp) ? make_organs(tmp, o->seed, g, sofa_why, sizeof sofa_why) : 0;
  if (o->scale < 1 && ng > 1) { /* smoke: the steak alone */
    for (int k = 0; k < ng; k++)
      if (!strcmp(g[k].name, "steak")) g[0] = g[k];
    ng = 1;
  }
  /* below scale 1 (the tests): the steak's designed cases and 40 x scale
   * random ones, one at least */
  int nrandom = o->scale < 1 ? (int)fmax(1, floor(40 * o->scale)) : (o->full ? 40 : 4),
      failed = ng == 0;
  static const char *cols[] = {"organ",
                               "case",
                               "verdict",
                               "pieces expected",
                               "pieces at the cut",
                               "pieces a second later",
                               "closed at the cut",
                               "closed a second later",
                               "self-intersecting pairs at the cut",
                               "self-intersecting pairs a second later",
                               "deepest crossing a second later (mean edges)",
                               "sphere components",
                               "points bound across the cut",
                               "largest volume drift (%)",
                               "cut frame CPU (ms, median)",
                               "surface vertices after"};
  tb_table *t = tb_table_new("cuts", "Every cut, judged", 16, cols);
  int total = 0, good = 0, ncross = 0, nshallow = 0; /* crossing a second later; by < SHALLOW */
  double deepest = 0;
  double liver_ms[16];
  int nliver = 0;
  tb_rng rng = tb_rng_seed(o->seed);
  for (int k = 0; k < ng; k++) {
    spec s[10 + 40];
    int n = designed(&g[k], s, 10);
    for (int q = 0; q < nrandom; q++) random_case(&g[k], &rng, q, &s[n++]);
    double L = comp(g[k].hi, g[k].ax) - comp(g[k].lo, g[k].ax);
    for (int q = 0; q < n; q++) {
      tb_progress("cuts", total, ng * n);
      tb_cut_trial *tr = &s[q].t;
      snprintf(tr->name, sizeof tr->name, "%.31s, %.30s", g[k].name, s[q].name);
      snprintf(tr->mesh, sizeof tr->mesh, "%s", g[k].mesh);
      snprintf(tr->spheres, sizeof tr->spheres, "%s", g[k].spheres);
      tr->hold_lo = tb_sub(g[k].lo, tb_v3(1, 1, 1));
      tr->hold_hi = tb_add(g[k].hi, tb_v3(1, 1, 1));
      if (g[k].ax == 0)
        tr->hold_hi.x = g[k].lo.x + HOLD * L;
      else
        tr->hold_hi.y = g[k].lo.y + HOLD * L;
      tr->after = 1.0, tr->dt = 0.01;
      tb_cut_outcome out;
      char verdict[300];
      if (tb_cut_trial_run(tr, &out, &err)) snprintf(out.why, sizeof out.why, "%.200s", err.msg);
      tb_cut_outcome_verdict(&out, MAX_DRIFT, verdict, sizeof verdict);
      int ok = !strcmp(verdict, "ok") && (!s[q].expect || s[q].expect == out.pieces_cut);
      if (!strcmp(verdict, "ok") && !ok)
        snprintf(verdict, sizeof verdict, "%d pieces, not the %d expected", out.pieces_cut,
                 s[q].expect);
      total++, good += ok;
      if (out.ran && (out.self_end > out.self_before || out.overlap_end > 0))
        ncross++, nshallow += out.deepest_end < SHALLOW, deepest = fmax(deepest, out.deepest_end);
      if (!strncmp(g[k].name, "liver", 5) && q < 10 && out.ran && nliver < 16)
        liver_ms[nliver++] = out.frame_ms;
      tb_table_row(t);
      tb_table_cell(t, "%s", g[k].name);
      tb_table_cell(t, "%s", s[q].name);
      tb_table_cell(t, "%s", verdict);
      if (s[q].expect)
        tb_table_num(t, s[q].expect, "%.0f");
      else
        tb_table_cell(t, "-");
      tb_table_num(t, out.ran ? out.pieces_cut : NAN, "%.0f");
      tb_table_num(t, out.ran ? out.pieces_end : NAN, "%.0f");
      tb_table_cell(t, "%s", !out.ran ? "-" : out.closed_cut ? "yes" : "NO");
      tb_table_cell(t, "%s", !out.ran ? "-" : out.closed_end ? "yes" : "NO");
      tb_table_num(t, out.ran ? out.self_cut : NAN, "%.0f");
      tb_table_num(t, out.ran ? out.self_end : NAN, "%.0f");
      tb_table_num(t, out.ran ? out.deepest_end : NAN, "%.4f");
      tb_table_num(t, out.ran ? out.spheres_cut : NAN, "%.0f");
      tb_table_num(t, out.ran ? out.crossing_cut : NAN, "%.0f");
      tb_table_num(t, out.ran ? 100 * out.drift : NAN, "%.2f");
      tb_table_num(t, out.frame_ms, "%.3f");
      tb_table_num(t, out.ran ? out.vertices_cut : NAN, "%.0f");
      char bench[96];
      snprintf(bench, sizeof bench, "cut/%.31s/%.47s", g[k].name, s[q].name);
      tb_suite_counter(su, bench, "ok", ok);
      tb_suite_counter(su, bench, "cut_frame_cpu_ms", out.frame_ms);
      tb_suite_counter(su, bench, "volume_drift", out.drift);
    }
  }
  tb_progress("cuts", total, total);
  tb_suite_table(su, t);
  tb_suite_note(su,
                "%d cases cross a second later where they did not before (within a piece or "
                "between pieces); %d of them by less than %.0f%% of a mean edge at the deepest "
                "(sheets in contact passing a hair through each other between the vertices the "
                "contact holds apart), the deepest by %.3f mean edges. Every crossing counts as "
                "a failure however shallow.",
                ncross, nshallow, 100 * SHALLOW, deepest);
  tb_est ms = tb_median_est(liver_ms, nliver);
  char v[200];
  tb_suite_note(su,
                "%d of %d cuts met everything (%d failed): every piece a closed, oriented "
                "2-manifold at the last blade's end and a second later, crossing itself nowhere "
                "the organ did not before the cut (SOFA's liver-smooth crosses itself in 7 "
                "triangle pairs), no piece inside another, the sphere graph's components the "
                "pieces (no skin point bound across the cut), each piece's volume within %.0f%% "
                "of its value at the cut's end over that second, and the pieces expected where "
                "the case says. Touching sheets (the two sides of a fresh cut) and triangles "
                "meeting only in a point both have a vertex at do not count as crossing "
                "(collision/self.c). Goal: no failure: %s.",
                good, total, total - good, 100 * MAX_DRIFT, good == total ? "met" : "not met");
  tb_suite_note(su,
                "Cut frame on the 8128-vertex liver (the designed cases' median CPU ms of the "
                "frames the blade moved in, one thread): %.3f ms, 95%% interval %.3f-%.3f over "
                "%d cases; goal <= %.0f ms: %s.",
                ms.value, ms.lo, ms.hi, ms.n, GOAL_MS,
                tb_verdict_text(ms, GOAL_MS, 0, v, sizeof v));
  tb_suite_note(
      su,
      "Each case: the organ's surface and its spheres (ours packed to the patent's counts, seed "
      "%llu; SOFA's liver.sph for its liver-smooth%s), the metaball model at its defaults, the "
      "points within %.0f%% of the long extent at one end held, gravity 9.81, dt 0.01; each "
      "blade comes from above, its edge along the path (from 0.1 to 0.3 s; a second blade from "
      "0.35 to 0.55 s), its depth through the organ (grazing: a fifth of it), then a second "
      "more. Random paths: %d per organ, seed %llu: 2-4 points through the box's middle, "
      "bending up to 30 degrees, the blade through or half-way, tilted up to 0.4 rad.",
      (unsigned long long)o->seed, sofa_why[0] ? sofa_why : "", 100 * HOLD, nrandom,
      (unsigned long long)o->seed);
  tb_threads_set(threads);
  for (int k = 0; k < ng; k++) remove(g[k].mesh), remove(g[k].spheres);
  rmdir(tmp);
  if (tb_suite_end(su, &err)) fprintf(stderr, "cuts: %s\n", err.msg), failed = 1;
  return failed;
}
