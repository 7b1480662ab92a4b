/* The metaball patent's tables and figures (a metaball-based hybrid cutting
 * method, ../shared/seeds/patent-metaball-hybrid-cutting.txt):
 * the `metaball` model (models/metaball_model.c) on the patent's organs
 * (meshgen/organs.c: liver 8128, spleen 1480, gallbladder 1415, steak 1266
 * surface vertices, packed to 570, 466, 452, 539 spheres) and on SOFA's
 * liver-smooth when ../shared/data is present.
 *  1. Table 1: per organ, vertices, spheres, the packing's time and
 *     coverage, ms per frame to deform (gravity, both ends held) and to cut
 *     (the blade's frames: MOVE + step), the cut's END, the patent's beside.
 *  2. Table 2 and the convergence after a push: suites/suite_metaball_cmp.c.
 *  3. The re-packing claim: spheres removed vs created and their radii (the
 *     patent: about twice as many, half the size), points left uncovered.
 *  4. The speed goal (§5): deform <= 1 ms and cut <= 2 ms a frame on the
 *     8128-vertex liver with 570 spheres: met, not met or inconclusive from
 *     the 95% interval of the repetitions' medians.
 *  5. Figs 7-10: per organ, before and after the cut, the spheres and their
 *     links above the surface.
 * Every organ is run `reps` times from scratch (same seed, same run) on one
 * thread: the timings are CPU time (wall beside), each repetition's median
 * frame one sample, the median over repetitions shown; the surfaces after
 * the cut must be bit-identical. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "suite_metaball.h"
#include "core/tb_mesh_io.h"
#include "core/tb_threads.h"
#include "core/tb_timer.h"
#include "cutting/tb_cut_surface.h"
#include "measure/tb_draw.h"
#include "measure/tb_pieces.h"
#include "meshgen/tb_meshgen.h"
#include "meshgen/tb_sphpack.h"
#include "render/tb_render.h"

#define AFTER_FRAMES 50 /* frames after the cut before the "after" picture */
#define GOAL_DEFORM 1.0 /* §5: ms per frame on the 8128-vertex liver, 570 spheres */
#define GOAL_CUT 2.0
#define W 640 /* pictures */
#define H 480
#define SOFA_SURF TB_SHARED_DATA_FILE("sofa/liver-smooth.obj")
#define SOFA_SPH TB_SHARED_DATA_FILE("sofa/liver.sph")
#define NMAX (TB_NORGANS + 1)
#define SPHERE_SCALE 0.35 /* the pictures draw the spheres at this share of their radius */

/* One organ: its surface (z up) and sphere count, the patent's figures;
 * given: spheres to use instead of packing (SOFA's liver.sph), else n 0. */
typedef struct organ {
  char name[32], source[96];
  int spheres;
  double deform_ms, cut_ms; /* the patent's (NAN: none) */
  tb_mesh surf;
  tb_spheres given;
} organ;

/* What an organ's runs give: CPU ms, and wall ms (*_w) beside. */
typedef struct row {
  int ok, identical, closed, components, links, nsph;
  char why[200];
  double *pack, *deform, *cut,
      *end; /* samples: reps, reps * nblocks, reps * TB_MBS_CUT_FRAMES, reps */
  double *pack_w, *deform_w, *cut_w, *end_w;
  double *move, *cstep; /* a cut frame's MOVE and step apart (reps * TB_MBS_CUT_FRAMES) */
  double *rdeform, *rcut, *rdeform_w, *rcut_w; /* each repetition's median (reps) */
  int npack, ndeform, ncut, nend, nrep;
  double *store; /* every sample array above, one block */
  tb_sphere_coverage cov;
  tb_cut_stats st;
  tb_vec3 blade[4]; /* the last cut's blade plane */
  double sag;       /* largest point displacement before the cut */
  int nv_after, ntri_after;
  tb_vec3 *x_after; /* rep 0's surface after the cut, to compare */
  int *tri_after;
} row;

int tb_mbs_finite(const tb_model *m) {
  const tb_vec3 *x = tb_model_positions(m);
  for (int i = 0, n = tb_model_npoints(m); i < n; i++)
    if (!isfinite(x[i].x + x[i].y + x[i].z)) return 0;
  return 1;
}

static void bbox(const tb_vec3 *x, int n, tb_vec3 *lo, tb_vec3 *hi) {
  *lo = tb_v3(INFINITY, INFINITY, INFINITY), *hi = tb_v3(-INFINITY, -INFINITY, -INFINITY);
  for (int i = 0; i < n; i++) {
    lo->x = fmin(lo->x, x[i].x), lo->y = fmin(lo->y, x[i].y), lo->z = fmin(lo->z, x[i].z);
    hi->x = fmax(hi->x, x[i].x), hi->y = fmax(hi->y, x[i].y), hi->z = fmax(hi->z, x[i].z);
  }
}

int tb_mbs_end_holds(const tb_vec3 *x, int n, int **ids, tb_vec3 **at, tb_error *err) {
  tb_vec3 lo, hi;
  bbox(x, n, &lo, &hi);
  int ax = hi.x - lo.x >= hi.y - lo.y ? 0 : 1;
  double a0 = ax ? lo.y : lo.x, a1 = ax ? hi.y : hi.x, band = TB_MBS_END_SHARE * (a1 - a0);
  *ids = malloc(sizeof(int) * (size_t)(n > 0 ? n : 1));
  *at = malloc(sizeof(tb_vec3) * (size_t)(n > 0 ? n : 1));
  if (!*ids || !*at)
    return free(*ids), free(*at), tb_error_set(err, "metaball", 0, "out of memory");
  int k = 0;
  for (int i = 0; i < n; i++) {
    double a = ax ? x[i].y : x[i].x;
    if (a <= a0 + band || a >= a1 - band) (*ids)[k] = i, (*at)[k++] = x[i];
  }
  return k;
}

int tb_mbs_frames(tb_model *m, const tb_step *in, int n, double *wall, double *cpu, tb_error *err) {
  double w = 0, c = 0;
  for (int k = 0; k < n; k++) {
    double dw, dc;
    tb_clock clk = tb_clock_start();
    int rc = tb_model_step(m, in, err);
    tb_clock_ms(&clk, &dw, &dc);
    if (rc) return -1;
    w += dw, c += dc;
  }
  if (!tb_mbs_finite(m)) return tb_error_set(err, "metaball", 0, "NaN or inf after %d frames", n);
  if (wall) *wall = n > 0 ? w / n : NAN;
  if (cpu) *cpu = n > 0 ? c / n : NAN;
  return 0;
}

int tb_mbs_deform(tb_model *m, const tb_step *in, const tb_mbs_plan *p, double *wall, double *cpu,
                  tb_error *err) {
  if (tb_mbs_frames(m, in, p->warm, NULL, NULL, err)) return -1;
  for (int b = 0; b < p->nblocks; b++)
    if (tb_mbs_frames(m, in, p->block, wall + b, cpu + b, err)) return -1;
  return 0;
}

/* The organs: ours, then SOFA's liver-smooth with liver.sph's spheres (both
 * rotated so that SOFA's up, y, is z) when the data is there (*sofa_why
 * says why not otherwise). */
static int organs(int only_steak, uint64_t seed, organ *o, char *sofa_why, size_t cap) {
  int n = 0;
  tb_error err;
  for (int k = 0; k < TB_NORGANS; k++) {
    const tb_organ_info *in = &tb_organs[k];
    if (only_steak && strcmp(in->name, "steak")) continue;
    organ *g = &o[n];
    memset(g, 0, sizeof *g);
    snprintf(g->name, sizeof g->name, "%s", in->name);
    snprintf(g->source, sizeof g->source, "ours (meshgen/organs.c, seed %llu)",
             (unsigned long long)seed);
    g->spheres = in->spheres, g->deform_ms = in->deform_ms, g->cut_ms = in->cut_ms;
    if (tb_organ_surface(in->name, 0, seed, &g->surf, &err))
      snprintf(g->source, sizeof g->source, "%.90s", err.msg);
    n++;
  }
  sofa_why[0] = 0;
  if (only_steak) return snprintf(sofa_why, cap, "left out at --scale < 1"), n;
  organ *g = &o[n];
  memset(g, 0, sizeof *g);
  if (tb_mesh_read(SOFA_SURF, &g->surf, &err) || tb_spheres_read(SOFA_SPH, &g->given, &err)) {
    tb_mesh_free(&g->surf), tb_spheres_free(&g->given);
    snprintf(sofa_why, cap, "not run: %.150s", err.msg);
    return n;
  }
  for (int i = 0; i < g->surf.nv; i++) /* a rotation about x: y -> z, z -> -y */
    g->surf.x[i] = tb_v3(g->surf.x[i].x, -g->surf.x[i].z, g->surf.x[i].y);
  for (int i = 0; i < g->given.n; i++)
    g->given.c[i] = tb_v3(g->given.c[i].x, -g->given.c[i].z, g->given.c[i].y);
  snprintf(g->name, sizeof g->name, "SOFA liver-smooth");
  snprintf(g->source, sizeof g->source, "SOFA liver-smooth.obj and liver.sph");
  g->spheres = g->given.n, g->deform_ms = g->cut_ms = NAN;
  return n + 1;
}

/* The spheres above (lifted by dz; created at the cut, index >= nold, in orange) and the surface
 * below, from the left front of box lo..hi, with a legend and a title. After a cut (blade not
 * NULL) the blade's plane is outlined and the pieces are drawn apart: each piece of the surface
 * and each sphere moved off the blade's plane by a tenth of the box's long side, as the patent's
 * figs. 7-10 show them. */
static int picture(tb_renderer *r, tb_model *m, int nold, tb_vec3 lo, tb_vec3 hi,
                   const tb_vec3 *blade, const char *title, const char *path, tb_error *err) {
  double dz = 1.2 * (hi.z - lo.z) + 0.5 * (hi.y - lo.y); /* clear of the surface in view */
  double gap = 0.1 * fmax(hi.x - lo.x, hi.y - lo.y);
  tb_camera cam;
  tb_vec3 top = tb_add(hi, tb_v3(0, 0, dz));
  if (blade) lo = tb_madd(lo, -gap, tb_v3(1, 1, 0)), top = tb_madd(top, gap, tb_v3(1, 1, 0));
  tb_camera_preset("left-front", lo, top, &cam);
  tb_renderer_begin(r, &cam, (const float[3]){1, 1, 1});
  tb_surface su = tb_model_surface(m);
  tb_model_spheres sp = m->cls->spheres(m->self);
  tb_vec3 *x = malloc(sizeof(tb_vec3) * (size_t)(su.nv + 1)),
          *c = malloc(sizeof(tb_vec3) * (size_t)(sp.n + 1));
  unsigned char *show = malloc((size_t)sp.n + 1);
  tb_pieces pc = {0};
  if (!x || !c || !show ||
      (blade && tb_pieces_measure(su.nv, su.x, su.ntri, su.tri, 0, &pc, err))) {
    free(x), free(c), free(show);
    return blade ? -1 : tb_error_set(err, "metaball", 0, "out of memory");
  }
  /* the side of the blade's plane: +1 or -1 along its normal */
  tb_vec3 n = blade ? tb_normalize(tb_cross(tb_sub(blade[1], blade[0]), tb_sub(blade[3], blade[0])))
                    : tb_v3(0, 0, 0);
  memcpy(x, su.x, sizeof(tb_vec3) * (size_t)su.nv);
  for (int i = 0; i < sp.n; i++) c[i] = tb_add(sp.c[i], tb_v3(0, 0, dz));
  if (blade) {
    double *side = calloc((size_t)pc.n + 1, sizeof(double));
    for (int i = 0; side && i < su.nv; i++)
      if (pc.of_vertex[i] >= 0) side[pc.of_vertex[i]] += tb_dot(tb_sub(su.x[i], blade[0]), n);
    for (int i = 0; side && i < su.nv; i++)
      if (pc.of_vertex[i] >= 0) x[i] = tb_madd(x[i], side[pc.of_vertex[i]] > 0 ? gap : -gap, n);
    for (int i = 0; i < sp.n; i++)
      c[i] = tb_madd(c[i], tb_dot(tb_sub(sp.c[i], blade[0]), n) > 0 ? gap : -gap, n);
    free(side);
    tb_pieces_free(&pc);
  }
  tb_render_mesh rm = {.nv = su.nv, .ntri = su.ntri, .x = x, .tri = su.tri};
  memcpy(rm.rgb, tb_draw_body_rgb, sizeof rm.rgb);
  tb_renderer_mesh(r, &rm);
  static const float old_rgb[3] = {0.55f, 0.65f, 0.85f}, new_rgb[3] = {0.95f, 0.55f, 0.15f};
  int rc = 0;
  for (int pass = 0; pass < 2 && !rc; pass++) {
    for (int i = 0; i < sp.n; i++) show[i] = sp.alive[i] && (i >= nold) == pass;
    rc = tb_draw_spheres(r, sp.n, c, sp.r, show, SPHERE_SCALE, pass ? new_rgb : old_rgb, err);
  }
  tb_draw_links(r, sp.nlinks, sp.links, c, (const float[3]){0.15f, 0.15f, 0.2f}, 1.0f);
  if (blade) {
    tb_vec3 e[8];
    for (int k = 0; k < 4; k++) e[2 * k] = blade[k], e[2 * k + 1] = blade[(k + 1) % 4];
    tb_renderer_lines(r, 4, e, (const float[3]){0.2f, 0.2f, 0.2f}, 2);
  }
  static const char *const labels[4] = {"surface: the point set's skin", "spheres (drawn above)",
                                        "spheres the cut made", "the blade's plane"};
  const float rgbs[4][3] = {{tb_draw_body_rgb[0], tb_draw_body_rgb[1], tb_draw_body_rgb[2]},
                            {old_rgb[0], old_rgb[1], old_rgb[2]},
                            {new_rgb[0], new_rgb[1], new_rgb[2]},
                            {0.2f, 0.2f, 0.2f}};
  tb_renderer_text(r, 0.02, 0.95, 0.035, -1, (const float[3]){0.1f, 0.1f, 0.1f}, title);
  tb_renderer_legend(r, 0.89, blade ? 4 : 2, labels, rgbs);
  free(x), free(c), free(show);
  return rc ? -1 : tb_renderer_write_png(r, path, err);
}

int tb_mbs_cut(tb_model *m, const tb_step *in, tb_mbs_cut_times *o, tb_error *err) {
  tb_vec3 lo, hi;
  bbox(tb_model_positions(m), tb_model_npoints(m), &lo, &hi);
  int ax = hi.x - lo.x >= hi.y - lo.y ? 0 : 1; /* the long axis; the blade goes along the other */
  double mz = 0.1 * (hi.z - lo.z), z0 = lo.z - mz;
  tb_vec3 c = tb_scale(tb_add(lo, hi), 0.5), p[2];
  if (ax == 0) {
    double m = 0.1 * (hi.y - lo.y);
    p[0] = tb_v3(c.x, lo.y - m, z0), p[1] = tb_v3(c.x, hi.y + m, z0);
  } else {
    double m = 0.1 * (hi.x - lo.x);
    p[0] = tb_v3(lo.x - m, c.y, z0), p[1] = tb_v3(hi.x + m, c.y, z0);
  }
  tb_vec3 depth = tb_v3(0, 0, hi.z - lo.z + 2 * mz), path[2] = {p[0], p[0]};
  o->blade[0] = p[0], o->blade[1] = p[1], o->blade[2] = tb_add(p[1], depth);
  o->blade[3] = tb_add(p[0], depth);
  tb_cut_event ev = {TB_CUT_BEGIN, 0, NULL, depth};
  if (tb_model_cut(m, &ev, NULL, err)) return -1;
  for (int f = 1; f <= TB_MBS_CUT_FRAMES; f++) {
    path[1] = tb_add(p[0], tb_scale(tb_sub(p[1], p[0]), (double)f / TB_MBS_CUT_FRAMES));
    ev = (tb_cut_event){TB_CUT_MOVE, 2, path, depth};
    double mw, sw;
    tb_clock c0 = tb_clock_start();
    if (tb_model_cut(m, &ev, NULL, err)) return -1;
    tb_clock_ms(&c0, &mw, &o->move[f - 1]);
    tb_clock c1 = tb_clock_start();
    if (tb_model_step(m, in, err)) return -1;
    tb_clock_ms(&c1, &sw, &o->step[f - 1]);
    o->wall[f - 1] = mw + sw;
  }
  ev = (tb_cut_event){TB_CUT_END, 0, NULL, depth};
  memset(&o->st, 0, sizeof o->st);
  tb_clock c0 = tb_clock_start();
  if (tb_model_cut(m, &ev, &o->st, err)) return -1;
  tb_clock_ms(&c0, &o->end_wall, &o->end_cpu);
  return 0;
}

/* Table 1's cut of repetition w->nend into w's samples. */
static int cut(tb_model *m, const tb_step *in, row *w, tb_error *err) {
  tb_mbs_cut_times o;
  if (tb_mbs_cut(m, in, &o, err)) return -1;
  for (int f = 0; f < TB_MBS_CUT_FRAMES; f++) {
    w->move[w->ncut] = o.move[f], w->cstep[w->ncut] = o.step[f], w->cut_w[w->ncut] = o.wall[f];
    w->cut[w->ncut++] = o.move[f] + o.step[f];
  }
  w->end_w[w->nend] = o.end_wall, w->end[w->nend] = o.end_cpu;
  w->nend++;
  w->st = o.st;
  memcpy(w->blade, o.blade, sizeof w->blade);
  return 0;
}

/* One repetition on organ g: pack (timed), create, deform, cut, settle;
 * rep 0 also measures coverage and draws; later ones must end identical. */
static int run(const organ *g, int rep, const tb_mbs_plan *p, int grid, uint64_t seed,
               tb_renderer *r, const char *dir, const char *stem, row *w, tb_error *err) {
  tb_sphpack_def pd = tb_sphpack_default_def(g->spheres);
  pd.seed = seed % 2147483647u;
  tb_spheres sp = {0};
  char sph[1100] = "";
  if (g->given.n) { /* the model reads them from a file: the rotated ones, written here */
    snprintf(sph, sizeof sph, "%s/%s-z-up.sph", dir, stem);
    if (rep == 0 && tb_spheres_write(sph, &g->given, err)) return -1;
  } else {
    tb_clock c0 = tb_clock_start();
    if (tb_sphere_pack(&g->surf, g->name, &pd, &sp, NULL, err)) return -1;
    tb_clock_ms(&c0, &w->pack_w[w->npack], &w->pack[w->npack]);
    w->npack++;
  }
  if (rep == 0 &&
      tb_sphere_coverage_of(&g->surf, g->name, g->given.n ? &g->given : &sp, grid, &w->cov, err))
    return tb_spheres_free(&sp), -1;
  tb_spheres_free(&sp);
  tb_settings set;
  tb_settings_init(&set);
  if (g->given.n) {
    char kv[1200];
    snprintf(kv, sizeof kv, "spheres_file=%s", sph);
    if (tb_settings_set(&set, kv, err)) return -1;
  } else {
    tb_settings_setd(&set, "spheres", g->spheres, NULL);
    tb_settings_setd(&set, "seed", (double)pd.seed, NULL);
  }
  tb_model m;
  if (tb_model_create(&m, "metaball", &g->surf, &set, err)) return -1;
  tb_model_spheres ms = m.cls->spheres(m.self);
  w->nsph = ms.n, w->links = ms.nlinks;
  int *ids = NULL, rc = 0;
  tb_vec3 *at = NULL, lo, hi;
  bbox(g->surf.x, g->surf.nv, &lo, &hi);
  int nf = tb_mbs_end_holds(tb_model_positions(&m), tb_model_npoints(&m), &ids, &at, err);
  if (nf < 0) return tb_model_destroy(&m), -1;
  tb_step in = {.dt = TB_MBS_DT, .gravity = tb_v3(0, 0, -TB_MBS_G)};
  in.nfixed = nf, in.fixed = ids, in.fixed_x = at;
  if ((rc = tb_mbs_deform(&m, &in, p, w->deform_w + w->ndeform, w->deform + w->ndeform, err)))
    goto done;
  w->ndeform += p->nblocks;
  const tb_vec3 *x = tb_model_positions(&m);
  w->sag = 0;
  for (int i = 0; i < g->surf.nv; i++) w->sag = fmax(w->sag, tb_dist(x[i], g->surf.x[i]));
  char path[1200];
  if (rep == 0) {
    snprintf(path, sizeof path, "%s/%s-before.png", dir, stem);
    char title[160];
    snprintf(title, sizeof title, "%.60s before the cut: %d spheres, held at both ends, sagging",
             g->name, ms.n);
    if ((rc = picture(r, &m, ms.n, lo, hi, NULL, title, path, err))) goto done;
  }
  if ((rc = cut(&m, &in, w, err))) goto done;
  /* this repetition's medians: its blocks' and its cut frames' */
  w->rdeform[rep] = tb_stats_of(w->deform + w->ndeform - p->nblocks, p->nblocks).median;
  w->rdeform_w[rep] = tb_stats_of(w->deform_w + w->ndeform - p->nblocks, p->nblocks).median;
  w->rcut[rep] = tb_stats_of(w->cut + w->ncut - TB_MBS_CUT_FRAMES, TB_MBS_CUT_FRAMES).median;
  w->rcut_w[rep] = tb_stats_of(w->cut_w + w->ncut - TB_MBS_CUT_FRAMES, TB_MBS_CUT_FRAMES).median;
  w->nrep = rep + 1;
  for (int k = 0; k < AFTER_FRAMES && !rc; k++) rc = tb_model_step(&m, &in, err);
  if (rc) goto done;
  if (!tb_mbs_finite(&m)) {
    rc = tb_error_set(err, "metaball", 0, "NaN or inf after the cut");
    goto done;
  }
  tb_surface su = tb_model_surface(&m);
  if (rep == 0) {
    w->closed = tb_cut_is_closed_manifold(su.nv, su.ntri, su.tri);
    w->components = tb_cut_components(su.nv, su.ntri, su.tri);
    w->nv_after = su.nv, w->ntri_after = su.ntri, w->identical = 1;
    w->x_after = malloc(sizeof(tb_vec3) * (size_t)su.nv);
    w->tri_after = malloc(sizeof(int) * 3 * (size_t)su.ntri);
    if (!w->x_after || !w->tri_after) {
      rc = tb_error_set(err, "metaball", 0, "out of memory");
      goto done;
    }
    memcpy(w->x_after, su.x, sizeof(tb_vec3) * (size_t)su.nv);
    memcpy(w->tri_after, su.tri, sizeof(int) * 3 * (size_t)su.ntri);
    snprintf(path, sizeof path, "%s/%s-after.png", dir, stem);
    char title[160];
    snprintf(title, sizeof title, "%.60s, t = %g s after the cut (pieces drawn apart)", g->name,
             AFTER_FRAMES * TB_MBS_DT);
    rc = picture(r, &m, ms.n, lo, hi, w->blade, title, path, err);
  } else {
    w->identical &= su.nv == w->nv_after && su.ntri == w->ntri_after &&
                    !memcmp(su.x, w->x_after, sizeof(tb_vec3) * (size_t)su.nv) &&
                    !memcmp(su.tri, w->tri_after, sizeof(int) * 3 * (size_t)su.ntri);
  }
done:
  free(ids), free(at);
  tb_model_destroy(&m);
  return rc ? -1 : 0;
}

/* Room for reps repetitions of nblocks blocks; 0, or -1 when out of memory. */
static int row_alloc(row *x, int reps, int nblocks) {
  size_t r = (size_t)reps, d = r * (size_t)nblocks, c = r * TB_MBS_CUT_FRAMES;
  double *p = x->store = malloc(sizeof(double) * (8 * r + 2 * d + 4 * c));
  if (!p) return -1;
  double **per_rep[] = {&x->pack,    &x->pack_w, &x->end,       &x->end_w,
                        &x->rdeform, &x->rcut,   &x->rdeform_w, &x->rcut_w};
  for (size_t k = 0; k < 8; k++) *per_rep[k] = p, p += r;
  x->deform = p, p += d, x->deform_w = p, p += d;
  x->cut = p, p += c, x->cut_w = p, p += c, x->move = p, p += c, x->cstep = p;
  return 0;
}

static double med(const double *s, int n) { return n ? tb_stats_of(s, n).median : NAN; }

static void table1(tb_suite *su, const organ *g, const row *w, int n) {
  static const char *cols[] = {"organ",
                               "surface",
                               "vertices",
                               "spheres (ours)",
                               "spheres (patent)",
                               "links",
                               "packing CPU (ms)",
                               "volume in spheres (%)",
                               "vertices in skin reach (%)",
                               "deform CPU (ms/frame, ours)",
                               "deform (ms/frame, patent)",
                               "cut CPU (ms/frame, ours)",
                               "cut (ms/frame, patent)",
                               "cut's END CPU (ms)",
                               "largest sag before the cut",
                               "pieces after",
                               "closed 2-manifold after",
                               "deform wall (ms/frame, ours)",
                               "cut wall (ms/frame, ours)"};
  tb_table *t = tb_table_new("table1",
                             "Patent table 1: per organ, ms per frame to deform and to cut "
                             "(metaball model, dt 0.01, gravity, both ends held; one thread, CPU "
                             "time, the median of the repetitions' medians)",
                             19, cols);
  for (int k = 0; k < n; k++) {
    tb_table_row(t);
    tb_table_cell(t, "%s", g[k].name);
    tb_table_cell(t, "%s", g[k].source);
    tb_table_num(t, g[k].surf.nv ? g[k].surf.nv : NAN, "%.0f");
    if (!w[k].ok) {
      tb_table_cell(t, "failed: %s", w[k].why);
      for (int c = 4; c < 19; c++) tb_table_cell(t, "-");
      continue;
    }
    tb_table_num(t, w[k].nsph, "%.0f");
    tb_table_num(t, k < TB_NORGANS && isfinite(g[k].deform_ms) ? g[k].spheres : NAN, "%.0f");
    tb_table_num(t, w[k].links, "%.0f");
    tb_table_num(t, med(w[k].pack, w[k].npack), "%.0f");
    tb_table_num(t, 100 * w[k].cov.volume, "%.1f");
    tb_table_num(t, 100 * w[k].cov.reach, "%.1f");
    tb_table_num(t, med(w[k].rdeform, w[k].nrep), "%.3f");
    tb_table_num(t, g[k].deform_ms, "%.2f");
    tb_table_num(t, med(w[k].rcut, w[k].nrep), "%.3f");
    tb_table_num(t, g[k].cut_ms, "%.2f");
    tb_table_num(t, med(w[k].end, w[k].nend), "%.1f");
    tb_table_num(t, w[k].sag, "%.3f");
    tb_table_num(t, w[k].components, "%.0f");
    tb_table_cell(t, "%s", w[k].closed ? "yes" : "NO");
    tb_table_num(t, med(w[k].rdeform_w, w[k].nrep), "%.3f");
    tb_table_num(t, med(w[k].rcut_w, w[k].nrep), "%.3f");
  }
  tb_suite_table(su, t);
}

static void repack_table(tb_suite *su, const organ *g, const row *w, int n) {
  static const char *cols[] = {"organ",
                               "spheres removed",
                               "spheres created",
                               "created / removed",
                               "mean radius removed",
                               "mean radius created",
                               "radius created / removed",
                               "points of the point set",
                               "points no new sphere covers",
                               "surface triangles split",
                               "crack triangles",
                               "surface points added"};
  tb_table *t = tb_table_new("repack",
                             "The re-packing claim: spheres the blade removed against those made "
                             "anew from the point set (the patent: about twice as many, half the "
                             "size)",
                             12, cols);
  for (int k = 0; k < n; k++) {
    if (!w[k].ok) continue;
    const tb_cut_stats *s = &w[k].st;
    tb_table_row(t);
    tb_table_cell(t, "%s", g[k].name);
    tb_table_num(t, s->removed, "%.0f"), tb_table_num(t, s->created, "%.0f");
    tb_table_num(t, s->removed ? (double)s->created / s->removed : NAN, "%.2f");
    tb_table_num(t, s->removed_r, "%.4f"), tb_table_num(t, s->created_r, "%.4f");
    tb_table_num(t, s->removed_r > 0 ? s->created_r / s->removed_r : NAN, "%.2f");
    tb_table_num(t, s->points, "%.0f"), tb_table_num(t, s->uncovered, "%.0f");
    tb_table_num(t, s->split_tris, "%.0f"), tb_table_num(t, s->crack_tris, "%.0f");
    tb_table_num(t, s->new_points, "%.0f");
  }
  tb_suite_table(su, t);
}

/* §5 on the liver row (the first organ): each repetition's median frame
 * (CPU time, one thread), their median and 95% interval against the goal. */
static void goal_table(tb_suite *su, const organ *g, const row *w, int nblocks) {
  static const char *cols[] = {"organ",
                               "vertices",
                               "spheres",
                               "repetitions",
                               "deform CPU (ms/frame, 95% interval)",
                               "deform CPU low",
                               "deform CPU high",
                               "goal (ms)",
                               "deform goal",
                               "cut CPU (ms/frame, 95% interval)",
                               "cut CPU low",
                               "cut CPU high",
                               "goal (ms)",
                               "cut goal",
                               "of a cut frame: MOVE CPU (ms, median)",
                               "of a cut frame: step CPU (ms, median)",
                               "deform wall (ms/frame, median)",
                               "cut wall (ms/frame, median)",
                               "patent deform / cut (ms)"};
  tb_table *t = tb_table_new("goal",
                             "Speed goal: deform <= 1 ms and cut <= 2 ms per frame "
                             "on the 8128-vertex liver with 570 spheres (one thread, CPU time)",
                             19, cols);
  for (int c = 5; c <= 11; c++)
    if (c == 5 || c == 6 || c == 10 || c == 11) tb_table_only(t, c, TB_CSV_ONLY);
  tb_est nan = {NAN, NAN, NAN, 0};
  tb_est d = w->ok ? tb_median_est(w->rdeform, w->nrep) : nan;
  tb_est c = w->ok ? tb_median_est(w->rcut, w->nrep) : nan;
  char vd[200], vc[200];
  tb_verdict_text(d, GOAL_DEFORM, 0, vd, sizeof vd);
  tb_verdict_text(c, GOAL_CUT, 0, vc, sizeof vc);
  tb_table_row(t);
  tb_table_cell(t, "%s", g->name);
  tb_table_num(t, g->surf.nv, "%.0f");
  tb_table_num(t, w->ok ? w->nsph : NAN, "%.0f");
  tb_table_num(t, w->ok ? w->nrep : NAN, "%.0f");
  tb_table_est(t, d, "%.3f", "");
  tb_table_num(t, d.lo, "%.6g"), tb_table_num(t, d.hi, "%.6g");
  tb_table_num(t, GOAL_DEFORM, "%.0f");
  tb_table_cell(t, "%s", w->ok ? vd : "-");
  tb_table_est(t, c, "%.3f", "");
  tb_table_num(t, c.lo, "%.6g"), tb_table_num(t, c.hi, "%.6g");
  tb_table_num(t, GOAL_CUT, "%.0f");
  tb_table_cell(t, "%s", w->ok ? vc : "-");
  tb_table_num(t, w->ok ? med(w->move, w->ncut) : NAN, "%.3f");
  tb_table_num(t, w->ok ? med(w->cstep, w->ncut) : NAN, "%.3f");
  tb_table_num(t, w->ok ? med(w->rdeform_w, w->nrep) : NAN, "%.3f");
  tb_table_num(t, w->ok ? med(w->rcut_w, w->nrep) : NAN, "%.3f");
  tb_table_cell(t, "%.2f / %.2f", g->deform_ms, g->cut_ms);
  tb_suite_table(su, t);
  tb_suite_counter_est(su, "metaball/goal", "deform_ms", d);
  tb_suite_counter_est(su, "metaball/goal", "cut_ms", c);
  tb_suite_counter(su, "metaball/goal", "deform_verdict", tb_verdict(d, GOAL_DEFORM, 0));
  tb_suite_counter(su, "metaball/goal", "cut_verdict", tb_verdict(c, GOAL_CUT, 0));
  tb_suite_note(su,
                "The goal's verdicts: each of %d repetitions (each from scratch) gives its median "
                "frame (deform: over its %d blocks; cut: over its %d frames), CPU time on one "
                "thread; their median and its 95%% interval (order statistics) decide: met when "
                "the whole interval is within the goal, not met when it is all beyond, else "
                "inconclusive (noise, or fewer than %d repetitions).",
                w->nrep, nblocks, TB_MBS_CUT_FRAMES, TB_EST_MIN);
}

static void record(tb_suite *su, const organ *g, const row *w, const char *stem) {
  char name[96];
  snprintf(name, sizeof name, "metaball/%s/deform", stem);
  tb_suite_bench(su, name, w->deform_w, w->deform, w->ndeform, "ms");
  tb_suite_counter(su, name, "vertices", g->surf.nv);
  tb_suite_counter(su, name, "spheres", w->nsph);
  tb_suite_counter(su, name, "links", w->links);
  tb_suite_counter(su, name, "largest_sag", w->sag);
  if (isfinite(g->deform_ms)) tb_suite_counter(su, name, "patent_ms", g->deform_ms);
  snprintf(name, sizeof name, "metaball/%s/cut_frame", stem);
  tb_suite_bench(su, name, w->cut_w, w->cut, w->ncut, "ms");
  if (isfinite(g->cut_ms)) tb_suite_counter(su, name, "patent_ms", g->cut_ms);
  tb_suite_counter(su, name, "move_median_ms", med(w->move, w->ncut));
  tb_suite_counter(su, name, "step_median_ms", med(w->cstep, w->ncut));
  snprintf(name, sizeof name, "metaball/%s/cut_end", stem);
  tb_suite_bench(su, name, w->end_w, w->end, w->nend, "ms");
  const tb_cut_stats *s = &w->st;
  tb_suite_counter(su, name, "spheres_removed", s->removed);
  tb_suite_counter(su, name, "spheres_created", s->created);
  tb_suite_counter(su, name, "mean_radius_removed", s->removed_r);
  tb_suite_counter(su, name, "mean_radius_created", s->created_r);
  tb_suite_counter(su, name, "points", s->points);
  tb_suite_counter(su, name, "points_uncovered", s->uncovered);
  tb_suite_counter(su, name, "split_triangles", s->split_tris);
  tb_suite_counter(su, name, "crack_triangles", s->crack_tris);
  tb_suite_counter(su, name, "surface_points_added", s->new_points);
  tb_suite_counter(su, name, "pieces", w->components);
  tb_suite_counter(su, name, "closed_manifold", w->closed);
  tb_suite_counter(su, name, "identical_repetitions", w->identical);
  snprintf(name, sizeof name, "metaball/%s/pack", stem);
  if (w->npack) /* given spheres: none */
    tb_suite_bench(su, name, w->pack_w, w->pack, w->npack, "ms");
  tb_suite_counter(su, name, "volume_covered", w->cov.volume);
  tb_suite_counter(su, name, "skin_reach", w->cov.reach);
}

/* The file stem of an organ: its name, spaces and capitals made plain. */
static void stem_of(const char *name, char *out, size_t cap) {
  size_t k = 0;
  for (; name[k] && k + 1 < cap; k++)
    out[k] = name[k] == ' '                     ? '-'
             : name[k] >= 'A' && name[k] <= 'Z' ? name[k] - 'A' + 'a'
                                                : name[k];
  out[k] = 0;
}

int tb_suite_metaball(const tb_suite_opts *o) {
  uint64_t t0 = tb_time_ns();
  char dir[900], why[200];
  tb_error err;
  if (snprintf(dir, sizeof dir, "%s/metaball", o->results) >= (int)sizeof dir) return 1;
  tb_suite *su = tb_suite_begin(dir, "metaball",
                                "The metaball patent: organs of overlapping spheres driven by PBD, "
                                "cut by the hybrid sphere - point set - sphere method",
                                o->seed, &err);
  if (!su) return fprintf(stderr, "metaball: %s\n", err.msg), 1;
  /* the goal's verdicts rest on the repetitions: at least TB_EST_MIN but at --scale < 1 */
  int smoke = o->scale < 1, reps = smoke ? 2 : o->full ? 9 : TB_EST_MIN, failed = 0;
  int threads = tb_threads_setting();
  tb_threads_set(1); /* times against goals and between models: one thread, CPU time */
  tb_mbs_plan p = smoke     ? (tb_mbs_plan){5, 5, 2}
                  : o->full ? (tb_mbs_plan){20, 50, 10}
                            : (tb_mbs_plan){20, 25, 4};
  int grid = o->full ? 64 : 40;
  tb_renderer *r = tb_renderer_new(W, H, 2, &err);
  if (!r) {
    fprintf(stderr, "metaball: %s\n", err.msg);
    tb_suite_end(su, &err);
    return 1;
  }
  organ g[NMAX];
  row w[NMAX];
  memset(w, 0, sizeof w);
  int n = organs(smoke, o->seed, g, why, sizeof why);
  for (int k = 0; k < n; k++) {
    row *x = &w[k];
    char stem[40];
    stem_of(g[k].name, stem, sizeof stem);
    int rc = row_alloc(x, reps, p.nblocks) ? tb_error_set(&err, "metaball", 0, "out of memory")
             : !g[k].surf.nv               ? tb_error_set(&err, "metaball", 0, "%s", g[k].source)
                                           : 0;
    for (int q = 0; q < reps && !rc; q++) {
      tb_progress("metaball", k * reps + q, n * reps + 1);
      rc = run(&g[k], q, &p, grid, o->seed, r, dir, stem, x, &err);
    }
    x->ok = !rc;
    if (rc) {
      snprintf(x->why, sizeof x->why, "%.190s", err.msg);
      fprintf(stderr, "metaball: %s: %s\n", g[k].name, err.msg), failed = 1;
      continue;
    }
    failed |= !x->identical || !x->closed;
    record(su, &g[k], x, stem);
  }
  const tb_context *cx = tb_suite_context(su);
  tb_suite_note(
      su,
      "The patent's table 1 gives, per organ, its surface vertices and spheres and the time per "
      "frame to deform and to cut (its machine not named). Ours: the organ's closed surface "
      "(meshgen/organs.c: synthetic grey-value volumes, marching cubes, exactly the patent's "
      "vertex "
      "count) packed by tb_sphere_pack (inner Voronoi poles, CGAL) to the patent's sphere count, "
      "the metaball model at its defaults (models/metaball_model.c) with that count; packing: "
      "tb_sphere_pack alone (the model packs again when it is created); coverage on a %d-point "
      "grid along the longest side (tb_sphere_coverage_of). Deform: dt %g, gravity %g along -z, "
      "the points within %g of the long extent of each end held; %d warm frames, then %d blocks "
      "of %d frames, each block's mean one sample; the model's step alone timed, on one thread, "
      "CPU time (wall beside). Cut: after "
      "those frames, a straight blade across the shorter horizontal extent at the middle of the "
      "longer, its depth through the whole thickness (+10%% each side), crossing in %d frames; "
      "a frame is the MOVE event (the blade's path so far) and the step (the same gravity and "
      "holds), each frame one sample; END (the spheres re-made from the point set, the surface "
      "split and closed) timed apart. Then %d frames more before the after picture. Each of %d "
      "repetitions, each from scratch (packing, model, frames, cut), gives its median frame; "
      "the table shows the median of those (END and packing: of the repetitions); every "
      "repetition's "
      "surface after the cut is bit-identical to the first's: %s. SOFA liver-smooth: %s. This "
      "machine: %s (%d cores), timed on %d thread (the skin, the point set's forces and bound "
      "can take more; the same bits on any count), load average %.2f at the start.",
      grid, TB_MBS_DT, TB_MBS_G, TB_MBS_END_SHARE, p.warm, p.nblocks, p.block, TB_MBS_CUT_FRAMES,
      AFTER_FRAMES, reps, failed ? "NO (or a run failed)" : "yes",
      why[0] ? why
             : "liver.sph's spheres (34) and the surface rotated so that SOFA's up (y) is z, the "
               "spheres written to sofa-liver-smooth-z-up.sph and given to the model "
               "(spheres_file); no packing, so no packing time",
      cx->cpu, cx->cores, tb_threads(), cx->have_load ? cx->load[0] : NAN);
  table1(su, g, w, n);
  repack_table(su, g, w, n);
  tb_suite_note(su,
                "From the cut's END (tb_cut_stats): the spheres the blade touched became a point "
                "set (cut_points per sphere); when the blade left, new spheres were placed on the "
                "medial axis of the point set's boundary points; the points no new sphere covers "
                "are dropped. Radii in the organ's units (the liver about 10 long).");
  if (!smoke) goal_table(su, &g[0], &w[0], p.nblocks);
  for (int k = 0; k < n; k++) {
    if (!w[k].ok) continue;
    char stem[40], f[64];
    stem_of(g[k].name, stem, sizeof stem);
    for (int a = 0; a < 2; a++) {
      snprintf(f, sizeof f, "%s-%s.png", stem, a ? "after" : "before");
      tb_suite_figure(
          su, f,
          "Figs 7-10: the %s %s the cut (%s): above, the spheres (drawn at %.2f of their "
          "radius; orange: made at the cut) and their links; below, the skinned "
          "surface",
          g[k].name, a ? "after" : "before",
          a ? "50 frames after the blade left, both ends held" : "hanging by its ends",
          SPHERE_SCALE);
    }
  }
  tb_progress("metaball", n * reps, n * reps + 1);
  failed |= tb_mbs_compare(su, o);
  tb_progress_done();
  tb_threads_set(threads);
  double wall = (double)(tb_time_ns() - t0) * 1e-9;
  tb_suite_counter(su, "suite", "wall_time_s", wall);
  tb_suite_note(su, "The suite took %.1f s in all.", wall);
  for (int k = 0; k < n; k++) {
    free(w[k].store);
    free(w[k].x_after), free(w[k].tri_after), tb_mesh_free(&g[k].surf),
        tb_spheres_free(&g[k].given);
  }
  tb_renderer_free(r);
  if (tb_suite_end(su, &err)) fprintf(stderr, "metaball: %s\n", err.msg), failed = 1;
  return failed;
}
