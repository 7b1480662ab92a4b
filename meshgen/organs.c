/* The metaball patent's four organs (its table 1: liver 8128 surface
 * vertices / 570 spheres, spleen 1480 / 466, gallbladder 1415 / 452, steak
 * 1266 / 539) as generated closed surfaces with exactly those vertex counts.
 * The patent scanned real organs; we have none, so, like the liver (meshgen/
 * liver.c, thesis §2.3.2), each is a CT-like grey-value volume of a
 * synthetic solid, its marching-cubes isosurface and the same clean-up, the
 * grid spacing searched for the vertex count, then tb_remesh_to_count
 * (meshgen/remesh_count.c) splits or collapses the last few edges.
 *
 * Solids (lengths in the liver's unit: SOFA's liver is about 10 long;
 * bounding boxes at seed 1 in tb_organs[].size):
 * - liver: meshgen/liver.c's blend of five ellipsoids, 10 x 4.6 x 2.6.
 * - spleen: a crescent, a swept sphere of varying radius (0.45 at the
 *   tips, 1.3 mid-way) along an 80-degree arc of radius 4, flattened to 0.62
 *   of its width, with a hilum groove carved into the concave side:
 *   6.0 x 2.7 x 1.6.
 * - gallbladder: a pear-shaped sac, a swept sphere from a round fundus
 *   (radius 0.8-0.85) through the body to a narrow neck (0.25) that bends up
 *   and back (Hartmann's pouch): 4.1 x 2.1 x 1.6.
 * - steak: a slab 1.5 thick, its outline a rounded rectangle (superellipse,
 *   exponent 3.5, 8 x 4.8) narrowing to one end and made irregular by four
 *   seeded harmonics, its thickness tilting along it by a seeded amount, the
 *   rim rounded by a soft minimum: 8.0 x 5.05 x 1.55.
 * A solid is a field phi (about the distance to its surface, > 0 inside);
 * the grey value is a sigmoid of phi plus smooth seeded noise (six random
 * plane waves), isovalue 0.5; the volume's border samples are set outside. */
#include <stdlib.h>
#include <string.h>

#include "tb_meshgen.h"
#include "core/tb_rng.h"

#define OG_PI 3.14159265358979323846
#define OG_EDGE 0.08  /* sigmoid width of the organ's edge */
#define OG_NOISE 0.06 /* grey-value noise amplitude */
#define OG_ISO 0.5
#define OG_WAVES 6
#define OG_HARM 4
#define OG_ROUND 8.0 /* sharpness of the soft max/min, 1/unit */
#define OG_MAX_NODES 17

const tb_organ_info tb_organs[TB_NORGANS] = {
    {"liver", 8128, 570, 6.25, 9.52, {10.0, 4.58, 2.59}, "meshgen/liver.c: 5 blended ellipsoids"},
    {"spleen", 1480, 466, 2.14, 2.58, {6.0, 2.7, 1.63}, "flattened crescent with a hilum groove"},
    {"gallbladder", 1415, 452, 2.65, 3.33, {4.14, 2.14, 1.61}, "pear-shaped sac with a bent neck"},
    {"steak", 1266, 539, 1.8, 2.4, {8.0, 5.05, 1.55}, "irregular rounded slab"},
};

const tb_organ_info *tb_organ_find(const char *name) {
  for (int i = 0; name && i < TB_NORGANS; i++)
    if (!strcmp(tb_organs[i].name, name)) return &tb_organs[i];
  return NULL;
}

/* ---- the solids ---- */
typedef enum og_kind { OG_SPLEEN = 1, OG_GALLBLADDER = 2, OG_STEAK = 3 } og_kind;

/* A solid: its kind, seeded parameters and the box holding it. */
typedef struct og_solid {
  og_kind kind;
  tb_vec3 wave[OG_WAVES]; /* noise: wave vectors, phases, amplitudes */
  double wave_phase[OG_WAVES], wave_amp[OG_WAVES];
  double harm_amp[OG_HARM], harm_phase[OG_HARM]; /* steak outline, harmonics 2..5 */
  double tilt;                                   /* steak thickness slope */
  double node[OG_MAX_NODES][4];                  /* swept sphere: x, y, z, radius */
  int nnode;
  double flat; /* z distances of the sweep divided by this */
  tb_vec3 lo, hi;
} og_solid;

/* Soft maximum of a and b (log-sum-exp), sharpness OG_ROUND. */
static double og_smax(double a, double b) {
  double m = a > b ? a : b;
  return m + log(exp(OG_ROUND * (a - m)) + exp(OG_ROUND * (b - m))) / OG_ROUND;
}

/* The solid's swept sphere: max over the segments of its nodes of r(t) -
 * |p - c(t)|, t the projection on the segment, z distances divided by flat. */
static double og_sweep(const og_solid *s, tb_vec3 p) {
  double best = -1e300;
  for (int i = 0; i + 1 < s->nnode; i++) {
    const double *n0 = s->node[i], *n1 = s->node[i + 1];
    tb_vec3 a = tb_v3(n0[0], n0[1], n0[2]), ab = tb_sub(tb_v3(n1[0], n1[1], n1[2]), a);
    double t = tb_dot(tb_sub(p, a), ab) / tb_dot(ab, ab);
    t = t < 0 ? 0 : (t > 1 ? 1 : t);
    tb_vec3 d = tb_sub(p, tb_madd(a, t, ab));
    d.z /= s->flat;
    double phi = n0[3] + t * (n1[3] - n0[3]) - tb_len(d);
    if (phi > best) best = phi;
  }
  return best;
}

/* The spleen: its crescent's nodes, an 80-degree arc of radius 4, concave
 * towards +y, radius 0.45 at the tips and 1.3 mid-way. */
static void og_spleen_nodes(og_solid *s) {
  s->nnode = OG_MAX_NODES, s->flat = 0.62;
  for (int i = 0; i < OG_MAX_NODES; i++) {
    double u = (double)i / (OG_MAX_NODES - 1), th = (u - 0.5) * 80.0 * OG_PI / 180.0;
    s->node[i][0] = 4.0 * sin(th), s->node[i][1] = 4.0 * (1.0 - cos(th)), s->node[i][2] = 0.0;
    s->node[i][3] = 0.45 + 0.85 * pow(sin(OG_PI * u), 0.7);
  }
}

static double og_spleen(const og_solid *s, tb_vec3 p) {
  double body = og_sweep(s, p);
  /* hilum: an ellipsoid groove along the concave border, below the mid-plane */
  tb_vec3 q = tb_v3(p.x / 1.1, (p.y - 1.55) / 0.5, (p.z + 0.25) / 0.45);
  double dq = tb_len(q), groove = dq > 1e-12 ? (1.0 - dq) * 0.45 : 0.45;
  return -og_smax(-body, groove);
}

/* The gallbladder's nodes: fundus, body, neck bending up and back. */
static void og_gallbladder_nodes(og_solid *s) {
  static const double node[6][4] = {
      {-1.55, 0.0, 0.0, 0.80}, {-0.6, 0.05, 0.0, 0.85}, {0.45, 0.15, 0.0, 0.62},
      {1.15, 0.35, 0.1, 0.40}, {1.5, 0.72, 0.25, 0.30}, {1.38, 1.1, 0.32, 0.25},
  };
  s->nnode = 6, s->flat = 0.95;
  memcpy(s->node, node, sizeof node);
}

static double og_steak(const og_solid *s, tb_vec3 p) {
  const double a = 4.0, b0 = 2.4, ex = 3.5, half = 0.75;
  double b = b0 * (1.0 - 0.12 * p.x / a); /* narrower towards +x */
  double rho = hypot(p.x, p.y), th = atan2(p.y, p.x), wob = 1.0;
  for (int k = 0; k < OG_HARM; k++) wob += s->harm_amp[k] * cos((k + 2) * th + s->harm_phase[k]);
  double d = pow(pow(fabs(p.x) / a, ex) + pow(fabs(p.y) / b, ex), 1.0 / ex) / wob;
  double flat = d > 1e-12 ? rho / d - rho : b0; /* along the ray to the outline */
  double hz = half * (1.0 + s->tilt * p.x / a);
  return -og_smax(-flat, fabs(p.z) - hz);
}

static double og_noise(const og_solid *s, tb_vec3 p) {
  double n = 0, sum = 0;
  for (int i = 0; i < OG_WAVES; i++) {
    n += s->wave_amp[i] * sin(tb_dot(s->wave[i], p) + s->wave_phase[i]);
    sum += s->wave_amp[i];
  }
  return n / sum;
}

static double og_phi(const og_solid *s, tb_vec3 p) {
  if (s->kind == OG_SPLEEN) return og_spleen(s, p);
  if (s->kind == OG_GALLBLADDER) return og_sweep(s, p);
  return og_steak(s, p);
}

/* The solid's seeded parameters: wavelengths 2.5 (amplitude 1) and 1.2
 * (0.5) in random directions; the steak's harmonics (0.01-0.04) and tilt
 * (+-0.1). */
static void og_solid_make(og_kind kind, uint64_t seed, og_solid *s) {
  memset(s, 0, sizeof *s);
  s->kind = kind;
  tb_rng rng = tb_rng_seed(seed ^ (0x9e3779b97f4a7c15ull * (uint64_t)kind));
  for (int i = 0; i < OG_WAVES; i++) {
    double lambda = i < OG_WAVES / 2 ? 2.5 : 1.2;
    double z = tb_rng_range(&rng, -1, 1), az = tb_rng_range(&rng, 0, 2 * OG_PI);
    double r = sqrt(1 - z * z) * 2 * OG_PI / lambda;
    s->wave[i] = tb_v3(r * cos(az), r * sin(az), z * 2 * OG_PI / lambda);
    s->wave_phase[i] = tb_rng_range(&rng, 0, 2 * OG_PI);
    s->wave_amp[i] = i < OG_WAVES / 2 ? 1.0 : 0.5;
  }
  for (int k = 0; k < OG_HARM; k++) {
    s->harm_amp[k] = tb_rng_range(&rng, 0.01, 0.04);
    s->harm_phase[k] = tb_rng_range(&rng, 0, 2 * OG_PI);
  }
  s->tilt = tb_rng_range(&rng, -0.1, 0.1);
  if (kind == OG_SPLEEN) og_spleen_nodes(s);
  if (kind == OG_GALLBLADDER) og_gallbladder_nodes(s);
  static const double box[4][6] = {{0, 0, 0, 0, 0, 0},
                                   {-3.2, -1.4, -1.0, 3.2, 2.1, 1.0},
                                   {-2.4, -0.9, -0.9, 1.8, 1.4, 1.2},
                                   {-4.3, -2.9, -0.9, 4.3, 2.9, 0.9}};
  s->lo = tb_v3(box[kind][0], box[kind][1], box[kind][2]);
  s->hi = tb_v3(box[kind][3], box[kind][4], box[kind][5]);
}

/* Grey values at spacing h over the solid's box and a margin. */
static int og_volume(const og_solid *s, double h, tb_volume *v, tb_error *err) {
  memset(v, 0, sizeof *v);
  double pad = 0.5 + 2 * h, lo[3] = {s->lo.x, s->lo.y, s->lo.z},
         hi[3] = {s->hi.x, s->hi.y, s->hi.z};
  int n[3];
  double org[3];
  for (int a = 0; a < 3; a++) {
    n[a] = (int)ceil((hi[a] - lo[a] + 2 * pad) / h) + 1;
    org[a] = 0.5 * (lo[a] + hi[a]) - 0.5 * (n[a] - 1) * h;
  }
  if ((double)n[0] * n[1] * n[2] > 6e7)
    return tb_error_set(err, "organ", 0, "spacing %g needs too many samples", h);
  double *f = malloc((size_t)n[0] * n[1] * n[2] * sizeof *f);
  if (!f) return tb_error_set(err, "organ", 0, "out of memory");
  for (int k = 0; k < n[2]; k++)
    for (int j = 0; j < n[1]; j++)
      for (int i = 0; i < n[0]; i++) {
        tb_vec3 p = tb_v3(org[0] + i * h, org[1] + j * h, org[2] + k * h);
        double g = 1.0 / (1.0 + exp(-og_phi(s, p) / OG_EDGE)) + OG_NOISE * og_noise(s, p);
        int border = i == 0 || j == 0 || k == 0 || i == n[0] - 1 || j == n[1] - 1 || k == n[2] - 1;
        f[((size_t)k * n[1] + j) * n[0] + i] = border ? 0.0 : g;
      }
  v->nx = n[0], v->ny = n[1], v->nz = n[2];
  v->origin = tb_v3(org[0], org[1], org[2]);
  v->h = tb_v3(h, h, h);
  v->f = f;
  return 0;
}

/* Marching cubes and the liver's clean-up (short edges collapsed, flips,
 * Taubin smoothing, flips) at spacing h. */
static int og_surface_at(const og_solid *s, double h, tb_mesh *m, tb_error *err) {
  tb_volume v;
  if (og_volume(s, h, &v, err)) return -1;
  int rc = tb_marching_cubes(&v, OG_ISO, m, NULL, err);
  tb_volume_free(&v);
  if (rc) return -1;
  int bad = tb_remesh_collapse_short(m, 0.25 * h) < 0 || tb_remesh_flip(m) < 0;
  if (!bad) tb_remesh_taubin(m, 6, 0.5, -0.53);
  if (bad || tb_remesh_flip(m) < 0) {
    tb_mesh_free(m);
    return tb_error_set(err, "organ", 0, "out of memory in the clean-up");
  }
  return 0;
}

/* The spacing whose surface has the vertex count closest to target: the
 * count goes like h^-2, so h * sqrt(n / target) is the next guess, kept
 * inside the bracket found so far (geometric mean when it leaves it);
 * stops within 1% (the count is noisy in h; tb_remesh_to_count does the
 * rest) or after 12 meshes. */
static int og_search(const og_solid *s, int target, tb_mesh *best, tb_error *err) {
  double h = 0.1 * sqrt(1400.0 / target), h_many = 0, h_few = 0;
  int best_off = -1;
  memset(best, 0, sizeof *best);
  for (int it = 0; it < 12; it++) {
    tb_mesh m;
    if (og_surface_at(s, h, &m, err)) return tb_mesh_free(best), -1;
    int off = abs(m.nv - target);
    if (best_off < 0 || off < best_off) {
      tb_mesh_free(best);
      *best = m, best_off = off;
    } else {
      tb_mesh_free(&m);
    }
    if (m.nv > target) h_many = h;
    if (m.nv < target) h_few = h;
    double next = h * sqrt((m.nv > 0 ? m.nv : 1) / (double)target);
    if (h_many > 0 && h_few > 0 && !(next > h_many && next < h_few)) next = sqrt(h_many * h_few);
    h = fmax(next, 0.01);
    if (best_off * 100 <= target) break;
  }
  return 0;
}

/* Within 5% of target: tb_remesh_to_count, flips around the new vertices,
 * and the final check. */
static int og_finish(tb_mesh *m, int target, const char *name, tb_error *err) {
  int rc = 0;
  if (abs(m->nv - target) * 20 > target)
    rc = tb_error_set(err, name, 0, "no grid spacing gives %d vertices within 5%% (closest %d)",
                      target, m->nv);
  else if (m->nv != target && (tb_remesh_to_count(m, target, err) < 0 || tb_remesh_flip(m) < 0))
    rc = tb_error_set(err, name, 0, "cannot make the surface's %d vertices %d", m->nv, target);
  tb_mesh_topo t = tb_mesh_topology(m);
  if (!rc && (!t.closed || !t.manifold || t.components != 1 || t.euler != 2 || t.misoriented_edges))
    rc = tb_error_set(err, name, 0, "the surface is not a closed sphere-like 2-manifold");
  if (rc) tb_mesh_free(m);
  return rc;
}

int tb_liver_surface_exact(const tb_liver_def *def, tb_mesh *surf, tb_error *err) {
  if (tb_liver_surface(def, surf, err)) return -1;
  int target = def->surface_verts ? def->surface_verts : tb_liver_surface_for(def->tets);
  return og_finish(surf, target, "liver", err);
}

int tb_organ_surface(const char *name, int verts, uint64_t seed, tb_mesh *out, tb_error *err) {
  memset(out, 0, sizeof *out);
  const tb_organ_info *info = tb_organ_find(name);
  if (!info)
    return tb_error_set(err, "organ", 0, "unknown organ '%s' (liver, spleen, gallbladder, steak)",
                        name ? name : "(null)");
  if (verts == 0) verts = info->verts;
  if (verts < 200 || verts > 50000)
    return tb_error_set(err, name, 0, "vertices must be in [200, 50000], not %d", verts);
  if (info == &tb_organs[0]) {
    tb_liver_def d = tb_liver_default_def();
    d.surface_verts = verts, d.seed = seed;
    return tb_liver_surface_exact(&d, out, err);
  }
  og_solid s;
  og_solid_make((og_kind)(info - tb_organs), seed, &s);
  if (og_search(&s, verts, out, err)) return -1;
  return og_finish(out, verts, name, err);
}
