/* Timing of the metaball cut (the goal: a cut frame <= 2 ms) and of the
 * re-packing against the patent's "about twice as many, half the size".
 * The patent's liver (or the organ named by the 4th argument):
 * tb_organ_surface at 8128 vertices, packed to 570 spheres (tb_sphere_pack;
 * the organ's patent counts), the ten largest fixed, under gravity. A
 * blade enters above it and crosses it along y at mid x in `frames`
 * frames, its path bending gently in x (a folded plane of frames + 1
 * points) and reaching below the liver. Per frame: tb_metaball_cut_advance
 * + tb_metaball_cut_step, timed together and apart; then
 * tb_metaball_cut_end. Prints the median and worst ms per cut frame, the
 * cut_end ms and its report (CPU time: the thread's on one thread, else the
 * process's; wall time beside), and for reference the median of a plain
 * tb_metaball_step of the same organ uncut (inside every cut frame: the
 * cut's own share is the difference).
 *
 *   ./build/metaball_cut_timing [frames] [per_sphere (0: the shared grid)] [spacing]
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "core/tb_threads.h"
#include "core/tb_timer.h"
#include "cutting/tb_fold.h"
#include "meshgen/tb_meshgen.h"
#include "meshgen/tb_sphpack.h"
#include "models/tb_metaball.h"

static int cmp(const void *a, const void *b) {
  double x = *(const double *)a, y = *(const double *)b;
  return (x > y) - (x < y);
}

int main(int argc, char **argv) {
  int frames = argc > 1 ? atoi(argv[1]) : 20;
  tb_metaball_cut_settings cs;
  tb_metaball_cut_settings_default(&cs);
  if (argc > 2) cs.per_sphere = atoi(argv[2]);
  if (argc > 3) cs.spacing = atof(argv[3]);
  if (frames < 1 || frames > 1000) return fprintf(stderr, "frames in 1 .. 1000\n"), 2;
  tb_error err;
  tb_mesh surf;
  const char *organ = argc > 4 ? argv[4] : "liver";
  const tb_organ_info *info = tb_organ_find(organ);
  if (!info) return fprintf(stderr, "unknown organ '%s'\n", organ), 2;
  if (tb_organ_surface(organ, 0, 1, &surf, &err)) return fprintf(stderr, "%s\n", err.msg), 1;
  tb_sphpack_def pd = tb_sphpack_default_def(info->spheres);
  tb_spheres sp = {0};
  if (tb_sphere_pack(&surf, organ, &pd, &sp, NULL, &err))
    return fprintf(stderr, "%s\n", err.msg), 1;
  tb_metaball_settings set;
  tb_metaball_settings_default(&set);
  tb_metaball *m = tb_metaball_create(sp.n, sp.c, sp.r, &surf, &set, &err);
  if (!m) return fprintf(stderr, "%s\n", err.msg), 1;
  for (int i = 0; i < 10; i++) tb_metaball_fix(m, i, 1); /* the largest ten hold it */
  if (tb_metaball_cut_begin(m, &cs, &err)) return fprintf(stderr, "%s\n", err.msg), 1;
  tb_vec3 lo = sp.c[0], hi = sp.c[0];
  for (int i = 0; i < sp.n; i++) {
    tb_vec3 r = tb_v3(sp.r[i], sp.r[i], sp.r[i]);
    lo = tb_vmin(lo, tb_sub(sp.c[i], r)), hi = tb_vmax(hi, tb_add(sp.c[i], r));
  }
  double xm = 0.5 * (lo.x + hi.x), wy = hi.y - lo.y, wx = hi.x - lo.x;
  tb_vec3 *path = malloc(sizeof(tb_vec3) * (size_t)(frames + 1));
  /* per frame: CPU and wall ms; the advance's and the cut step's sums */
  double *ms = malloc(sizeof(double) * 2 * (size_t)frames), *wms = ms ? ms + frames : NULL;
  double adv = 0, stp = 0, adv_w = 0, stp_w = 0;
  if (!path || !ms) return fprintf(stderr, "out of memory\n"), 1;
  for (int k = 0; k <= frames; k++) {
    double t = (double)k / frames;
    path[k] = tb_v3(xm + 0.08 * wx * sin(M_PI * t), lo.y - 0.1 * wy + t * 1.2 * wy,
                    hi.z + 0.1 * (hi.z - lo.z));
  }
  tb_vec3 depth = tb_v3(0, 0, -1.2 * (hi.z - lo.z));
  int substeps = 0, maxsub = 0;
  for (int k = 1; k <= frames; k++) {
    tb_fold f;
    if (tb_fold_init(&f, path, k + 1, depth, &err)) return fprintf(stderr, "%s\n", err.msg), 1;
    double aw, ac, sw = 0, sc = 0;
    tb_clock c0 = tb_clock_start();
    int rc = tb_metaball_cut_advance(m, &f, &err) < 0;
    tb_clock_ms(&c0, &aw, &ac);
    tb_clock c1 = tb_clock_start();
    rc = rc || tb_metaball_cut_step(m, 0.01, tb_v3(0, 0, -9.81), NULL, &err);
    tb_clock_ms(&c1, &sw, &sc);
    tb_fold_free(&f);
    if (rc) return fprintf(stderr, "frame %d: %s\n", k, err.msg), 1;
    ms[k - 1] = ac + sc, wms[k - 1] = aw + sw;
    adv += ac, stp += sc, adv_w += aw, stp_w += sw;
    substeps += tb_metaball_cut_substeps(m);
    if (tb_metaball_cut_substeps(m) > maxsub) maxsub = tb_metaball_cut_substeps(m);
  }
  tb_metaball *plain = tb_metaball_create(sp.n, sp.c, sp.r, &surf, &set, &err);
  if (!plain) return fprintf(stderr, "%s\n", err.msg), 1;
  double *pms = malloc(sizeof(double) * 2 * (size_t)frames), *pwms = pms ? pms + frames : NULL;
  if (!pms) return fprintf(stderr, "out of memory\n"), 1;
  for (int i = 0; i < 10; i++) tb_metaball_fix(plain, i, 1);
  for (int k = 0; k < frames; k++) {
    tb_clock c0 = tb_clock_start();
    tb_metaball_step(plain, 0.01, tb_v3(0, 0, -9.81), NULL);
    tb_clock_ms(&c0, pwms + k, pms + k);
  }
  qsort(pms, (size_t)frames, sizeof(double), cmp);
  qsort(pwms, (size_t)frames, sizeof(double), cmp);
  tb_metaball_destroy(plain);
  int np = tb_metaball_cut_points(m, NULL), driven = 0;
  for (int p = 0; p < np; p++) driven += tb_metaball_cut_driver(m, p) != -1;
  double omega = tb_metaball_cut_omega(m);
  tb_metaball_cut_report rep;
  double end_ms, end_wall;
  tb_clock c0 = tb_clock_start();
  if (tb_metaball_cut_end(m, &rep, &err)) return fprintf(stderr, "%s\n", err.msg), 1;
  tb_clock_ms(&c0, &end_wall, &end_ms);
  qsort(ms, (size_t)frames, sizeof(double), cmp);
  qsort(wms, (size_t)frames, sizeof(double), cmp);
  printf("%s: %d vertices, %d spheres; cut in %d frames, %s; %d thread%s\n", organ, surf.nv, sp.n,
         frames, cs.per_sphere > 0 ? "per-sphere sampling" : "shared grid", tb_threads(),
         tb_threads() > 1 ? "s" : "");
  printf(
      "cut frame (advance + cut_step): CPU median %.3f ms, worst %.3f ms; wall median %.3f ms, "
      "worst %.3f ms; mean advance %.3f ms CPU (%.3f wall), mean cut_step %.3f ms CPU (%.3f "
      "wall); %d points (%d driven), meshless substeps %.1f a frame (at most %d; omega %.0f "
      "rad/s at the end)\n",
      ms[frames / 2], ms[frames - 1], wms[frames / 2], wms[frames - 1], adv / frames,
      adv_w / frames, stp / frames, stp_w / frames, np, driven, (double)substeps / frames, maxsub,
      omega);
  printf(
      "cut_end %.2f ms CPU (%.2f wall): %d spheres removed (mean r %.3f) -> %d created (mean r "
      "%.3f): "
      "%.2fx as many, %.2fx the size; %d points, %d boundary, %d candidates, %d uncovered, %d "
      "dropped\n",
      end_ms, end_wall, rep.removed, rep.removed_r, rep.created, rep.created_r,
      rep.removed ? (double)rep.created / rep.removed : 0,
      rep.removed_r > 0 ? rep.created_r / rep.removed_r : 0, rep.points, rep.boundary,
      rep.candidates, rep.uncovered, rep.dropped);
  printf(
      "for reference, tb_metaball_step uncut: CPU median %.3f ms, wall median %.3f ms (the "
      "cut's own share of a frame, CPU: %.3f ms)\n",
      pms[frames / 2], pwms[frames / 2], ms[frames / 2] - pms[frames / 2]);
  free(path), free(ms), free(pms);
  tb_metaball_destroy(m);
  tb_spheres_free(&sp);
  tb_mesh_free(&surf);
  return 0;
}
