/* Surface mass-spring model with virtual volumetric springs (Bao, Wang,
 * Liu, Cheng 2006, "A dynamic mass spring model for simulation of soft
 * tissue deformation", J. System Simulation 18(4); SPEC §2.4).
 *
 * Points are the mesh's nodes; springs sit on the edges of a closed
 * triangle surface (the mesh's own triangles, or a tet mesh's boundary).
 * Per surface point i (eqs 1-2):
 *   F_i = sum_j g_ij - d_i v_i + f_ext,i + m_i g,
 *   g_ij = k_ij (|x_j - x_i| - R_ij) (x_j - x_i) / |x_j - x_i|   (eq. 3),
 * R_ij the rest length. The virtual volumetric spring (§2): rest length
 * zero, one end held at the node's rest position X_i, dx = x_i - X_i:
 *   g_i = -[k'_s |dx| + k'_d (v_i . dx) / |dx|] dx / |dx|   (0 at dx = 0).
 * volume_springs=0 leaves it out: the hollow shell the paper compares with.
 *
 * integrator=quasistatic (the paper's, §2): each step moves a free point by
 *   dx_i = alpha F_i dt^2 / m_i,
 * ignoring inertia; the reported velocity is dx_i / dt, and the damping
 * terms of the next step (-d_i v_i and the k'_d term) use it. alpha scales
 * the step (the paper leaves it open): 1 moves a point as far as one
 * explicit Euler step from rest would. The equilibrium does not depend on
 * alpha, only how fast it is reached: a mode of stiffness k relaxes with a
 * time constant of about (m + alpha (d + k'_d) dt) / (alpha k dt) (alpha 1,
 * k'_s 1.5, dt 0.01: 67 s). The damping terms feed the last increment back
 * with the factor -alpha (d + k'_d) dt / m, so a step is stable while
 *   alpha (d + k'_d) dt / m < 1  and  alpha dt^2 K / m + 2 alpha (d + k'_d) dt / m < 2,
 * K the largest stiffness (at most 2 sum_j k_ij + k'_s): alpha < 100 at
 * the paper's parameters with dt 0.01. integrator=euler: symplectic
 * (semi-implicit) Euler, v += dt F / m then x += dt v, for comparison.
 *
 * A prescribed point ends the step at fixed_x with velocity
 * (fixed_x - x_old) / dt. On a tet mesh the interior nodes are not
 * simulated: each takes the displacement and velocity of the surface node
 * nearest to it at rest (the lowest index among equals), unless prescribed;
 * external forces given on them act on that surface node. Masses: node_mass,
 * else the density's (tets: lumped; a surface: the enclosed volume's mass
 * shared by vertex area). The energy is the springs' potential plus the
 * surface points' kinetic energy.
 *
 * levels > 1: dynamic local refinement (the paper's §3, vvs_refine.c):
 * the points of every butterfly level exist from the start, those not on
 * the current surface are off (not simulated, at rest).
 *
 * Hot data are flat arrays per point (x, v, X, f, m, 1/m, k'_s, k'_d, d)
 * and per spring ((i, j), R, k), and the list of simulated points;
 * vvs_build_springs makes the springs from any triangle list over the
 * points. A step allocates nothing. */
#include <math.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>

#include "vvs_priv.h"
static int cmp_pair(const void *a, const void *b) {
  const int *p = a, *q = b;
  return p[0] != q[0] ? (p[0] < q[0] ? -1 : 1) : (p[1] != q[1] ? (p[1] < q[1] ? -1 : 1) : 0);
}

static void destroy(void *self) {
  vvs *s = self;
  if (!s) return;
  free(s->x), free(s->v), free(s->x0), free(s->f);
  free(s->mass), free(s->invm), free(s->ksv), free(s->kdv), free(s->d), free(s->follow);
  free(s->sim), free(s->tri), free(s->ij), free(s->len0), free(s->k);
  free(s->depth), free(s->share), free(s->stress), free(s->kdiag), free(s->qinv);
  free(s->barea), free(s->bload), free(s->u);
  if (s->lod) tb_lod_free(s->lod), free(s->lod);
  free(s);
}

int vvs_alloc(vvs *s, int nv, int cap_tri, tb_error *err) {
  size_t n = (size_t)nv, c = (size_t)(cap_tri > 0 ? cap_tri : 1);
  s->nv = nv, s->cap_tri = cap_tri;
  s->x = malloc(sizeof(tb_vec3) * n), s->x0 = malloc(sizeof(tb_vec3) * n);
  s->v = calloc(n, sizeof(tb_vec3)), s->f = calloc(n, sizeof(tb_vec3));
  s->mass = calloc(n, sizeof(double)), s->invm = calloc(n, sizeof(double));
  s->ksv = calloc(n, sizeof(double)), s->kdv = calloc(n, sizeof(double));
  s->d = calloc(n, sizeof(double)), s->follow = malloc(sizeof(int) * n);
  s->sim = malloc(sizeof(int) * n), s->tri = malloc(sizeof(int) * 3 * c);
  s->ij = malloc(sizeof(int) * 6 * c); /* every half-edge's pair while sorting */
  s->len0 = malloc(sizeof(double) * 3 * c), s->k = malloc(sizeof(double) * 3 * c);
  if (!s->x || !s->x0 || !s->v || !s->f || !s->mass || !s->invm || !s->ksv || !s->kdv || !s->d ||
      !s->follow || !s->sim || !s->tri || !s->ij || !s->len0 || !s->k)
    return tb_error_set(err, "msm-vvs", 0, "out of memory (%d points)", nv);
  return 0;
}

void vvs_build_springs(vvs *s, int ntri, const int *tri, int closed) {
  int *e = s->ij, n = 0;
  if (closed) {
    for (int k = 0; k < 3 * ntri; k++) {
      int a = tri[k], b = tri[k - k % 3 + (k + 1) % 3];
      if (a < b) e[2 * n] = a, e[2 * n + 1] = b, n++;
    }
  } else {
    for (int t = 0; t < ntri; t++)
      for (int c = 0; c < 3; c++) {
        int a = tri[3 * t + c], b = tri[3 * t + (c + 1) % 3];
        e[6 * t + 2 * c] = a < b ? a : b, e[6 * t + 2 * c + 1] = a < b ? b : a;
      }
    qsort(e, 3 * (size_t)ntri, 2 * sizeof(int), cmp_pair);
    for (int q = 0; q < 3 * ntri; q++)
      if (!n || cmp_pair(e + 2 * q, e + 2 * (n - 1)))
        e[2 * n] = e[2 * q], e[2 * n + 1] = e[2 * q + 1], n++;
  }
  for (int q = 0; q < n; q++)
    s->len0[q] = tb_dist(s->x0[e[2 * q]], s->x0[e[2 * q + 1]]), s->k[q] = s->set.ks;
  s->ns = n;
  s->nsim = 0;
  for (int i = 0; i < s->nv; i++)
    if (s->follow[i] == VVS_SIM) s->sim[s->nsim++] = i;
  s->version++;
}

/* Every edge of the surface has a positive, finite rest length. */
static int check_springs(const vvs *s, tb_error *err) {
  for (int q = 0; q < s->ns; q++)
    if (!(s->len0[q] > 0) || !isfinite(s->len0[q]))
      return tb_error_set(err, "mesh", 0, "edge %d-%d has rest length %g (coincident nodes)",
                          s->ij[2 * q], s->ij[2 * q + 1], s->len0[q]);
  return 0;
}

/* Each point no triangle uses follows the nearest simulated point at rest
 * (the lowest index among equals). */
static void choose_followed(vvs *s) {
  for (int i = 0; i < s->nv; i++) {
    if (s->follow[i] < 0) continue; /* simulated or off */
    double best = INFINITY;
    int at = -1;
    for (int j = 0; j < s->nv; j++) {
      if (s->follow[j] != VVS_SIM) continue; /* not simulated */
      tb_vec3 r = tb_sub(s->x0[j], s->x0[i]);
      double d2 = tb_dot(r, r);
      if (d2 < best) best = d2, at = j;
    }
    s->follow[i] = at;
  }
}

/* Masses of a closed surface from the density: the enclosed volume's mass,
 * a third of each triangle's area share to each of its vertices. */
static int surface_masses(const tb_mesh *mesh, double density, double *mass, tb_error *err) {
  double vol = tb_mesh_volume(mesh), area = 0;
  if (!(vol > 0))
    return tb_error_set(err, "mesh", 0,
                        "the surface encloses volume %g <= 0 (triangles facing inward?)", vol);
  memset(mass, 0, sizeof(double) * (size_t)mesh->nv);
  for (int t = 0; t < mesh->ntri; t++) {
    const int *n = mesh->tri + 3 * t;
    double a = tb_tri_area(mesh->x[n[0]], mesh->x[n[1]], mesh->x[n[2]]);
    for (int c = 0; c < 3; c++) mass[n[c]] += a / 3;
    area += a;
  }
  for (int i = 0; i < mesh->nv; i++) mass[i] *= density * vol / area;
  for (int i = 0; i < mesh->nv; i++)
    if (!(mass[i] > 0))
      return tb_error_set(err, "mesh", 0, "node %d has no mass (set node_mass)", i);
  return 0;
}

static void *create(const tb_mesh *mesh, const void *settings, tb_error *err) {
  const vvs_settings *def = settings;
  vvs *s = calloc(1, sizeof *s);
  if (!s) {
    tb_error_set(err, "msm-vvs", 0, "out of memory");
    return NULL;
  }
  s->set = *def, s->nbase = mesh->nv;
  int *tri = NULL, ntri = tb_model_surface_triangles(mesh, "msm-vvs", &tri, err);
  if (ntri < 0) goto fail;
  if (def->levels > 1) {
    if (mesh->ntet > 0) {
      tb_error_set(err, "msm-vvs", 0,
                   "local refinement (levels %d) needs a closed triangle surface, not a tet mesh",
                   def->levels);
      goto fail;
    }
    if (vvs_refine_init(s, mesh, err)) goto fail; /* every level's points */
  } else if (vvs_alloc(s, mesh->nv, ntri, err))
    goto fail;
  memcpy(s->x, mesh->x, sizeof(tb_vec3) * (size_t)mesh->nv);
  memcpy(s->x0, mesh->x, sizeof(tb_vec3) * (size_t)mesh->nv);
  if (def->node_mass > 0 || mesh->ntet > 0) {
    if (tb_lumped_masses(mesh, def->density, def->node_mass, s->mass, err)) goto fail;
  } else if (surface_masses(mesh, def->density, s->mass, err))
    goto fail;
  for (int i = 0; i < mesh->nv; i++) {
    s->invm[i] = 1.0 / s->mass[i], s->d[i] = def->kd;
    s->ksv[i] = def->volume_springs ? def->ks_v : 0.0;
    s->kdv[i] = def->volume_springs ? def->kd_v : 0.0;
  }
  for (int i = 0; i < s->nv; i++) s->follow[i] = i < mesh->nv ? 0 : VVS_OFF;
  for (int q = 0; q < 3 * ntri; q++) s->follow[tri[q]] = VVS_SIM;
  memcpy(s->tri, tri, sizeof(int) * 3 * (size_t)ntri);
  s->ntri = ntri;
  free(tri), tri = NULL;
  vvs_build_springs(s, s->ntri, s->tri, 0);
  if (check_springs(s, err)) goto fail;
  if (s->lod) vvs_refine_params(s);
  s->version = 0; /* the rest surface */
  choose_followed(s);
  return s;
fail:
  free(tri);
  destroy(s);
  return NULL;
}

/* F_i of eqs 1-3 and §2 into f for the simulated points (f holds the
 * external forces on entry); a followed point's load moves to its leader. */
static void forces(vvs *s, tb_vec3 g) {
  tb_vec3 *restrict f = s->f;
  const tb_vec3 *restrict x = s->x, *restrict v = s->v, *restrict x0 = s->x0;
  for (int i = 0; i < s->nbase; i++)
    if (s->follow[i] >= 0) {
      int j = s->follow[i];
      f[j] = tb_add(f[j], f[i]), f[i] = tb_v3(0, 0, 0);
    }
  for (int q = 0; q < s->nsim; q++) {
    const int i = s->sim[q];
    f[i] = tb_madd(tb_madd(f[i], s->mass[i], g), -s->d[i], v[i]); /* gravity, -d_i v_i */
    tb_vec3 dx = tb_sub(x[i], x0[i]);
    double l = tb_len(dx);
    if (l > 0 && (s->ksv[i] > 0 || s->kdv[i] > 0)) { /* the virtual volumetric spring */
      double c = -(s->ksv[i] * l + s->kdv[i] * tb_dot(v[i], dx) / l) / l;
      f[i] = tb_madd(f[i], c, dx);
    }
  }
  for (int e = 0; e < s->ns; e++) { /* eq. 3 */
    const int i = s->ij[2 * e], j = s->ij[2 * e + 1];
    tb_vec3 r = tb_sub(x[j], x[i]);
    double l = tb_len(r), c = l > 0 ? s->k[e] * (l - s->len0[e]) / l : 0.0;
    f[i] = tb_madd(f[i], c, r), f[j] = tb_madd(f[j], -c, r);
  }
}

/* The external forces (on the mesh's nodes; refining, through the current
 * surface: vvs_refine_loads), then F_i. */
static void load(vvs *s, const tb_step *in) {
  size_t nb = (size_t)s->nbase;
  if (s->lod && in->force)
    vvs_refine_loads(s, in->force);
  else {
    if (in->force)
      memcpy(s->f, in->force, sizeof(tb_vec3) * nb);
    else
      memset(s->f, 0, sizeof(tb_vec3) * nb);
    for (int q = s->nsim - 1; q >= 0 && s->sim[q] >= s->nbase; q--) /* a finer level's */
      s->f[s->sim[q]] = tb_v3(0, 0, 0);
  }
  forces(s, in->gravity);
}

static int step(void *self, const tb_step *in, tb_error *err) {
  vvs *s = self;
  const int nb = s->nbase, nfixed = in->nfixed;
  if (nfixed < 0 || (nfixed > 0 && (!in->fixed || !in->fixed_x)))
    return tb_error_set(err, "msm-vvs", 0, "bad prescribed set (nfixed %d)", nfixed);
  for (int p = 0; p < nfixed; p++)
    if (in->fixed[p] < 0 || in->fixed[p] >= nb || (p > 0 && in->fixed[p] <= in->fixed[p - 1]))
      return tb_error_set(err, "msm-vvs", 0,
                          "prescribed nodes must be strictly ascending in [0, %d): entry %d is %d",
                          nb, p, in->fixed[p]);
  load(s, in);
  tb_vec3 *x = s->x, *v = s->v;
  const double dt = in->dt, h = s->set.alpha * dt * dt;
  if (s->lod && h != s->qh) vvs_refine_steps(s, h);
  for (int p = 0; p < nfixed; p++) { /* prescribed (fixed_x may alias the positions) */
    const int i = in->fixed[p];
    const tb_vec3 xe = in->fixed_x[p];
    v[i] = tb_scale(tb_sub(xe, x[i]), 1.0 / dt), x[i] = xe;
  }
  int p = 0; /* the simulated points but the prescribed ones (both ascending) */
  for (int q = 0; q < s->nsim; q++) {
    const int i = s->sim[q];
    while (p < nfixed && in->fixed[p] < i) p++;
    if (p < nfixed && in->fixed[p] == i) continue;
    if (s->set.integrator == VVS_QUASISTATIC) {
      /* alpha F dt^2 / m; refining, m at least 2 alpha dt^2 K_i (vvs_refine.c) */
      tb_vec3 dx = tb_scale(s->f[i], h * (s->lod ? s->qinv[i] : s->invm[i]));
      x[i] = tb_add(x[i], dx), v[i] = tb_scale(dx, 1.0 / dt);
    } else { /* symplectic Euler */
      v[i] = tb_madd(v[i], dt * s->invm[i], s->f[i]);
      x[i] = tb_madd(x[i], dt, v[i]);
    }
  }
  p = 0; /* the followers (a tet mesh's interior), unless prescribed */
  for (int i = 0; i < nb; i++) {
    while (p < nfixed && in->fixed[p] < i) p++;
    const int j = s->follow[i];
    if (j < 0 || (p < nfixed && in->fixed[p] == i)) continue;
    x[i] = tb_add(s->x0[i], tb_sub(x[j], s->x0[j])), v[i] = v[j];
  }
  /* refinement after the step: the next step's forces see the new surface */
  if (s->lod && ++s->steps % s->set.refine_every == 0) vvs_refine_step(s);
  return 0;
}

static const tb_vec3 *positions(const void *self) { return ((const vvs *)self)->x; }
static const tb_vec3 *velocities(const void *self) { return ((const vvs *)self)->v; }
static const double *masses(const void *self) { return ((const vvs *)self)->mass; }
static int npoints(const void *self) { return ((const vvs *)self)->nv; }

static tb_surface surface(const void *self) {
  const vvs *s = self;
  tb_surface r = {s->nv, s->ntri, s->x, s->tri, s->version, s->x0};
  return r;
}

/* sum 1/2 k (l - R)^2 + sum 1/2 k'_s |x - X|^2 + sum 1/2 m |v|^2 over the
 * simulated points (no gravity potential) */
static double energy(const void *self) {
  const vvs *s = self;
  double w = 0;
  for (int e = 0; e < s->ns; e++) {
    double d = tb_dist(s->x[s->ij[2 * e]], s->x[s->ij[2 * e + 1]]) - s->len0[e];
    w += 0.5 * s->k[e] * d * d;
  }
  for (int q = 0; q < s->nsim; q++) {
    const int i = s->sim[q];
    tb_vec3 dx = tb_sub(s->x[i], s->x0[i]);
    w += 0.5 * (s->ksv[i] * tb_dot(dx, dx) + s->mass[i] * tb_dot(s->v[i], s->v[i]));
  }
  return w;
}

static void correct(void *self, int n, const int *ids, const tb_vec3 *x, const tb_vec3 *v) {
  vvs *s = self;
  for (int k = 0; k < n; k++) {
    if (x) s->x[ids[k]] = x[k];
    if (v) s->v[ids[k]] = v[k];
  }
}

#define S vvs_settings
static const tb_setting settings[] = {
    TB_SETTINGS_MASS(S, 1.0), /* the paper's m = 1 */
    TB_SETTING_R(S, ks, 3.0, 0.0, HUGE_VAL, 0, "surface spring stiffness k_ij (eq. 3)"),
    TB_SETTING_R(S, kd, 0.5, 0.0, HUGE_VAL, 0, "node damping d_i: force -d_i v_i (eq. 2)"),
    TB_SETTING_R(S, ks_v, 1.5, 0.0, HUGE_VAL, 0, "virtual volumetric spring stiffness k'_s"),
    TB_SETTING_R(S, kd_v, 0.5, 0.0, HUGE_VAL, 0, "virtual volumetric spring damping k'_d"),
    TB_SETTING_I(S, volume_springs, 1, 0, 1,
                 "1: a virtual volumetric spring per node; 0: the hollow shell"),
    TB_SETTING_C(S, integrator, VVS_QUASISTATIC, VVS_EULER, "quasistatic|euler",
                 "quasistatic: dx = alpha F dt^2 / m (the paper); euler: symplectic Euler"),
    TB_SETTING_R(S, alpha, 1.0, 0.0, HUGE_VAL, TB_OPEN_LO,
                 "quasi-static step scale (1: one Euler step from rest; stable below "
                 "m / ((kd + kd_v) dt))"),
    TB_SETTING_I(S, levels, 1, 1, 4,
                 "butterfly levels of detail (1: the mesh as it is; 2+: dynamic local "
                 "refinement of a closed surface, Bao 2006 §3)"),
    TB_SETTING_R(S, refine_force, 1.0, 0.0, HUGE_VAL, 0,
                 "a point whose force per area share (of a base point's) passes this splits its "
                 "faces a level deeper (levels > 1; 0: everything refined)"),
    TB_SETTING_I(S, refine_every, 5, 1, 100000,
                 "steps between two checks of the refinement criterion (levels > 1)"),
    TB_SETTING_R(S, coarsen_share, 0.5, 0.0, 1.0, 0,
                 "hysteresis: a refined point goes back a level when its force falls below "
                 "this share of refine_force"),
};
#undef S

const tb_model_class tb_model_msm_vvs = {
    .name = "msm-vvs",
    .summary =
        "surface mass-spring with virtual volumetric springs, quasi-static steps (Bao 2006 "
        "eqs 1-3, §2)",
    .settings = settings,
    .nsettings = (int)(sizeof settings / sizeof settings[0]),
    .settings_size = sizeof(vvs_settings),
    .create = create,
    .step = step,
    .positions = positions,
    .velocities = velocities,
    .energy = energy,
    .destroy = destroy,
    .masses = masses,
    .npoints = npoints,
    .surface = surface,
    .correct = correct,
    .surface_mesh = 1,
};
