/* The synthetic liver: a CT-like grey-value volume of a liver-shaped solid
 * and its marching-cubes surface (thesis §2.3.2 and §2.5: the thesis
 * segments the Visible Human abdomen and extracts a 725-vertex surface; we
 * have no CT data in the repository, so we synthesise the volume).
 *
 * Shape: five ellipsoids (a large right lobe with an inferior bulge, a
 * middle part, a flat tapering left lobe and a small posterior caudate
 * lobe), each giving a distance-like field r_dir*(1 - d) (d: normalised
 * ellipsoid radius, r_dir: the ellipsoid's radius towards the point),
 * blended by a soft maximum. Grey value: a sigmoid of the blended field
 * (tissue ~1, background ~0, smooth edge) plus smooth low-amplitude value
 * noise (two octaves on fixed lattices, C1 interpolation) seeded by
 * def->seed. Isovalue 0.5. Everything is laid out for length 10 (like
 * SOFA's liver, about 10 x 4.4 x 2.5) and scaled by length/10. */
#include <stdlib.h>
#include <string.h>

#include "tb_meshgen.h"
#include "core/tb_rng.h"

#define LV_NELL 5
#define LV_BLEND 4.0 /* soft-max sharpness, 1/design unit */
#define LV_EDGE 0.2  /* sigmoid width of the organ edge, design units */
#define LV_ISO 0.5
#define LV_MAX_NOISE 0.3

typedef struct lv_ellipsoid {
  double c[3], r[3], rot_deg; /* centre, radii, rotation about z */
} lv_ellipsoid;

static const lv_ellipsoid lv_shape[LV_NELL] = {
    {{-2.2, 0.0, 0.0}, {2.8, 2.2, 1.25}, 0.0},    /* right lobe */
    {{-3.0, -0.7, -0.15}, {1.9, 1.5, 1.0}, 25.0}, /* its inferior bulge */
    {{0.4, 0.25, 0.05}, {2.5, 1.7, 0.9}, -8.0},   /* middle */
    {{2.8, 0.6, 0.15}, {2.2, 1.1, 0.55}, -12.0},  /* left lobe, flat */
    {{-0.4, -1.0, -0.45}, {1.2, 0.9, 0.6}, 0.0},  /* caudate lobe */
};

/* Noise lattices: spacing 1 and 0.5 over a fixed design-space box. */
#define LV_NLO_X (-7.0)
#define LV_NLO_Y (-4.0)
#define LV_NLO_Z (-3.0)
#define LV_NEXT_X 14.0
#define LV_NEXT_Y 8.0
#define LV_NEXT_Z 6.0

typedef struct lv_noise {
  int n[3];
  double step;
  double *val;
} lv_noise;

tb_liver_def tb_liver_default_def(void) {
  tb_liver_def d;
  d.surface_verts = 725, d.tet_verts = 1206, d.tets = 4230; /* thesis §2.5 */
  d.length = 10.0, d.noise = 0.08, d.seed = 1;
  return d;
}

/* Rotation of each ellipsoid, cos and sin, filled before sampling. */
typedef struct lv_rot {
  double cs, sn;
} lv_rot;

static double lv_field(const double p[3], const lv_rot *rot) {
  double phi[LV_NELL], m = -1e300;
  for (int i = 0; i < LV_NELL; i++) {
    const lv_ellipsoid *e = &lv_shape[i];
    double cs = rot[i].cs, sn = rot[i].sn;
    double dx = p[0] - e->c[0], dy = p[1] - e->c[1], dz = p[2] - e->c[2];
    double q[3] = {cs * dx + sn * dy, -sn * dx + cs * dy, dz}; /* into the ellipsoid's frame */
    double d2 = 0.0, rho2 = 0.0;
    for (int a = 0; a < 3; a++) d2 += (q[a] / e->r[a]) * (q[a] / e->r[a]), rho2 += q[a] * q[a];
    double d = sqrt(d2);
    double rdir = d > 1e-12 ? sqrt(rho2) / d : e->r[2];
    phi[i] = rdir * (1.0 - d);
    if (phi[i] > m) m = phi[i];
  }
  double s = 0.0;
  for (int i = 0; i < LV_NELL; i++) s += exp(LV_BLEND * (phi[i] - m));
  return m + log(s) / LV_BLEND;
}

static int lv_noise_make(lv_noise *nz, double step, tb_rng *rng) {
  nz->step = step;
  nz->n[0] = (int)(LV_NEXT_X / step) + 1;
  nz->n[1] = (int)(LV_NEXT_Y / step) + 1;
  nz->n[2] = (int)(LV_NEXT_Z / step) + 1;
  size_t n = (size_t)nz->n[0] * nz->n[1] * nz->n[2];
  nz->val = malloc(n * sizeof *nz->val);
  if (!nz->val) return -1;
  for (size_t i = 0; i < n; i++) nz->val[i] = tb_rng_range(rng, -1.0, 1.0);
  return 0;
}

/* Value noise in [-1, 1], C1 (smoothstep weights), clamped at the box. */
static double lv_noise_at(const lv_noise *nz, const double p[3]) {
  static const double lo[3] = {LV_NLO_X, LV_NLO_Y, LV_NLO_Z};
  int i0[3];
  double w[3];
  for (int a = 0; a < 3; a++) {
    double u = (p[a] - lo[a]) / nz->step;
    if (u < 0) u = 0;
    if (u > nz->n[a] - 1) u = nz->n[a] - 1;
    int i = (int)u;
    if (i > nz->n[a] - 2) i = nz->n[a] - 2;
    double t = u - i;
    i0[a] = i, w[a] = t * t * (3.0 - 2.0 * t);
  }
  double s = 0.0;
  for (int c = 0; c < 8; c++) {
    int ix = i0[0] + (c & 1), iy = i0[1] + ((c >> 1) & 1), iz = i0[2] + ((c >> 2) & 1);
    double wt = ((c & 1) ? w[0] : 1 - w[0]) * (((c >> 1) & 1) ? w[1] : 1 - w[1]) *
                (((c >> 2) & 1) ? w[2] : 1 - w[2]);
    s += wt * nz->val[((size_t)iz * nz->n[1] + iy) * nz->n[0] + ix];
  }
  return s;
}

static int lv_check_def(const tb_liver_def *def, tb_error *err) {
  if (!def) return tb_error_set(err, "liver", 0, "no definition");
  if (!(def->length > 0) || !isfinite(def->length))
    return tb_error_set(err, "liver", 0, "length must be positive and finite, not %g", def->length);
  if (!(def->noise >= 0 && def->noise <= LV_MAX_NOISE))
    return tb_error_set(err, "liver", 0, "noise must be in [0, %g], not %g", LV_MAX_NOISE,
                        def->noise);
  return 0;
}

int tb_liver_volume(const tb_liver_def *def, double h, tb_volume *v, double *iso, tb_error *err) {
  memset(v, 0, sizeof *v);
  if (lv_check_def(def, err)) return -1;
  double scale = def->length / 10.0, hd = h / scale; /* design units */
  if (!(hd >= 0.01 && hd <= 2.0))
    return tb_error_set(err, "liver", 0, "spacing %g is out of range [%g, %g] for length %g", h,
                        0.01 * scale, 2.0 * scale, def->length);
  /* design-space box: ellipsoid bounds, the soft maximum's swelling, and a
   * margin where the grey value is safely below the isovalue */
  double lo[3] = {1e300, 1e300, 1e300}, hi[3] = {-1e300, -1e300, -1e300};
  lv_rot rot[LV_NELL];
  for (int i = 0; i < LV_NELL; i++) {
    const lv_ellipsoid *e = &lv_shape[i];
    double th = e->rot_deg * 3.14159265358979323846 / 180.0;
    rot[i].cs = cos(th), rot[i].sn = sin(th);
    double ext[3] = {hypot(e->r[0] * cos(th), e->r[1] * sin(th)),
                     hypot(e->r[0] * sin(th), e->r[1] * cos(th)), e->r[2]};
    for (int a = 0; a < 3; a++) {
      lo[a] = fmin(lo[a], e->c[a] - ext[a]);
      hi[a] = fmax(hi[a], e->c[a] + ext[a]);
    }
  }
  double pad = log((double)LV_NELL) / LV_BLEND + 1.0 + 2.0 * hd;
  int n[3];
  double org[3];
  for (int a = 0; a < 3; a++) {
    double len = hi[a] - lo[a] + 2.0 * pad;
    n[a] = (int)ceil(len / hd) + 1;
    org[a] = 0.5 * (lo[a] + hi[a]) - 0.5 * (n[a] - 1) * hd;
  }
  tb_rng rng = tb_rng_seed(def->seed);
  lv_noise coarse = {{0, 0, 0}, 0, NULL}, fine = {{0, 0, 0}, 0, NULL};
  double *f = malloc((size_t)n[0] * n[1] * n[2] * sizeof *f);
  if (!f || lv_noise_make(&coarse, 1.0, &rng) || lv_noise_make(&fine, 0.5, &rng)) {
    free(f), free(coarse.val), free(fine.val);
    return tb_error_set(err, "liver", 0, "out of memory");
  }
  for (int k = 0; k < n[2]; k++)
    for (int j = 0; j < n[1]; j++)
      for (int i = 0; i < n[0]; i++) {
        double p[3] = {org[0] + i * hd, org[1] + j * hd, org[2] + k * hd};
        double g = 1.0 / (1.0 + exp(-lv_field(p, rot) / LV_EDGE));
        g += def->noise * (lv_noise_at(&coarse, p) + 0.5 * lv_noise_at(&fine, p)) / 1.5;
        f[((size_t)k * n[1] + j) * n[0] + i] = g;
      }
  free(coarse.val), free(fine.val);
  v->nx = n[0], v->ny = n[1], v->nz = n[2];
  v->origin = tb_v3(org[0] * scale, org[1] * scale, org[2] * scale);
  v->h = tb_v3(h, h, h);
  v->f = f;
  *iso = LV_ISO;
  return 0;
}

/* Volume, marching cubes and clean-up at spacing h. */
static int lv_surface_at(const tb_liver_def *def, double h, tb_mesh *m, tb_error *err) {
  tb_volume v;
  double iso;
  if (tb_liver_volume(def, h, &v, &iso, err)) return -1;
  int rc = tb_marching_cubes(&v, iso, m, NULL, err);
  tb_volume_free(&v);
  if (rc) return -1;
  if (tb_remesh_collapse_short(m, 0.25 * h) < 0) goto oom;
  /* flips and Taubin smoothing spread the vertices out (min angle ~25 deg) */
  if (tb_remesh_flip(m) < 0) goto oom;
  tb_remesh_taubin(m, 6, 0.5, -0.53);
  if (tb_remesh_flip(m) < 0) goto oom;
  return 0;
oom:
  tb_mesh_free(m);
  return tb_error_set(err, "liver", 0, "out of memory in the clean-up");
}

int tb_liver_surface_for(int tets) {
  return tets > 0 ? (int)lround(725.0 * pow(tets / 4230.0, 0.8)) : 0;
}

int tb_liver_surface(const tb_liver_def *def, tb_mesh *surf, tb_error *err) {
  memset(surf, 0, sizeof *surf);
  if (lv_check_def(def, err)) return -1;
  int target = def->surface_verts ? def->surface_verts : tb_liver_surface_for(def->tets);
  if (target < 100 || target > 50000)
    return tb_error_set(err, "liver", 0, "surface_verts must be in [100, 50000], not %d", target);
  /* The vertex count falls roughly like h^-2: power-law steps inside a
   * shrinking bracket [h_many, h_few], in log h, bounded iterations. */
  double scale = def->length / 10.0;
  double h = 0.4 * scale * sqrt(725.0 / target), h_many = 0.0, h_few = 0.0;
  tb_mesh best = {0};
  int best_off = -1;
  for (int it = 0; it < 40; it++) {
    tb_mesh m;
    if (lv_surface_at(def, h, &m, err)) {
      tb_mesh_free(&best);
      return -1;
    }
    int n = m.nv, off = abs(n - target);
    if (best_off < 0 || off < best_off) {
      tb_mesh_free(&best);
      best = m, best_off = off;
    } else {
      tb_mesh_free(&m);
    }
    if (best_off * 200 <= target) break; /* within 0.5% */
    if (n < 1) n = 1;
    if (n > target)
      h_many = h;
    else
      h_few = h;
    double next = h * sqrt((double)n / target);
    if (h_many > 0 && h_few > 0) {
      double lo = log(h_many), hi = log(h_few), ln = log(next);
      double margin = 0.1 * (hi - lo);
      if (!(ln > lo + margin && ln < hi - margin)) ln = 0.5 * (lo + hi);
      next = exp(ln);
    }
    h = fmin(fmax(next, 0.011 * scale), 1.9 * scale);
  }
  if (best_off * 20 > target) {
    int nv = best.nv;
    tb_mesh_free(&best);
    return tb_error_set(err, "liver", 0,
                        "no grid spacing gives %d surface vertices within 5%% "
                        "(closest %d)",
                        target, nv);
  }
  tb_mesh_topo topo = tb_mesh_topology(&best);
  if (!topo.closed || !topo.manifold || topo.components != 1 || topo.euler != 2 ||
      topo.misoriented_edges != 0) {
    tb_mesh_free(&best);
    return tb_error_set(err, "liver", 0, "surface is not a closed sphere-like 2-manifold");
  }
  *surf = best;
  return 0;
}
