/* A simulation scene: its defaults, its mesh and what it prescribes each
 * step. Scenes live in bench/scene_*.c, one table in bench/sim.c. */
#ifndef TB_SIM_PRIV_H
#define TB_SIM_PRIV_H

#include "tb_sim.h"

struct tb_sim_scene {
  const char *name;
  const char *summary;
  tb_sim_def defaults;
  /* The rest tet mesh for def (boundary triangles included). */
  int (*mesh)(const tb_sim_def *def, tb_mesh *out, tb_error *err);
  /* Chooses the anchored and driven sets, builds the tool; after the model. */
  int (*setup)(tb_sim *s, tb_error *err);
  /* Inputs of the step that ends at time t: sets s->mark/target for
   * prescribed nodes (cleared by the caller), s->force and s->gravity. */
  int (*inputs)(tb_sim *s, double t, tb_error *err);
};

extern const tb_sim_scene tb_scene_liver_stretch, tb_scene_liver_press, tb_scene_beam,
    tb_scene_drop;
extern const tb_sim_scene tb_scene_beam_stretch, tb_scene_beam_twist, tb_scene_beam_crush;

/* Indices of nodes selected by keep(x, data), malloc'ed; returns the count or -1. */
int tb_sim_select(const tb_mesh *m, int (*keep)(tb_vec3 x, const void *data), const void *data,
                  int **out);
/* Marks the anchored nodes prescribed at their rest positions. */
void tb_sim_hold_anchor(tb_sim *s);
/* Holds the anchor and returns how far the driven set has come at t: the
 * ramp fraction t / (release / 2), 1 once the ramp is done, and -1 once it
 * is let go (t past `release`, unless s->hold). */
double tb_sim_ramp(tb_sim *s, double t);
/* A beam along x: the anchor is the face at the lowest x, the driven set
 * the face at the highest. */
int tb_sim_beam_ends(tb_sim *s, tb_error *err);
/* The liver tet mesh for the liver scenes (nodes: target vertices). */
int tb_sim_liver_mesh(const tb_sim_def *def, tb_mesh *out, tb_error *err);

#endif
