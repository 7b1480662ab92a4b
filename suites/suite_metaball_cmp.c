/* The metaball patent's table 2 and its convergence claim on the steak
 *, part of the `metaball` suite (suites/suite_metaball.c).
 *  Table 2: the patent compares FEM + meshless (6272 elements, 25.2 / 8.6
 *  ms to deform / cut a frame), PBD on tets (1477 elements, 1.7 / 6.5 ms)
 *  and its own method (539 spheres, 1.5 / 2.4 ms). Ours: fem-corot on a
 *  TetGen steak of ~6272 tets, pbd-stvk on one of ~1477 (meshgen/liver_tets.c
 *  on a coarser steak surface, within 2% of the counts), each at its
 *  defaults with the same dt, holds and gravity as table 1, and the metaball
 *  steak of table 1 again: the three on one thread, live side by side and
 *  taking turns block by block, CPU time (wall beside), each tet model's
 *  time over the metaball's with its 95% interval (paired by block). Then
 *  table 1's cut on each (the tet models by element removal, models/carve.c):
 *  ms per cut frame and what the cut left (pieces, closed, manifold, volume).
 *  Convergence: frames to come to rest after a push (a downward force on a
 *  top patch at the middle, both ends held, no gravity; then released):
 *  the metaball steak against pbd-stvk, fem-corot and msm on the ~1477-tet
 *  steak. At rest: the largest point speed below REST_SHARE of the steak's
 *  box diagonal per second for WINDOW consecutive frames. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "suite_metaball.h"
#include "core/tb_timer.h"
#include "meshgen/tb_meshgen.h"

#define PUSH_FRAMES 30 /* the push lasts 0.3 s */
#define PUSH_FORCE \
  200 /* total force on the patch (the steak weighs about 50 x 9.81 at density 1) */
#define PATCH_SHARE \
  0.2 /* the patch: surface points above the middle within this share of the width */
#define REST_SHARE 1e-3 /* at rest: speed below this x the box diagonal per s ... */
#define WINDOW 10       /* ... for this many frames */

/* The patent's table 2. */
enum { FEM, PBD, MB, NROWS };
static const struct {
  const char *method, *ours;
  int elements;
  double deform, cut;
} patent[NROWS] = {
    {"FEM + meshless", "fem-corot", 6272, 25.2, 8.6},
    {"PBD on tets", "pbd-stvk", 1477, 1.7, 6.5},
    {"the patent (metaball)", "metaball", 539, 1.5, 2.4},
};

/* A TetGen steak of about `tets` tets: the steak's surface at the vertex
 * count the liver generator would use for that many tets. */
static int steak_tets(int tets, uint64_t seed, tb_mesh *out, tb_error *err) {
  tb_mesh surf;
  int verts = tb_liver_surface_for(tets);
  if (tb_organ_surface("steak", verts < 200 ? 200 : verts, seed, &surf, err)) return -1;
  tb_liver_def d = tb_liver_default_def();
  d.surface_verts = 0, d.tet_verts = 0, d.tets = tets, d.seed = seed;
  int rc = tb_liver_tets(&d, &surf, out, err);
  tb_mesh_free(&surf);
  return rc;
}

/* A model deforming under table 1's holds and gravity, timed block by
 * block so that several take turns. */
typedef struct deformer {
  int live, failed;
  tb_model m;
  tb_step in;
  int *ids;
  tb_vec3 *at;
  double *wall, *cpu; /* nblocks: mean ms per frame of each block */
  tb_error err;
} deformer;

static void deformer_open(deformer *d, const char *model, const tb_mesh *mesh,
                          const tb_settings *set, double *store, int nblocks) {
  memset(d, 0, sizeof *d);
  d->wall = store, d->cpu = store + nblocks;
  for (int b = 0; b < 2 * nblocks; b++) store[b] = NAN;
  if (tb_model_create(&d->m, model, mesh, set, &d->err)) {
    d->failed = 1;
    return;
  }
  d->live = 1;
  int nf = tb_mbs_end_holds(tb_model_positions(&d->m), tb_model_npoints(&d->m), &d->ids, &d->at,
                            &d->err);
  if (nf < 0) {
    d->failed = 1;
    return;
  }
  d->in = (tb_step){.dt = TB_MBS_DT, .gravity = tb_v3(0, 0, -TB_MBS_G)};
  d->in.nfixed = nf, d->in.fixed = d->ids, d->in.fixed_x = d->at;
}

/* n frames; block >= 0: their mean CPU and wall ms per frame to it. */
static void deformer_frames(deformer *d, int n, int block) {
  if (!d->live || d->failed) return;
  double w, c;
  if (tb_mbs_frames(&d->m, &d->in, n, &w, &c, &d->err))
    d->failed = 1;
  else if (block >= 0)
    d->wall[block] = w, d->cpu[block] = c;
}

static void deformer_close(deformer *d) {
  if (d->live) tb_model_destroy(&d->m);
  free(d->ids), free(d->at);
  d->live = 0, d->ids = NULL, d->at = NULL;
}

/* The convergence of one model: its push's dent, frames to rest. */
typedef struct conv {
  int ok, at_rest, frames, patch, points;
  double dent, speed_end, tol, ms; /* ms: a step's CPU time, median */
  char why[160];
} conv;

/* Surface points (those of the mesh's triangles) above the middle height
 * within PATCH_SHARE of the shorter horizontal extent from the centre. */
static int patch_of(const tb_mesh *mesh, const tb_vec3 *x, int **ids) {
  tb_vec3 lo = x[0], hi = x[0];
  for (int i = 1; i < mesh->nv; i++) {
    lo.x = fmin(lo.x, x[i].x), lo.y = fmin(lo.y, x[i].y), lo.z = fmin(lo.z, x[i].z);
    hi.x = fmax(hi.x, x[i].x), hi.y = fmax(hi.y, x[i].y), hi.z = fmax(hi.z, x[i].z);
  }
  tb_vec3 c = tb_scale(tb_add(lo, hi), 0.5);
  double rad = PATCH_SHARE * fmin(hi.x - lo.x, hi.y - lo.y);
  unsigned char *on = calloc((size_t)mesh->nv, 1);
  *ids = malloc(sizeof(int) * (size_t)mesh->nv);
  if (!on || !*ids) return free(on), free(*ids), *ids = NULL, -1;
  for (int k = 0; k < 3 * mesh->ntri; k++) on[mesh->tri[k]] = 1;
  int n = 0;
  for (int i = 0; i < mesh->nv; i++)
    if (on[i] && x[i].z > c.z && hypot(x[i].x - c.x, x[i].y - c.y) < rad) (*ids)[n++] = i;
  free(on);
  return n;
}

static void converge(const char *model, const tb_mesh *mesh, const tb_settings *set, int max_frames,
                     conv *o) {
  tb_error err;
  tb_model m;
  memset(o, 0, sizeof *o);
  if (tb_model_create(&m, model, mesh, set, &err)) {
    snprintf(o->why, sizeof o->why, "%.150s", err.msg);
    return;
  }
  int np = tb_model_npoints(&m), *ids = NULL, *patch = NULL;
  tb_vec3 *at = NULL, *f = calloc((size_t)np, sizeof(tb_vec3)), *x0 = malloc(sizeof(tb_vec3) * np);
  double *ms = malloc(sizeof(double) * (size_t)(PUSH_FRAMES + max_frames));
  int nf = tb_mbs_end_holds(tb_model_positions(&m), np, &ids, &at, &err);
  int npatch = f && x0 && ms ? patch_of(mesh, tb_model_positions(&m), &patch) : -1;
  if (nf < 0 || npatch <= 0) {
    snprintf(o->why, sizeof o->why, "%.150s", nf < 0 ? err.msg : "no patch (or out of memory)");
    goto done;
  }
  memcpy(x0, tb_model_positions(&m), sizeof(tb_vec3) * (size_t)np);
  tb_vec3 lo = x0[0], hi = x0[0];
  for (int i = 1; i < np; i++)
    lo.x = fmin(lo.x, x0[i].x), lo.y = fmin(lo.y, x0[i].y), lo.z = fmin(lo.z, x0[i].z),
    hi.x = fmax(hi.x, x0[i].x), hi.y = fmax(hi.y, x0[i].y), hi.z = fmax(hi.z, x0[i].z);
  o->tol = REST_SHARE * tb_dist(lo, hi), o->patch = npatch, o->points = np;
  for (int k = 0; k < npatch; k++) f[patch[k]] = tb_v3(0, 0, -(double)PUSH_FORCE / npatch);
  tb_step in = {.dt = TB_MBS_DT, .force = f, .nfixed = nf, .fixed = ids, .fixed_x = at};
  int quiet = 0, k;
  for (k = 0; k < PUSH_FRAMES + max_frames; k++) {
    if (k == PUSH_FRAMES) {
      const tb_vec3 *x = tb_model_positions(&m);
      for (int q = 0; q < npatch; q++) o->dent += (x0[patch[q]].z - x[patch[q]].z) / npatch;
      in.force = NULL;
    }
    tb_clock clk = tb_clock_start();
    int rc = tb_model_step(&m, &in, &err);
    tb_clock_ms(&clk, NULL, ms + k);
    if (rc || !tb_mbs_finite(&m)) {
      snprintf(o->why, sizeof o->why, "frame %d: %.140s", k + 1,
               tb_mbs_finite(&m) ? err.msg : "NaN or inf");
      goto done;
    }
    const tb_vec3 *v = tb_model_velocities(&m);
    double s = 0;
    for (int i = 0; i < np; i++) s = fmax(s, tb_len(v[i]));
    o->speed_end = s;
    if (k < PUSH_FRAMES) continue;
    quiet = s < o->tol ? quiet + 1 : 0;
    if (quiet == WINDOW) break;
  }
  o->at_rest = quiet == WINDOW;
  o->frames = o->at_rest ? k + 1 - WINDOW - PUSH_FRAMES : k - PUSH_FRAMES;
  o->ms = tb_stats_of(ms, k < PUSH_FRAMES + max_frames ? k + 1 : k).median;
  o->ok = 1;
done:
  free(ids), free(at), free(f), free(x0), free(ms), free(patch);
  tb_model_destroy(&m);
}

/* What table 2 measured of each row: CPU and wall ms per frame (medians
 * over blocks), the CPU ratio to the metaball steak's paired by block; then
 * table 1's cut on the model as it hangs: a cut frame's CPU ms (MOVE + step,
 * the median of the frames with its interval) and wall, END's ms, and the
 * surface it leaves (pieces, closed, manifold, enclosed volume against just
 * before the cut). */
typedef struct t2row {
  int ok, elements;
  char why[160];
  tb_est cpu, ratio;
  double wall;
  int cut_ok, pieces, closed, manifold;
  tb_est cut_cpu;
  double cut_wall, end_ms, vol_change;
  double frame[TB_MBS_CUT_FRAMES], frame_w[TB_MBS_CUT_FRAMES]; /* cut frames' CPU and wall ms */
  char cut_why[160];
} t2row;

static double surface_volume(const tb_model *m, tb_mesh_topo *topo) {
  tb_surface su = tb_model_surface(m);
  tb_mesh view = {.nv = su.nv, .x = (tb_vec3 *)su.x, .ntri = su.ntri, .tri = (int *)su.tri};
  if (topo) *topo = tb_mesh_topology(&view);
  return tb_mesh_volume(&view);
}

static void cut_row(deformer *d, t2row *w) {
  if (!d->live || d->failed) return;
  double v0 = surface_volume(&d->m, NULL);
  tb_mbs_cut_times t;
  tb_error err;
  if (tb_mbs_cut(&d->m, &d->in, &t, &err)) {
    snprintf(w->cut_why, sizeof w->cut_why, "cut failed: %.140s", err.msg);
    return;
  }
  for (int f = 0; f < TB_MBS_CUT_FRAMES; f++)
    w->frame[f] = t.move[f] + t.step[f], w->frame_w[f] = t.wall[f];
  w->cut_cpu = tb_median_est(w->frame, TB_MBS_CUT_FRAMES);
  w->cut_wall = tb_stats_of(t.wall, TB_MBS_CUT_FRAMES).median, w->end_ms = t.end_cpu;
  tb_mesh_topo topo;
  w->vol_change = surface_volume(&d->m, &topo) / v0 - 1;
  w->pieces = topo.components, w->closed = topo.closed, w->manifold = topo.manifold;
  w->cut_ok = tb_mbs_finite(&d->m);
  if (!w->cut_ok) snprintf(w->cut_why, sizeof w->cut_why, "cut failed: NaN or inf");
}

static void table2(tb_suite *su, const t2row *w) {
  static const char *cols[] = {"method (patent)",
                               "ours",
                               "elements (patent)",
                               "elements (ours)",
                               "deform (ms/frame, patent)",
                               "deform CPU (ms/frame, ours)",
                               "cut (ms/frame, patent)",
                               "cut frame CPU (ms, ours, 95% interval)",
                               "cut frame CPU low (ms)",
                               "cut frame CPU high (ms)",
                               "cut end CPU (ms)",
                               "pieces after the cut",
                               "surface closed",
                               "surface manifold",
                               "volume change through the cut (%)",
                               "deform wall (ms/frame, ours)",
                               "cut frame wall (ms, ours)",
                               "deform / metaball's, CPU (ours, 95% interval)",
                               "deform / metaball's low",
                               "deform / metaball's high",
                               "deform / metaball's (patent)"};
  enum { NCOL = (int)(sizeof cols / sizeof cols[0]) };
  tb_table *t = tb_table_new("table2",
                             "Patent table 2: the steak, the patent's comparison beside ours "
                             "(dt 0.01, gravity, both ends held; one thread, CPU time, the "
                             "models deforming in turns block by block; then table 1's cut "
                             "on each, the tet models by element removal)",
                             NCOL, cols);
  tb_table_only(t, 8, TB_CSV_ONLY), tb_table_only(t, 9, TB_CSV_ONLY);
  tb_table_only(t, 18, TB_CSV_ONLY), tb_table_only(t, 19, TB_CSV_ONLY);
  for (int r = 0; r < NROWS; r++) {
    tb_table_row(t);
    tb_table_cell(t, "%s", patent[r].method);
    tb_table_cell(t, "%s", patent[r].ours);
    tb_table_num(t, patent[r].elements, "%.0f");
    if (!w[r].ok) {
      tb_table_cell(t, "%s", w[r].why);
      for (int c = 4; c < NCOL; c++) tb_table_cell(t, "-");
      continue;
    }
    int el = w[r].elements;
    tb_table_numf(t, el, "%d %s (%+.1f%%)", el, r == MB ? "spheres" : "tets",
                  100.0 * (el - patent[r].elements) / patent[r].elements);
    tb_table_num(t, patent[r].deform, "%.1f");
    tb_table_num(t, w[r].cpu.value, "%.3f");
    tb_table_num(t, patent[r].cut, "%.1f");
    if (w[r].cut_ok) {
      tb_table_est(t, w[r].cut_cpu, "%.3f", "");
      tb_table_num(t, w[r].cut_cpu.lo, "%.6g"), tb_table_num(t, w[r].cut_cpu.hi, "%.6g");
      tb_table_num(t, w[r].end_ms, "%.3f");
      tb_table_num(t, w[r].pieces, "%.0f");
      tb_table_cell(t, "%s", w[r].closed ? "yes" : "no");
      tb_table_cell(t, "%s", w[r].manifold ? "yes" : "no");
      tb_table_num(t, 100 * w[r].vol_change, "%+.2f");
    } else {
      tb_table_cell(t, "%s", w[r].cut_why[0] ? w[r].cut_why : "-");
      for (int c = 8; c < 15; c++) tb_table_cell(t, "-");
    }
    tb_table_num(t, w[r].wall, "%.3f");
    if (w[r].cut_ok)
      tb_table_num(t, w[r].cut_wall, "%.3f");
    else
      tb_table_cell(t, "-");
    if (r == MB) {
      for (int c = 17; c < NCOL; c++) tb_table_cell(t, "-");
      continue;
    }
    tb_table_est(t, w[r].ratio, "%.2f", "x");
    tb_table_num(t, w[r].ratio.lo, "%.6g"), tb_table_num(t, w[r].ratio.hi, "%.6g");
    tb_table_num(t, patent[r].deform / patent[MB].deform, "%.2fx");
  }
  tb_suite_table(su, t);
}

int tb_mbs_compare(tb_suite *su, const tb_suite_opts *o) {
  int smoke = o->scale < 1, failed = 0;
  tb_mbs_plan p = smoke     ? (tb_mbs_plan){2, 3, 2}
                  : o->full ? (tb_mbs_plan){10, 20, 10}
                            : (tb_mbs_plan){5, 10, TB_EST_MIN};
  int nb = p.nblocks;
  tb_mesh tets[2];
  t2row w[NROWS];
  memset(tets, 0, sizeof tets), memset(w, 0, sizeof w);
  tb_error err;
  tb_mesh surf = {0};
  int have_surf = !tb_organ_surface("steak", 0, o->seed, &surf, &err);
  if (!have_surf) snprintf(w[MB].why, sizeof w[MB].why, "failed: %.140s", err.msg), failed = 1;
  for (int r = 0; r < 2; r++)
    if (steak_tets(patent[r].elements, o->seed, &tets[r], &err)) {
      snprintf(w[r].why, sizeof w[r].why, "failed: %.140s", err.msg), failed = 1;
      fprintf(stderr, "metaball: table 2, %s: %s\n", patent[r].ours, err.msg);
    }
  /* the three models live side by side, taking turns block by block
   * (fem-corot, pbd-stvk, metaball, fem-corot, ...), so that a busy spell
   * of the machine falls on all alike and block b of each covers the same
   * stretch of the sag */
  double *store = malloc(sizeof(double) * 2 * NROWS * (size_t)nb);
  deformer d[NROWS];
  memset(d, 0, sizeof d);
  for (int r = 0; r < NROWS && store; r++) {
    tb_settings set;
    tb_settings_init(&set);
    if (r == MB) { /* table 1's steak: the patent's spheres, the same packing seed */
      tb_settings_setd(&set, "spheres", patent[MB].elements, NULL);
      tb_settings_setd(&set, "seed", (double)(o->seed % 2147483647u), NULL);
    }
    const tb_mesh *mesh = r == MB ? (have_surf ? &surf : NULL) : (w[r].why[0] ? NULL : &tets[r]);
    if (mesh)
      deformer_open(&d[r], patent[r].ours, mesh, r == MB ? &set : NULL,
                    store + 2 * (size_t)r * (size_t)nb, nb);
  }
  for (int r = 0; r < NROWS && store; r++) deformer_frames(&d[r], p.warm, -1);
  for (int b = 0; b < nb && store; b++)
    for (int r = 0; r < NROWS; r++) deformer_frames(&d[r], p.block, b);
  for (int r = 0; r < NROWS; r++) {
    if (w[r].why[0]) continue;
    if (!store || !d[r].live || d[r].failed) {
      snprintf(w[r].why, sizeof w[r].why, "failed: %.140s", store ? d[r].err.msg : "out of memory"),
          failed = 1;
      fprintf(stderr, "metaball: table 2, %s: %s\n", patent[r].ours, w[r].why);
      continue;
    }
    w[r].ok = 1;
    w[r].elements = r == MB ? tb_model_npoints(&d[r].m) : tets[r].ntet;
    w[r].cpu = tb_median_est(d[r].cpu, nb);
    w[r].wall = tb_median_est(d[r].wall, nb).value;
  }
  if (w[MB].ok) {
    tb_model_spheres sp = d[MB].m.cls->spheres(d[MB].m.self);
    w[MB].elements = sp.n;
  }
  for (int r = 0; r < NROWS; r++) {
    if (!w[r].ok) continue;
    if (r != MB && w[MB].ok) w[r].ratio = tb_ratio_est(d[r].cpu, d[MB].cpu, nb);
    char name[96];
    if (r == MB)
      snprintf(name, sizeof name, "table2/metaball/spheres:%d", w[r].elements);
    else
      snprintf(name, sizeof name, "table2/%s/tets:%d", patent[r].ours, tets[r].ntet);
    tb_suite_bench(su, name, d[r].wall, d[r].cpu, nb, "ms");
    if (r != MB) {
      tb_suite_counter(su, name, "tets", tets[r].ntet);
      tb_suite_counter(su, name, "nodes", tets[r].nv);
      if (w[MB].ok) {
        tb_suite_counter_est(su, name, "over_metaball", w[r].ratio);
      }
    }
    tb_suite_counter(su, name, "patent_deform_ms", patent[r].deform);
    tb_suite_counter(su, name, "patent_cut_ms", patent[r].cut);
  }
  /* then table 1's cut on each, one after the other */
  for (int r = 0; r < NROWS; r++) {
    if (!w[r].ok) continue;
    cut_row(&d[r], &w[r]);
    if (!w[r].cut_ok) {
      failed = 1;
      fprintf(stderr, "metaball: table 2, %s: %s\n", patent[r].ours, w[r].cut_why);
      continue;
    }
    char name[96];
    snprintf(name, sizeof name, "table2/%s/cut", patent[r].ours);
    tb_suite_bench(su, name, w[r].frame_w, w[r].frame, TB_MBS_CUT_FRAMES, "ms");
    tb_suite_counter(su, name, "end_ms", w[r].end_ms);
    tb_suite_counter(su, name, "pieces", w[r].pieces);
    tb_suite_counter(su, name, "closed", w[r].closed);
    tb_suite_counter(su, name, "manifold", w[r].manifold);
    tb_suite_counter(su, name, "volume_change", w[r].vol_change);
    tb_suite_counter(su, name, "patent_cut_ms", patent[r].cut);
  }
  for (int r = 0; r < NROWS; r++) deformer_close(&d[r]);
  free(store);
  table2(su, w);
  tb_suite_note(su,
                "Ours at each model's defaults (fem-corot: E 3000, nu 0.3, implicit Euler, "
                "CHOLMOD; pbd-stvk: k 0.4, 5 iterations; density 1; metaball: table 1's steak, "
                "539 spheres packed with the same seed), the same dt (%g), gravity "
                "and holds as table 1, on one thread; the three models live side by side and "
                "take turns: %d warm frames each, then %d blocks of %d frames, block by block "
                "(fem-corot, pbd-stvk, metaball, fem-corot, ...), each block's mean CPU ms per "
                "frame one sample, the median shown (wall beside); `deform / metaball's` is the "
                "median of the blocks' paired CPU-time ratios with its 95%% interval. The tet "
                "steaks: tb_organ_surface(\"steak\") at tb_liver_surface_for(N) vertices, "
                "TetGen with the largest tet volume searched to within 2%% of N. The cut: then, "
                "on each model as it hangs, one after the other, table 1's cut (the blade's "
                "edge under the steak across its width through the middle, its depth through "
                "the thickness, crossing in %d frames); a cut frame is the MOVE event and a "
                "step, CPU time, the median of the %d frames with its 95%% interval (the "
                "patent's cut column is its ms per cut frame). The metaball model cuts by the "
                "patent's hybrid method (spheres the blade touches become meshless points, "
                "re-packed at END, the surface split and closed); pbd-stvk and fem-corot by "
                "element removal (SOFA's carving, models/carve.c: every tet the blade's sweep "
                "meets is removed at each frame, the surface is the boundary of the tets left, "
                "masses lumped again; the patent does not say how its two comparisons cut); "
                "FEM + meshless is not built (fem-corot stands in, cut the same way). Surface: "
                "pieces, closed and manifold (element removal leaves edges "
                "shared by four triangles where two tets left meet along an edge), and the "
                "volume it encloses against just before the cut (element removal loses the "
                "removed tets).",
                TB_MBS_DT, p.warm, p.nblocks, p.block, TB_MBS_CUT_FRAMES, TB_MBS_CUT_FRAMES);
  /* convergence: the metaball steak on its surface, the tet models on the 1477-tet steak */
  static const char *models[] = {"metaball", "pbd-stvk", "fem-corot", "msm"};
  int max_frames = smoke ? 100 : o->full ? 3000 : 1500;
  static const char *cols[] = {"model",
                               "mesh",
                               "points",
                               "patch points",
                               "dent at the release",
                               "frames to rest",
                               "seconds to rest",
                               "at rest",
                               "largest speed at the end (per s)",
                               "step CPU (ms, median)"};
  char title[240];
  snprintf(title, sizeof title,
           "Convergence on the steak: frames to come to rest after a push (%d N down on a top "
           "patch for %d frames, then released; both ends held, no gravity, dt %g)",
           PUSH_FORCE, PUSH_FRAMES, TB_MBS_DT);
  tb_table *t = tb_table_new("convergence", title, 10, cols);
  double tol = NAN;
  for (int k = 0; k < 4; k++) {
    const tb_mesh *mesh = k == 0 ? (have_surf ? &surf : NULL) : w[PBD].why[0] ? NULL : &tets[PBD];
    conv c = {0};
    tb_settings set;
    tb_settings_init(&set);
    if (k == 0) tb_settings_setd(&set, "spheres", patent[MB].elements, NULL);
    if (mesh)
      converge(models[k], mesh, &set, max_frames, &c);
    else
      snprintf(c.why, sizeof c.why, "no mesh");
    tb_table_row(t);
    tb_table_cell(t, "%s", models[k]);
    if (!mesh)
      tb_table_cell(t, "-");
    else if (k == 0)
      tb_table_cell(t, "steak surface, %d vertices (table 1's spheres)", mesh->nv);
    else
      tb_table_cell(t, "steak, %d tets", mesh->ntet);
    if (!c.ok) {
      tb_table_cell(t, "failed: %s", c.why), failed = 1;
      for (int q = 3; q < 10; q++) tb_table_cell(t, "-");
      continue;
    }
    tol = c.tol;
    tb_table_num(t, c.points, "%.0f"), tb_table_num(t, c.patch, "%.0f");
    tb_table_num(t, c.dent, "%.4f");
    tb_table_numf(t, c.frames, c.at_rest ? "%d" : "> %d", c.frames);
    tb_table_numf(t, c.frames * TB_MBS_DT, c.at_rest ? "%.2f" : "> %.2f", c.frames * TB_MBS_DT);
    tb_table_cell(t, "%s", c.at_rest ? "yes" : "no");
    tb_table_num(t, c.speed_end, "%.2e");
    tb_table_num(t, c.ms, "%.3f");
    char name[64];
    snprintf(name, sizeof name, "convergence/%s", models[k]);
    tb_suite_counter(su, name, "frames_to_rest", c.frames);
    tb_suite_counter(su, name, "seconds_to_rest", c.frames * TB_MBS_DT);
    tb_suite_counter(su, name, "at_rest", c.at_rest);
    tb_suite_counter(su, name, "dent", c.dent);
    tb_suite_counter(su, name, "points", c.points);
  }
  tb_suite_table(su, t);
  tb_suite_note(su,
                "Each model at its defaults (metaball: 539 spheres (the patent's), damping "
                "2 per s relative to the rigid motion, 8 sweeps; pbd-stvk; fem-corot; msm: unit "
                "node masses, ks 180, kd 5). Held: the points within %g of the long extent of "
                "each end; the patch: surface points above the middle height within %g of the "
                "width from the centre, the force shared equally. Dent: the patch's mean "
                "downward displacement at the release. At rest: the largest point speed below "
                "%g of the box diagonal per s (%.4f per s) for %d consecutive frames; frames "
                "counted from the release to the first of those; at most %d frames.",
                TB_MBS_END_SHARE, PATCH_SHARE, REST_SHARE, tol, WINDOW, max_frames);
  tb_mesh_free(&surf), tb_mesh_free(&tets[0]), tb_mesh_free(&tets[1]);
  return failed;
}
