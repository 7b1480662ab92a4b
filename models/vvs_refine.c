/* Dynamic local refinement of msm-vvs (Bao et al. 2006, §3.2-3.3): the
 * surface is refined around the points under stress and coarsened where
 * the stress has gone, over butterfly levels precomputed at create
 * (models/lod.c).
 *
 * Criterion (§3.2). The paper refines where "the force on a node" passes a
 * threshold. The net force on a node tends to zero as a quasi-static body
 * settles, so the measure here is the node's stress: the sum of its
 * springs' force magnitudes, sum_j k |l_ij - R_ij|, divided by the square
 * root of its area share (its surface area over a base point's). Under a
 * strain e a spring of length h stretches by e h, so the sum goes as k e h
 * and the share as h^2: divided by the share itself (a force per area) the
 * same strain would score twice as high on each finer level, and
 * refinement would feed itself (and keep growing after a release); over
 * its square root the measure is k e, the same at every level, and a level
 * is chosen by the strain field alone. At a base point (share about 1)
 * both are the force on it.
 * A point whose stress reaches refine_force deepens by one level (its
 * depth becomes one more than the level it was born on, up to the finest);
 * one below coarsen_share x refine_force goes back a level; between the
 * two it stays (hysteresis). The criterion is checked after every
 * refine_every-th step (the stresses summed then, not in every step), so
 * the next step's forces see the new surface. When a depth changes the
 * surface is rebuilt
 * from the base with every point's depth (tb_lod_apply): a smaller
 * threshold spreads refinement further, as the paper says.
 *
 * A point coming on is placed on the butterfly surface of the deformed
 * coarser level: its rest position (the butterfly point of the rest
 * positions) plus the butterfly point of the displacements of its edge's
 * level (the stencil is linear with weights summing to 1, so a rigid motion
 * of the coarser level moves it rigidly too; the ends' mean was up to 12%
 * of an edge off on a bent surface). A stencil point not on the surface
 * takes the mean displacement of the ends of the edge it was born on
 * (ascending order serves parents first). Its velocity is the mean of the
 * ends'. A point going off is parked: not simulated, velocity 0.
 *
 * Physical constants when the resolution changes (§3.3 "adjust the
 * model's physical parameters"): the total mass is kept, shared by area
 * (a third of each adjacent triangle's rest area); the damping d_i and the
 * virtual spring k'_s, k'_d scale with the same share, so that they stay
 * per unit area; the surface springs keep ks, since a triangulated sheet of
 * springs of stiffness k has an in-plane stiffness that does not depend on
 * its edge length (halving the edges halves each spring's stretch and
 * doubles the springs across a cut). So a base point's share is about 1 and
 * a point of level 1 about 1/4.
 *
 * The quasi-static update dx = alpha F dt^2 / m has no inertia: its mass
 * only sizes the step, and the step is stable while alpha dt^2 K_i / m_i
 * stays below about 1 (K_i: the point's springs' k summed, with k'_s; the
 * model's head comment). A point of level l holds 4^-l of the mass but
 * meets springs as stiff as a base point's, so its step grows 4^l times:
 * at the scenes' alpha 50 level 1 is at 0.37, level 2 at 1.5 and blew up.
 * Refining, the step's mass is therefore at least 2 alpha dt^2 K_i (a
 * Jacobi bound, 0.5): base and level-1 points keep their own, finer ones
 * take smaller steps. The equilibrium does not depend on it. The Euler
 * integrator keeps each point's mass (the dynamics; finer levels then need
 * a smaller dt, and the health check says so). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "vvs_priv.h"
#include "core/tb_butterfly.h"

int vvs_refine_init(vvs *s, const tb_mesh *mesh, tb_error *err) {
  s->lod = calloc(1, sizeof *s->lod);
  if (!s->lod) return tb_error_set(err, "msm-vvs", 0, "out of memory");
  if (tb_lod_create(s->lod, mesh, s->set.levels, err)) {
    free(s->lod), s->lod = NULL;
    return -1;
  }
  const tb_lod *lod = s->lod;
  size_t nv = (size_t)lod->nv;
  if (vvs_alloc(s, lod->nv, lod->level_nf[lod->nlevels - 1], err)) return -1;
  s->depth = calloc(nv, 1), s->share = calloc(nv, sizeof(double));
  s->stress = calloc(nv, sizeof(double)), s->kdiag = calloc(nv, sizeof(double));
  s->qinv = calloc(nv, sizeof(double));
  s->barea = calloc((size_t)lod->level_nv[0], sizeof(double));
  s->bload = calloc((size_t)lod->level_nv[0], sizeof(tb_vec3));
  s->u = calloc(nv, sizeof(tb_vec3));
  if (!s->depth || !s->share || !s->stress || !s->kdiag || !s->qinv || !s->barea || !s->bload ||
      !s->u)
    return tb_error_set(err, "msm-vvs", 0, "out of memory (%d points over %d levels)", lod->nv,
                        lod->nlevels);
  memcpy(s->x0, lod->rest, sizeof(tb_vec3) * nv);
  memcpy(s->x, lod->rest, sizeof(tb_vec3) * nv);
  for (int b = 0; b < lod->level_nf[0]; b++) {
    const int *t = lod->tri[0] + 3 * b;
    double a = tb_tri_area(lod->rest[t[0]], lod->rest[t[1]], lod->rest[t[2]]) / 3;
    for (int k = 0; k < 3; k++) s->barea[t[k]] += a;
  }
  return 0;
}

/* Loads (§4's press) through the current surface, not on the base points
 * alone, so refinement sees the load it is to resolve: base point i's
 * force is a traction f_i / A_i over its rest area share A_i, linear over
 * each base triangle B; a surface triangle of B's tree, of parametric
 * share phi of B (4^-l for a leaf of level l, half of that for each of a
 * transition band's two), gives each of its corners A_B phi / 3 times the
 * traction at that corner's place in B (its rest position's barycentric
 * coordinates there). On the base surface that is every point's own force
 * back; refined, the same total over more points (exactly when the corners
 * lie in B's plane, as a plane patch's do). */
static void barycentric(tb_vec3 p, tb_vec3 a, tb_vec3 b, tb_vec3 c, double w[3]) {
  tb_vec3 e1 = tb_sub(b, a), e2 = tb_sub(c, a), d = tb_sub(p, a);
  double g11 = tb_dot(e1, e1), g12 = tb_dot(e1, e2), g22 = tb_dot(e2, e2);
  double r1 = tb_dot(d, e1), r2 = tb_dot(d, e2), det = g11 * g22 - g12 * g12;
  double u = det > 0 ? (g22 * r1 - g12 * r2) / det : 0,
         v = det > 0 ? (g11 * r2 - g12 * r1) / det : 0;
  w[1] = fmax(0, u), w[2] = fmax(0, v), w[0] = fmax(0, 1 - u - v);
  double sum = w[0] + w[1] + w[2];
  for (int k = 0; k < 3; k++) w[k] = sum > 0 ? w[k] / sum : 1.0 / 3;
}

void vvs_refine_loads(vvs *s, const tb_vec3 *force) {
  const tb_lod *lod = s->lod;
  const int nb = s->nbase;
  int any = 0;
  for (int i = 0; i < nb; i++) {
    s->bload[i] = s->barea[i] > 0 ? tb_scale(force[i], 1 / s->barea[i]) : tb_v3(0, 0, 0);
    any |= force[i].x != 0 || force[i].y != 0 || force[i].z != 0;
  }
  for (int q = 0; q < s->nsim; q++) s->f[s->sim[q]] = tb_v3(0, 0, 0);
  if (!any) return;
  for (int t = 0; t < lod->ntri; t++) {
    int f, l = tb_lod_level(lod, lod->out_leaf[t], &f), base = f >> (2 * l);
    int pair = (t > 0 && lod->out_leaf[t - 1] == lod->out_leaf[t]) ||
               (t + 1 < lod->ntri && lod->out_leaf[t + 1] == lod->out_leaf[t]);
    const int *B = lod->tri[0] + 3 * base, *T = lod->out_tri + 3 * t;
    if (tb_len(s->bload[B[0]]) + tb_len(s->bload[B[1]]) + tb_len(s->bload[B[2]]) == 0) continue;
    const tb_vec3 *X = lod->rest;
    double share =
        tb_tri_area(X[B[0]], X[B[1]], X[B[2]]) / (double)(1 << (2 * l)) / (pair ? 2 : 1) / 3;
    for (int k = 0; k < 3; k++) {
      double w[3];
      barycentric(X[T[k]], X[B[0]], X[B[1]], X[B[2]], w);
      tb_vec3 load = tb_scale(s->bload[B[0]], w[0]);
      load = tb_madd(tb_madd(load, w[1], s->bload[B[1]]), w[2], s->bload[B[2]]);
      s->f[T[k]] = tb_madd(s->f[T[k]], share, load);
    }
  }
}

void vvs_refine_params(vvs *s) {
  double *a = s->share, total = 0;
  if (!(s->mass_base > 0)) /* the masses create gave the mesh's nodes */
    for (int i = 0; i < s->nbase; i++) s->mass_base += s->mass[i];
  for (int q = 0; q < s->nsim; q++) a[s->sim[q]] = 0;
  for (int t = 0; t < s->ntri; t++) {
    const int *n = s->tri + 3 * t;
    double at = tb_tri_area(s->x0[n[0]], s->x0[n[1]], s->x0[n[2]]);
    for (int c = 0; c < 3; c++) a[n[c]] += at / 3;
    total += at;
  }
  double per = total / s->nbase, vs = s->set.volume_springs ? 1.0 : 0.0;
  for (int q = 0; q < s->nsim; q++) {
    const int i = s->sim[q];
    double sh = a[i] /= per;
    s->mass[i] = s->mass_base / s->nbase * sh, s->invm[i] = 1 / s->mass[i];
    s->d[i] = s->set.kd * sh, s->ksv[i] = vs * s->set.ks_v * sh, s->kdv[i] = vs * s->set.kd_v * sh;
    s->kdiag[i] = s->ksv[i];
  }
  for (int e = 0; e < s->ns; e++)
    s->kdiag[s->ij[2 * e]] += s->k[e], s->kdiag[s->ij[2 * e + 1]] += s->k[e];
  s->qh = 0; /* the step's masses anew */
}

void vvs_refine_steps(vvs *s, double h) {
  for (int q = 0; q < s->nsim; q++) {
    const int i = s->sim[q];
    s->qinv[i] = 1 / fmax(s->mass[i], 2 * h * s->kdiag[i]);
  }
  s->qh = h;
}

/* Each simulated point's stress, sum_j k |l_ij - R_ij| (the criterion). */
static void stresses(vvs *s) {
  for (int q = 0; q < s->nsim; q++) s->stress[s->sim[q]] = 0;
  for (int e = 0; e < s->ns; e++) {
    const int i = s->ij[2 * e], j = s->ij[2 * e + 1];
    double a = s->k[e] * fabs(tb_dist(s->x[i], s->x[j]) - s->len0[e]);
    s->stress[i] += a, s->stress[j] += a;
  }
}

/* The level a point was born on. */
static int birth(const tb_lod *lod, int i) {
  int l = 0;
  while (i >= lod->level_nv[l]) l++;
  return l;
}

/* The butterfly point of displacements u on the edge of level birth - 1
 * that point i was born on. */
static tb_vec3 born_at(const tb_lod *lod, const tb_vec3 *u, int i) {
  const int l = birth(lod, i) - 1, a = lod->ends[2 * i], b = lod->ends[2 * i + 1];
  const tb_halfedge he = {lod->level_nv[l], lod->level_nf[l], lod->tri[l], lod->pair[l],
                          lod->out[l]};
  int h0 = lod->out[l][a], h = h0;
  while (lod->tri[l][tb_he_next(h)] != b) { /* around a to the half-edge a -> b */
    h = lod->pair[l][tb_he_prev(h)];
    if (h == h0) return tb_scale(tb_add(u[a], u[b]), 0.5); /* not an edge of level l */
  }
  return tb_butterfly_point(&he, u, h);
}

int vvs_refine_step(vvs *s) {
  tb_lod *lod = s->lod;
  const double hi = s->set.refine_force, lo = hi * s->set.coarsen_share;
  const int deepest = lod->nlevels - 1;
  int changed = 0;
  stresses(s);
  for (int q = 0; q < s->nsim; q++) {
    const int i = s->sim[q], d = s->depth[i];
    const double st = s->stress[i], sh = s->share[i];
    int nd = d;
    if (st >= hi * sqrt(sh)) { /* deeper, unless born on the finest level */
      int b = birth(lod, i);
      int up = (d > b ? d : b) + 1;
      if (b < deepest) nd = up < deepest ? up : deepest;
    } else if (d > 0 && st < lo * sqrt(sh)) {
      int b = birth(lod, i);
      nd = d - 1 > b ? d - 1 : 0; /* a depth at or below the birth level does nothing */
    }
    if (nd != d) s->depth[i] = (unsigned char)nd, changed = 1;
  }
  if (!changed) return 0;
  tb_lod_apply(lod, s->depth);
  if (lod->ntri == s->ntri && !memcmp(lod->out_tri, s->tri, sizeof(int) * 3 * (size_t)s->ntri))
    return 0;        /* another point's depth holds the same faces split */
  tb_vec3 *u = s->u; /* the displacements, ascending: an edge's ends come first */
  for (int i = 0; i < s->nbase; i++) u[i] = tb_sub(s->x[i], s->x0[i]);
  for (int i = s->nbase; i < s->nv; i++) {
    int on = lod->active[i], was = s->follow[i] == VVS_SIM;
    const int a = lod->ends[2 * i], b = lod->ends[2 * i + 1];
    if (on && !was) {
      s->x[i] = tb_add(s->x0[i], born_at(lod, u, i));
      s->v[i] = tb_scale(tb_add(s->v[a], s->v[b]), 0.5);
      s->follow[i] = VVS_SIM;
    } else if (!on && was) {
      s->follow[i] = VVS_OFF, s->v[i] = tb_v3(0, 0, 0), s->depth[i] = 0;
    }
    u[i] = on ? tb_sub(s->x[i], s->x0[i]) : tb_scale(tb_add(u[a], u[b]), 0.5);
  }
  s->ntri = lod->ntri;
  memcpy(s->tri, lod->out_tri, sizeof(int) * 3 * (size_t)lod->ntri);
  vvs_build_springs(s, s->ntri, s->tri, 1);
  vvs_refine_params(s);
  s->refinements++;
  return 1;
}
