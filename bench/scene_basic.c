/* The simple scenes: `beam`, a cantilever (fixed at x = 0) under a tip load
 * or gravity, the case with an analytic answer (Euler-Bernoulli deflection
 * P L^3 / (3 E I)); and `drop`, the liver in free fall (x = x0 + g t^2 / 2
 * for every model; ground contact comes later). */
#include <math.h>
#include <stdlib.h>

#include "sim_priv.h"
#include "tb_meshgen.h"

#define BEAM_L 10.0
#define BEAM_H 1.0

static int beam_mesh(const tb_sim_def *d, tb_mesh *out, tb_error *err) {
  int nx = d->nodes, nyz = nx / 10 > 1 ? nx / 10 : 1;
  if (nx < 1 || nx > 400)
    return tb_error_set(err, "beam", 0, "nodes (cells along x) must be 1..400");
  return tb_beam(BEAM_L, BEAM_H, BEAM_H, nx, nyz, nyz, out, err);
}

static int beam_inputs(tb_sim *s, double t, tb_error *err) {
  (void)t, (void)err;
  tb_sim_hold_anchor(s);
  double f = s->def.gravity > 0 ? 0 : s->def.amplitude / s->ndriven;
  for (int k = 0; k < s->ndriven; k++) s->force[s->driven[k]] = tb_v3(0, 0, -f);
  return 0;
}

/* Tip load 0.075: Euler-Bernoulli deflection 0.1 (1% of L) with E = 3000. */
const tb_sim_scene tb_scene_beam = {
    "beam",
    "cantilever 10 x 1 x 1 fixed at x = 0, tip load `amplitude` along -z (or `gravity`)",
    {.dt = 0.01, .duration = 2.0, .amplitude = 0.075, .release = 2.0, .nodes = 20, .seed = 1},
    beam_mesh,
    tb_sim_beam_ends,
    beam_inputs,
};

static int drop_setup(tb_sim *s, tb_error *err) {
  (void)s, (void)err;
  return 0;
}
static int drop_inputs(tb_sim *s, double t, tb_error *err) {
  (void)s, (void)t, (void)err;
  return 0;
}

const tb_sim_scene tb_scene_drop = {
    "drop",
    "the liver in free fall under `gravity` (no ground yet)",
    {.dt = 0.01, .duration = 0.5, .release = 0.5, .nodes = 1206, .gravity = 9.81, .seed = 1},
    tb_sim_liver_mesh,
    drop_setup,
    drop_inputs,
};
