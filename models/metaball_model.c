/* The metaball model behind the model interface (the metaball
 * patent's step 1 (SPH spheres from the OBJ surface by a Voronoi analysis)
 * and step 2 (PBD on the spheres, Gaussian skin); models/metaball.c does
 * the spheres and the skin, meshgen/sphpack.c the packing).
 *
 * Create: a closed triangle surface (surface_mesh), or a tet mesh whose
 * boundary triangles are that surface. The surface is packed with
 * tb_sphere_pack to `spheres` spheres (0: the patent's ratio, 570 spheres
 * for the 8128-vertex liver, i.e. round(nsurf * 570 / 8128) surface
 * vertices, within [40, 600] so that a coarse beam still has enough and
 * create stays fast), then tb_metaball_create binds every node. Or the
 * spheres come from a SOFA .sph file (spheres_file; SOFA's liver.sph for its
 * liver-smooth), read by tb_spheres_read, with spheres left at 0.
 *
 * Points. The model's points are the mesh's nodes, skinned: a surface
 * vertex by the patent's Gaussian rule (at most 3 spheres with
 * 1 <= d / r <= 2); a tet mesh's interior node (inside spheres, d / r < 1)
 * by the same rule's fallback, the one sphere of smallest d / r, so it
 * moves rigidly with it. A point's velocity is its skin's displacement
 * over the step / dt (a prescribed point's: its own), so a point let go
 * after being prescribed, or put elsewhere by the contact response, goes
 * back onto the skin without a velocity spike.
 *
 * Masses. The body's mass M is density * enclosed volume (node_mass > 0:
 * node_mass * nodes); sphere s gets M r_s^3 / sum r^3 (spheres overlap, so
 * density * 4/3 pi r^3 would count the overlaps twice). A point's mass is
 * its share of its spheres' masses, m_v = sum_s m_s w_vs / W_s with
 * W_s = sum_v w_vs over the points bound to s (a sphere no point is bound
 * to gives its mass to the point nearest its centre), so the point
 * masses sum to M. Forces: a node force f_v acts on its spheres as
 * w_vs f_v (the transpose of the skin); gravity acts on the spheres.
 *
 * Prescribed nodes. Each one holds, for the step, the one of its bound
 * spheres whose centre is nearest to it at rest (so a hold is local: on a
 * ball every vertex is also bound to the big central sphere, whose d / r
 * is the smallest): that sphere follows the rigid motion that best maps its
 * prescribed points' rest positions onto their targets (centroids, and
 * the rotation of the polar decomposition of their covariance, iterated from
 * the last one by tb_metaball_turns, when there
 * are 3 or more; else it keeps its rotation), and it is fixed for the
 * step: it does not move in the sweeps and its unit constraint keeps that
 * rotation (models/metaball.c), so the body follows it without pivoting
 * about it; after the skin the prescribed nodes are put exactly at their
 * targets, with the velocity that moved them there. Between them
 * and their free neighbours the skin is as smooth as the spheres allow.
 *
 * Damping. `damping` (per second) damps the spheres' velocities relative
 * to the body's rigid motion (Müller et al. 2007, "Position based
 * dynamics", §3.5): v_s += (1 - exp(-damping dt)) (v_cm + w x r_s - v_s),
 * so a free fall and a free rotation are not slowed (the scenes' `drag`
 * is the ambient damping). models/metaball.c's own absolute damping is
 * off (0) in this model.
 *
 * Ground (own_ground). After the sweeps the skin is computed; a point
 * below the plane by h pushes each of its spheres up along the normal by
 * at least h (a sphere takes the largest push of its points), so every
 * point ends on or above the plane (the weights sum to 1); Coulomb
 * friction acts on the pushed spheres as a contact (tb_ground_friction,
 * models/ground.c); a pushed sphere loses the part of its velocity into
 * the ground, the rest kept: the contact is inelastic (restitution is
 * not used). Points left below by rounding go onto the plane.
 *
 * Cutting (tb_model_cut; models/metaball_model_cut.c): while a blade
 * moves the step runs the coupled spheres + point set frame
 * (tb_metaball_cut_step); after it the surface has more vertices, so the
 * points are the mesh's nodes followed by the cut's new vertices, with
 * rest positions surface().x0; the settings cut_points and cut_E shape the
 * point set.
 *
 * energy(): NAN. The constraints' stiffnesses are PBD's [0, 1] shares of
 * a projection, not a potential, so the model has no energy; the scene's
 * detector checks NaN and the velocity bound. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "metaball_model_priv.h"
#include "meshgen/tb_sphpack.h"

static void destroy(void *self) {
  mb_model *s = self;
  if (!s) return;
  tb_metaball_destroy(s->mb);
  free(s->x), free(s->v), free(s->skin0), free(s->presc), free(s->mass), free(s->fs),
      free(s->cstart);
  free(s->hold), free(s->hold0), free(s->apq), free(s->nhold), free(s->held), free(s->push),
      free(s->keep), free(s->cids);
  free(s->cp), free(s->cdepth), free(s->dominant), free(s->tri);
  if (s->have_fold) tb_fold_free(&s->fold);
  free(s);
}

/* The sphere count: the setting, or the patent's ratio (see the head). */
static int sphere_count(const mb_settings *set, int nsurf) {
  if (set->spheres > 0) return set->spheres;
  long n = lround(nsurf * 570.0 / 8128.0);
  return (int)(n < 40 ? 40 : n > 600 ? 600 : n);
}

/* Point masses as shares of the alive spheres' masses (see the head): a
 * sphere no point is bound to gives its mass to the point nearest its
 * centre. Also each point's dominant sphere (the bound one nearest at
 * rest), which a prescribed point holds. */
int mb_share_masses(mb_model *s, tb_error *err) {
  tb_metaball *m = s->mb;
  double *W = calloc((size_t)m->n, sizeof(double));
  if (!W) return tb_error_set(err, "metaball", 0, "out of memory");
  for (int v = 0; v < s->nv; v++)
    for (int q = 0; q < 3; q++)
      if (m->bind[v][q] >= 0) W[m->bind[v][q]] += m->bw[v][q];
  memset(s->mass, 0, sizeof(double) * (size_t)s->nv);
  for (int v = 0; v < s->nv; v++)
    for (int q = 0; q < 3; q++) {
      int b = m->bind[v][q];
      if (b >= 0) s->mass[v] += m->m[b] * m->bw[v][q] / W[b];
    }
  for (int b = 0; b < m->n; b++) {
    if (W[b] > 0 || !m->alive[b]) continue;
    int at = 0;
    for (int v = 1; v < s->nv; v++)
      if (tb_dist(s->x[v], m->c[b]) < tb_dist(s->x[at], m->c[b])) at = v;
    s->mass[at] += m->m[b];
  }
  free(W);
  for (int v = 0; v < s->nv; v++) {
    const int *bs = m->bind[v];
    int b = 0;
    for (int q = 1; q < 3; q++)
      if (bs[q] >= 0 &&
          (bs[b] < 0 || tb_dist(m->x0[v], m->c0[bs[q]]) < tb_dist(m->x0[v], m->c0[bs[b]])))
        b = q;
    s->dominant[v] = bs[b];
  }
  return 0;
}

/* Every per-point array for nv points and per-sphere array for ns spheres
 * (new entries zero); 0 or -1. */
int mb_grow(mb_model *s, int nv, int ns) {
  size_t V = (size_t)nv, N = (size_t)ns;
#define GROW(f, count, old)                                              \
  do {                                                                   \
    void *g = realloc(s->f, sizeof *s->f * (count));                     \
    if (!g) return -1;                                                   \
    s->f = g;                                                            \
    if ((count) > (size_t)(old))                                         \
      memset(s->f + (old), 0, sizeof *s->f * ((count) - (size_t)(old))); \
  } while (0)
  GROW(x, V, s->nv);
  GROW(v, V, s->nv);
  GROW(skin0, V, s->nv);
  GROW(mass, V, s->nv);
  GROW(dominant, V, s->nv);
  GROW(presc, V, s->nv);
  GROW(fs, N, s->ns);
  GROW(cstart, N, s->ns);
  GROW(hold, N, s->ns);
  GROW(hold0, N, s->ns);
  GROW(apq, N, s->ns);
  GROW(nhold, N, s->ns);
  GROW(held, N, s->ns);
  GROW(push, N, s->ns);
  GROW(keep, N, s->ns);
  GROW(cids, N, s->ns);
  GROW(cp, N, s->ns);
  GROW(cdepth, N, s->ns);
#undef GROW
  return 0;
}

static void *create(const tb_mesh *mesh, const void *settings, tb_error *err) {
  mb_model *s = calloc(1, sizeof *s);
  if (!s) return tb_error_set(err, "metaball", 0, "out of memory"), NULL;
  s->set = *(const mb_settings *)settings;
  int *tri = NULL, ntri = tb_model_surface_triangles(mesh, "metaball", &tri, err);
  if (ntri < 0) return destroy(s), NULL;
  tb_mesh surf = {0};
  surf.nv = mesh->nv, surf.x = mesh->x, surf.ntri = ntri, surf.tri = tri;
  int nsurf = 0;
  unsigned char *on = calloc((size_t)mesh->nv, 1);
  if (!on) goto oom;
  for (int k = 0; k < 3 * ntri; k++) on[tri[k]] = 1;
  for (int v = 0; v < mesh->nv; v++) nsurf += on[v];
  free(on);
  tb_sphpack_def def = tb_sphpack_default_def(sphere_count(&s->set, nsurf));
  def.samples = s->set.samples, def.seed = (uint64_t)s->set.seed;
  tb_spheres sp = {0};
  if (s->set.spheres_file[0] && s->set.spheres) {
    tb_error_set(err, "metaball", 0, "give spheres or spheres_file, not both");
    free(tri);
    return destroy(s), NULL;
  }
  if (s->set.spheres_file[0] ? tb_spheres_read(s->set.spheres_file, &sp, err)
                             : tb_sphere_pack(&surf, "mesh", &def, &sp, NULL, err)) {
    free(tri);
    tb_spheres_free(&sp);
    return destroy(s), NULL;
  }
  double vs = 0;
  for (int i = 0; i < sp.n; i++) vs += 4.0 / 3.0 * M_PI * sp.r[i] * sp.r[i] * sp.r[i];
  double total =
      s->set.node_mass > 0 ? s->set.node_mass * mesh->nv : s->set.density * tb_mesh_volume(mesh);
  tb_metaball_settings ms;
  tb_metaball_settings_default(&ms);
  ms.density = total / vs, ms.stretch = s->set.stretch, ms.unit = s->set.unit, ms.damping = 0;
  ms.sigma = s->set.sigma, ms.overlap = s->set.overlap, ms.iterations = s->set.iterations;
  if (!(ms.density > 0) || !isfinite(ms.density)) {
    tb_error_set(err, "mesh", 0, "the body's mass is %g (the surface encloses no volume)", total);
    goto fail;
  }
  s->mb = tb_metaball_create(sp.n, sp.c, sp.r, &surf, &ms, err);
  s->tri = tri, s->ntri = ntri, tri = NULL;
  if (!s->mb) goto fail;
  if (mb_grow(s, mesh->nv, sp.n)) goto oom;
  s->nv = mesh->nv, s->ns = sp.n;
  memcpy(s->x, tb_metaball_skin(s->mb), sizeof(tb_vec3) * (size_t)s->nv);
  if (mb_share_masses(s, err)) goto fail;
  tb_spheres_free(&sp);
  return s;
oom:
  tb_error_set(err, "metaball", 0, "out of memory");
fail:
  free(tri);
  tb_spheres_free(&sp);
  destroy(s);
  return NULL;
}

/* Müller 2007 §3.5 over the alive, free spheres (see the head). */
static void damp(mb_model *s, double dt) {
  tb_metaball *m = s->mb;
  double k = 1 - exp(-s->set.damping * dt), M = 0;
  if (!(k > 0)) return;
  tb_vec3 xc = tb_v3(0, 0, 0), vc = tb_v3(0, 0, 0);
  for (int i = 0; i < m->n; i++) {
    if (!m->alive[i]) continue;
    M += m->m[i], xc = tb_madd(xc, m->m[i], m->c[i]), vc = tb_madd(vc, m->m[i], m->v[i]);
  }
  if (!(M > 0)) return;
  xc = tb_scale(xc, 1 / M), vc = tb_scale(vc, 1 / M);
  tb_vec3 L = tb_v3(0, 0, 0);
  tb_mat3 I = {{{0}}};
  for (int i = 0; i < m->n; i++) {
    if (!m->alive[i]) continue;
    tb_vec3 r = tb_sub(m->c[i], xc);
    L = tb_madd(L, m->m[i], tb_cross(r, m->v[i]));
    double rr = tb_dot(r, r), rv[3] = {r.x, r.y, r.z}; /* m (|r|^2 I - r r^T) */
    for (int a = 0; a < 3; a++)
      for (int b = 0; b < 3; b++) I.m[a][b] += m->m[i] * ((a == b) * rr - rv[a] * rv[b]);
  }
  tb_mat3 Ii;
  tb_vec3 w = tb_m3_inverse(I, &Ii) ? tb_m3_mulv(Ii, L) : tb_v3(0, 0, 0);
  for (int i = 0; i < m->n; i++) {
    if (!m->alive[i] || m->fixed[i]) continue;
    tb_vec3 rigid = tb_add(vc, tb_cross(w, tb_sub(m->c[i], xc)));
    m->v[i] = tb_madd(m->v[i], k, tb_sub(rigid, m->v[i]));
  }
}

/* The ground on the skin (see the head): spheres pushed, friction, and
 * the skin again. */
static void ground(mb_model *s, const tb_ground *g, double dt) {
  tb_metaball *m = s->mb;
  const tb_vec3 *x = m->x;
  int any = 0;
  for (int v = 0; v < s->nv; v++) {
    double h = tb_dot(tb_sub(x[v], g->p), g->n);
    if (!(h < 0)) continue;
    for (int q = 0; q < 3; q++) {
      int b = m->bind[v][q];
      if (b >= 0 && -h > s->push[b]) s->push[b] = -h, any = 1;
    }
  }
  if (!any) return;
  int nc = 0;
  for (int i = 0; i < m->n; i++) {
    if (!(s->push[i] > 0)) continue;
    if (m->alive[i] && !m->fixed[i])
      s->cids[nc] = i, s->cdepth[nc] = s->push[i], s->cp[nc++] = tb_madd(m->c[i], s->push[i], g->n);
    s->push[i] = 0;
  }
  tb_ground_friction(g, nc, s->cids, s->cdepth, s->cstart, m->m, s->cp, s->keep);
  for (int k = 0; k < nc; k++) {
    int i = s->cids[k];
    tb_vec3 v = tb_scale(tb_sub(s->cp[k], s->cstart[i]), 1 / dt);
    double vn = tb_dot(v, g->n);
    if (vn < 0) v = tb_madd(v, -vn, g->n);
    m->c[i] = s->cp[k], m->v[i] = v;
  }
  static const double eye[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
  tb_metaball_transform(m, eye, tb_v3(0, 0, 0)); /* the skin again (exact identity) */
  tb_vec3 *xs = m->x;
  for (int v = 0; v < s->nv; v++) { /* rounding */
    double h = tb_dot(tb_sub(xs[v], g->p), g->n);
    if (h < 0) xs[v] = tb_madd(xs[v], -h, g->n);
  }
}

static int step(void *self, const tb_step *in, tb_error *err) {
  mb_model *s = self;
  tb_metaball *m = s->mb;
  const int nfixed = in->nfixed;
  const double dt = in->dt;
  if (nfixed < 0 || (nfixed > 0 && (!in->fixed || !in->fixed_x)))
    return tb_error_set(err, "metaball", 0, "bad prescribed set (nfixed %d)", nfixed);
  for (int p = 0; p < nfixed; p++)
    if (in->fixed[p] < 0 || in->fixed[p] >= s->nv || (p > 0 && in->fixed[p] <= in->fixed[p - 1]))
      return tb_error_set(err, "metaball", 0,
                          "prescribed nodes must be strictly ascending in [0, %d): entry %d is %d",
                          s->nv, p, in->fixed[p]);
  memcpy(s->skin0, m->x, sizeof(tb_vec3) * (size_t)s->nv);
  memcpy(s->cstart, m->c, sizeof(tb_vec3) * (size_t)s->ns);
  /* node forces to the spheres by the binding weights */
  const tb_vec3 *fs = NULL;
  if (in->force) {
    memset(s->fs, 0, sizeof(tb_vec3) * (size_t)s->ns);
    for (int v = 0; v < s->nv; v++)
      for (int q = 0; q < 3; q++)
        if (m->bind[v][q] >= 0)
          s->fs[m->bind[v][q]] = tb_madd(s->fs[m->bind[v][q]], m->bw[v][q], in->force[v]);
    fs = s->fs;
  }
  /* held spheres: the rigid fit of their prescribed points (see the head) */
  int nh = 0;
  for (int p = 0; p < nfixed; p++) {
    int v = in->fixed[p], b = s->dominant[v];
    if (b < 0 || !m->alive[b]) continue;
    if (!s->nhold[b]) s->held[nh++] = b, s->hold[b] = s->hold0[b] = tb_v3(0, 0, 0);
    s->hold[b] = tb_add(s->hold[b], in->fixed_x[p]);
    s->hold0[b] = tb_add(s->hold0[b], m->x0[v]), s->nhold[b]++;
  }
  for (int k = 0; k < nh; k++) {
    int b = s->held[k];
    s->hold[b] = tb_scale(s->hold[b], 1.0 / s->nhold[b]);
    s->hold0[b] = tb_scale(s->hold0[b], 1.0 / s->nhold[b]);
    s->apq[b] = (tb_mat3){{{0}}};
  }
  for (int p = 0; p < nfixed; p++) {
    int v = in->fixed[p], b = s->dominant[v];
    if (b < 0 || !m->alive[b]) continue;
    tb_vec3 d = tb_sub(in->fixed_x[p], s->hold[b]), q = tb_sub(m->x0[v], s->hold0[b]);
    double dv[3] = {d.x, d.y, d.z}, qv[3] = {q.x, q.y, q.z};
    for (int r = 0; r < 3; r++)
      for (int c = 0; c < 3; c++) s->apq[b].m[r][c] += dv[r] * qv[c];
  }
  for (int k = 0; k < nh; k++) {
    int b = s->held[k];
    if (s->nhold[b] >= 3 && fabs(tb_m3_det(s->apq[b])) > 0) /* warm-started: a turn or two */
      m->rot[b] = tb_metaball_turns(s->apq[b], m->rot[b], 50, 1e-14);
    tb_vec3 at = tb_sub(s->hold[b], tb_m3_mulv(m->rot[b], tb_sub(s->hold0[b], m->c0[b])));
    s->nhold[b] = m->fixed[b] ? 2 : 1; /* 2: fixed before */
    m->v[b] = tb_scale(tb_sub(at, m->c[b]), 1 / dt), m->c[b] = at, m->fixed[b] = 1;
  }
  int rc = 0;
  if (tb_metaball_cutting(m))
    rc = tb_metaball_cut_step(m, dt, in->gravity, fs, err);
  else
    tb_metaball_step(m, dt, in->gravity, fs);
  for (int k = 0; k < nh; k++) {
    int b = s->held[k];
    m->fixed[b] = s->nhold[b] == 2, s->nhold[b] = 0;
    if (m->fixed[b]) m->v[b] = tb_v3(0, 0, 0);
  }
  if (rc) return -1;
  damp(s, dt);
  if (in->ground) ground(s, in->ground, dt);
  /* the points: the prescribed ones at their targets, the others on the
   * skin, each with its velocity (each point alone: any thread count) */
  for (int p = 0; p < nfixed; p++) {
    int v = in->fixed[p];
    s->v[v] = tb_scale(tb_sub(in->fixed_x[p], s->x[v]), 1 / dt), s->x[v] = in->fixed_x[p];
    s->presc[v] = 1;
  }
#pragma omp parallel for schedule(static) if (s->nv >= TB_METABALL_PARALLEL_MIN)
  for (int v = 0; v < s->nv; v++)
    if (!s->presc[v]) s->v[v] = tb_scale(tb_sub(m->x[v], s->skin0[v]), 1 / dt), s->x[v] = m->x[v];
  for (int p = 0; p < nfixed; p++) s->presc[in->fixed[p]] = 0;
  return 0;
}

static const tb_vec3 *positions(const void *self) { return ((const mb_model *)self)->x; }
static const tb_vec3 *velocities(const void *self) { return ((const mb_model *)self)->v; }
static const double *point_masses(const void *self) { return ((const mb_model *)self)->mass; }
static double energy(const void *self) { return (void)self, NAN; }

/* Overwrites points between steps (contact response); the next step's
 * skin starts from the spheres again. */
static void correct(void *self, int n, const int *ids, const tb_vec3 *x, const tb_vec3 *v) {
  mb_model *s = self;
  for (int k = 0; k < n; k++) {
    if (x) s->x[ids[k]] = x[k];
    if (v) s->v[ids[k]] = v[k];
  }
}

static int npoints(const void *self) { return ((const mb_model *)self)->nv; }

static tb_surface surface(const void *self) {
  const mb_model *s = self;
  tb_surface su = {s->nv, s->ntri, s->x, s->tri, s->version, s->mb->x0};
  return su;
}

static tb_model_spheres spheres(const void *self) {
  const mb_model *s = self;
  const int *links;
  int nl = tb_metaball_links(s->mb, &links);
  tb_model_spheres out = {s->mb->n,     nl,    s->mb->c,  s->mb->r,
                          s->mb->alive, links, s->mb->nv, (const int(*)[3])s->mb->bind};
  return out;
}

#define S mb_settings
static const tb_setting settings[] = {
    TB_SETTINGS_MASS(S, 0.0),
    TB_SETTING_R(S, stretch, 0.03, 0.0, 1.0, 0,
                 "stiffness of the links between overlapping spheres (PBD share)"),
    TB_SETTING_R(S, unit, 0.2, 0.0, 1.0, 0,
                 "stiffness of the unit (shape-matching) constraints: recovery of the rest shape"),
    TB_SETTING_R(S, damping, 2.0, 0.0, HUGE_VAL, 0,
                 "per second: sphere velocities relative to the rigid motion decay as exp(-d t)"),
    TB_SETTING_R(S, sigma, 1.0, 0.0, HUGE_VAL, TB_OPEN_LO,
                 "skin: Gaussian exp(-k^2 / (2 sigma^2)) of k = d / r"),
    TB_SETTING_R(S, overlap, 1.0, 0.0, HUGE_VAL, TB_OPEN_LO,
                 "spheres are linked when |c_i - c_j| < overlap (r_i + r_j)"),
    TB_SETTING_I(S, iterations, 8, 1, 1000, "Gauss-Seidel sweeps of the stretch links per step"),
    TB_SETTING_I(S, spheres, 0, 0, 100000,
                 "spheres packed into the surface (0: 570 per 8128 surface vertices, the "
                 "patent's liver, within [40, 600])"),
    TB_SETTING_I(S, samples, 0, 0, 10000000,
                 "surface samples of the packing (0: max(vertices, 20 spheres, 4000))"),
    TB_SETTING_I(S, seed, 1, 0, 2147483647, "seed of the packing's area-weighted samples"),
    TB_SETTING_I(S, cut_points, 40, 4, 10000,
                 "cut: points a sphere the blade touches turns into (the patent's second mode)"),
    TB_SETTING_R(S, cut_E, 1000.0, 0.0, HUGE_VAL, TB_OPEN_LO,
                 "cut: Young's modulus of the meshless point set"),
    TB_SETTING_F(S, spheres_file,
                 "SOFA .sph spheres (sph 1.0) to use instead of the packing; spheres must be 0"),
};
#undef S

const tb_model_class tb_model_metaball = {
    .name = "metaball",
    .summary =
        "overlapping spheres packed in the surface, PBD stretch + unit constraints, "
        "Gaussian skin (the metaball patent, step 2)",
    .settings = settings,
    .nsettings = (int)(sizeof settings / sizeof settings[0]),
    .settings_size = sizeof(mb_settings),
    .create = create,
    .step = step,
    .positions = positions,
    .velocities = velocities,
    .energy = energy,
    .destroy = destroy,
    .masses = point_masses,
    .correct = correct,
    .npoints = npoints,
    .surface = surface,
    .cut = mb_cut,
    .spheres = spheres,
    .own_ground = 1,
    .surface_mesh = 1,
};
