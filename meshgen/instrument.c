/* A laparoscopic grasper as two closed tubes swept along polylines with
 * elliptical cross-sections: the shaft running into the lower jaw, and the
 * upper jaw hinged at the shaft's tip, opened by jaw_opening. Each tube of S
 * segments and R rings, capped at both ends, has S*R + 2 vertices and 2*S*R
 * triangles; the defaults (S 16, 24 + 15 rings) give the thesis's
 * instrument counts, 628 vertices / 1248 triangles. The tip (hinge) is at
 * the origin, the shaft along +z, the jaws toward -z. */
#include <stdlib.h>
#include <string.h>

#include "tb_meshgen.h"

tb_instrument_def tb_instrument_default_def(void) {
  tb_instrument_def d;
  d.length = 15.0;
  d.radius = 0.25;
  d.jaw_length = 1.2;
  d.jaw_opening = 0.5;
  d.segments = 16;
  d.shaft_rings = 24;
  d.jaw_rings = 15;
  return d;
}

/* One ring of the tube: centre, tangent and the ellipse's half-axes along
 * the two normal directions (u in the plane of the jaws, v across it). */
typedef struct ring {
  tb_vec3 c, t;
  double a, b;
} ring;

/* Appends a closed tube over rings[0..n-1] to m (arrays sized by caller). */
static void add_tube(tb_mesh *m, const ring *rings, int n, int segs) {
  int base = m->nv;
  for (int r = 0; r < n; r++) {
    tb_vec3 t = tb_normalize(rings[r].t);
    tb_vec3 side = tb_v3(1, 0, 0); /* the jaws open in the y-z plane */
    tb_vec3 v = tb_normalize(tb_cross(t, side));
    tb_vec3 u = tb_cross(v, t);
    for (int s = 0; s < segs; s++) {
      double phi = 2.0 * M_PI * s / segs;
      m->x[m->nv++] =
          tb_madd(tb_madd(rings[r].c, rings[r].a * cos(phi), u), rings[r].b * sin(phi), v);
    }
  }
  int cap0 = m->nv, cap1 = m->nv + 1;
  m->x[m->nv++] = rings[0].c;
  m->x[m->nv++] = rings[n - 1].c;
  int *tri = m->tri + 3 * m->ntri;
  for (int r = 0; r + 1 < n; r++)
    for (int s = 0; s < segs; s++) {
      int a = base + r * segs + s, b = base + r * segs + (s + 1) % segs;
      int c = a + segs, d = b + segs;
      tri[0] = a, tri[1] = b, tri[2] = c, tri += 3;
      tri[0] = b, tri[1] = d, tri[2] = c, tri += 3;
    }
  for (int s = 0; s < segs; s++) {
    int a = base + s, b = base + (s + 1) % segs;
    tri[0] = cap0, tri[1] = b, tri[2] = a, tri += 3;
    int c = base + (n - 1) * segs + s, d = base + (n - 1) * segs + (s + 1) % segs;
    tri[0] = cap1, tri[1] = c, tri[2] = d, tri += 3;
  }
  m->ntri += 2 * segs * n;
}

/* Jaw profile at fraction s in [0,1] from hinge to tip: flattened, tapered. */
static void jaw_section(const tb_instrument_def *d, double s, double *a, double *b) {
  *a = d->radius * (0.95 - 0.55 * s); /* across the opening plane */
  *b = d->radius * (0.55 - 0.30 * s); /* in the opening plane: flat jaws */
}

int tb_instrument(const tb_instrument_def *d, tb_mesh *out, tb_error *err) {
  memset(out, 0, sizeof *out);
  if (!(d->length > 0 && d->radius > 0 && d->jaw_length > 0) ||
      !isfinite(d->length + d->radius + d->jaw_length))
    return tb_error_set(err, "instrument", 0, "length, radius and jaw_length must be positive");
  if (!(d->jaw_opening >= 0 && d->jaw_opening < 2.5))
    return tb_error_set(err, "instrument", 0, "jaw_opening must be in [0, 2.5) radians");
  if (d->segments < 3 || d->segments > 4096 || d->shaft_rings < 4 || d->jaw_rings < 2 ||
      d->shaft_rings > 100000 || d->jaw_rings > 100000)
    return tb_error_set(err, "instrument", 0,
                        "segments >= 3, shaft_rings >= 4 and jaw_rings >= 2 are required");
  int S = d->segments, R1 = d->shaft_rings, R2 = d->jaw_rings;
  out->x = malloc(sizeof(tb_vec3) * ((size_t)S * (R1 + R2) + 4));
  out->tri = malloc(sizeof(int) * 6 * (size_t)S * (R1 + R2));
  ring *rings = malloc(sizeof(ring) * (size_t)(R1 > R2 ? R1 : R2));
  if (!out->x || !out->tri || !rings) {
    free(rings), tb_mesh_free(out);
    return tb_error_set(err, "instrument", 0, "out of memory");
  }
  double half = d->jaw_opening / 2;
  tb_vec3 lower = tb_v3(0, -sin(half), -cos(half)), upper = tb_v3(0, sin(half), -cos(half));
  /* shaft + lower jaw: 1/3 of the rings on the jaw, the rest on the shaft */
  int nj = R1 / 3, ns = R1 - nj;
  for (int r = 0; r < ns; r++) {
    double z = d->length * (1.0 - (double)r / (ns - 1));
    rings[r] = (ring){tb_v3(0, 0, z), tb_v3(0, 0, -1), d->radius, d->radius};
  }
  rings[ns - 1].t = tb_add(tb_v3(0, 0, -1), lower); /* bend at the hinge */
  for (int r = 0; r < nj; r++) {
    double s = (double)(r + 1) / nj;
    rings[ns + r].c = tb_scale(lower, s * d->jaw_length);
    rings[ns + r].t = lower;
    jaw_section(d, s, &rings[ns + r].a, &rings[ns + r].b);
  }
  add_tube(out, rings, R1, S);
  /* upper jaw: from inside the shaft's tip out to its own tip */
  for (int r = 0; r < R2; r++) {
    double s = (double)r / (R2 - 1);
    rings[r].c = tb_madd(tb_v3(0, 0, 0.5 * d->radius * (1 - s)), s * d->jaw_length, upper);
    rings[r].t = upper;
    jaw_section(d, s, &rings[r].a, &rings[r].b);
  }
  add_tube(out, rings, R2, S);
  free(rings);
  return 0;
}
