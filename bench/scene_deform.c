/* Large-deformation scenes on a beam 4 x 1 x 1 held at x = 0 (the
 * stability suite's tests of which models invert, lose volume or fail to
 * recover). The end face x = L is prescribed: ramped linearly over the
 * first half of the time before `release`, held until `release`, then let
 * go so the beam can recover.
 *   beam-stretch  the end face pulled `amplitude` (default L: to 2 L, 100%)
 *                 along the axis;
 *   beam-twist    the end face rotated `amplitude` degrees (default 180)
 *                 about the beam's axis (y = z = H / 2);
 *   beam-crush    the end face pushed `amplitude` (default L / 2: to L / 2,
 *                 50%) along the axis towards the held face.
 * `nodes` is the cells along x; the cross-section gets nodes / 4 cells a
 * side (at least 1), so the cells are cubes. */
#include <math.h>
#include <stdlib.h>

#include "sim_priv.h"
#include "tb_meshgen.h"

#define DEF_L 4.0
#define DEF_H 1.0

static int deform_mesh(const tb_sim_def *d, tb_mesh *out, tb_error *err) {
  int nx = d->nodes, nyz = nx / 4 > 1 ? nx / 4 : 1;
  if (nx < 1 || nx > 400)
    return tb_error_set(err, "beam-stretch/twist/crush", 0, "nodes (cells along x) must be 1..400");
  return tb_beam(DEF_L, DEF_H, DEF_H, nx, nyz, nyz, out, err);
}

static int stretch_inputs(tb_sim *s, double t, tb_error *err) {
  (void)err;
  double f = tb_sim_ramp(s, t);
  for (int k = 0; f >= 0 && k < s->ndriven; k++) {
    int i = s->driven[k];
    s->mark[i] = 1, s->target[i] = tb_madd(s->mesh.x[i], f * s->def.amplitude, tb_v3(1, 0, 0));
  }
  return 0;
}

static int crush_inputs(tb_sim *s, double t, tb_error *err) {
  (void)err;
  double f = tb_sim_ramp(s, t);
  for (int k = 0; f >= 0 && k < s->ndriven; k++) {
    int i = s->driven[k];
    s->mark[i] = 1, s->target[i] = tb_madd(s->mesh.x[i], -f * s->def.amplitude, tb_v3(1, 0, 0));
  }
  return 0;
}

static int twist_inputs(tb_sim *s, double t, tb_error *err) {
  (void)err;
  double f = tb_sim_ramp(s, t), a = f * s->def.amplitude * (M_PI / 180.0);
  double c = cos(a), sn = sin(a), mid = 0.5 * DEF_H;
  for (int k = 0; f >= 0 && k < s->ndriven; k++) {
    int i = s->driven[k];
    tb_vec3 x = s->mesh.x[i];
    double y = x.y - mid, z = x.z - mid;
    s->mark[i] = 1, s->target[i] = tb_v3(x.x, mid + c * y - sn * z, mid + sn * y + c * z);
  }
  return 0;
}

const tb_sim_scene tb_scene_beam_stretch = {
    "beam-stretch",
    "beam 4 x 1 x 1 held at x = 0, the end face pulled `amplitude` along x (to 2 L), let go at "
    "`release`",
    {.dt = 0.01, .duration = 6.0, .amplitude = DEF_L, .release = 1.0, .nodes = 8, .seed = 1},
    deform_mesh,
    tb_sim_beam_ends,
    stretch_inputs,
};

const tb_sim_scene tb_scene_beam_twist = {
    "beam-twist",
    "beam 4 x 1 x 1 held at x = 0, the end face turned `amplitude` degrees (180) about the axis, "
    "let go at `release`",
    {.dt = 0.01, .duration = 6.0, .amplitude = 180.0, .release = 1.0, .nodes = 8, .seed = 1},
    deform_mesh,
    tb_sim_beam_ends,
    twist_inputs,
};

const tb_sim_scene tb_scene_beam_crush = {
    "beam-crush",
    "beam 4 x 1 x 1 held at x = 0, the end face pushed `amplitude` along -x (to L / 2), let go "
    "at `release`",
    {.dt = 0.01, .duration = 6.0, .amplitude = 0.5 * DEF_L, .release = 1.0, .nodes = 8, .seed = 1},
    deform_mesh,
    tb_sim_beam_ends,
    crush_inputs,
};
