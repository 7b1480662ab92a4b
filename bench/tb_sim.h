/* Simulation scenes: a tet mesh, a deformation model (models/tb_model.h)
 * and what the scene does to it over time (fixed nodes, a pulled patch, an
 * instrument pressing in, a tip load, gravity). One scene is one entry of
 * the table in bench/sim.c; `simulate`, `table 3.5` and `figure 3.10` run
 * them through this driver, which checks the model's health every step so
 * no blown-up run is reported as a result. */
#ifndef TB_SIM_H
#define TB_SIM_H

#include <stdint.h>

#include "tb_collider.h"
#include "tb_model.h"

/* Scene settings; zero means the scene's default. */
typedef struct tb_sim_def {
  double dt;        /* time step */
  double duration;  /* simulated time */
  double amplitude; /* stretch: pull distance; press: depth; beam: tip load; drop: unused */
  double release;   /* stretch: time the patch is let go */
  int nodes;        /* liver scenes: target tet-mesh vertices (thesis 1206); beam: cells along x */
  double gravity;   /* magnitude along -z (drop: 9.81; others 0) */
  double vmax;      /* health: velocity bound (0: 100 * scene size / duration) */
  int inversion;    /* 1: an inverted tet stops the run (else it is only counted) */
  double drag;      /* ambient viscous drag: force -drag * m_i * v_i on every node (0: none) */
  /* health: energy growth (models with an energy; see tb_sim_step) */
  double energy_factor; /* the bound is this times the reference energy (0: 100) */
  int energy_every;     /* the energy is checked on the first this-many steps, then on every
                           this-many-th (0: 16; 1: every step) */
  uint64_t seed;
} tb_sim_def;

/* Sets one of the fields above from "key=value" (dt, duration, amplitude,
 * release, nodes, gravity, vmax, inversion, drag, energy_factor,
 * energy_every). Returns 1 when the key is not a scene key (the caller
 * then tries the model's keys), 0 when set, -1 on a bad value. */
int tb_sim_def_set(tb_sim_def *def, const char *key_eq_value, tb_error *err);

typedef struct tb_sim_scene tb_sim_scene; /* private: bench/sim_priv.h */

/* The scenes, by name: liver-stretch, liver-press, beam, drop, beam-stretch,
 * beam-twist, beam-crush. */
const char *const *tb_sim_scene_names(int *count);
const char *tb_sim_scene_summary(const char *name);

/* State of one simulation. The hot arrays belong to the model; the rest is
 * the scene's bookkeeping. */
typedef struct tb_sim {
  const tb_sim_scene *scene;
  tb_sim_def def; /* with the scene's defaults filled in */
  tb_mesh mesh;   /* rest tet mesh (boundary triangles included) */
  tb_model model;
  double t;
  long steps;
  double size; /* diagonal of the rest bounding box */
  /* what the next step receives */
  tb_vec3 gravity;
  int nfixed;
  int *fixed;
  tb_vec3 *fixed_x;
  tb_vec3 *force;
  char *mark;      /* per node: prescribed this step (scenes set mark and target) */
  tb_vec3 *target; /* per node: its prescribed position */
  double *mass;    /* the model's lumped node masses (for drag) */
  /* scene bookkeeping: an anchored set, a driven set and its direction */
  int nanchor, *anchor;
  int ndriven, *driven;
  tb_vec3 drive;
  int hold; /* 1: the driven set is not let go at `release` (held until cleared) */
  /* liver-press: the instrument and its collision query against the surface */
  tb_mesh tool;
  tb_collider *collider;
  tb_pairlist pairs;
  char *contact; /* per node: held on the tool's surface last step */
  int ncontact;
  tb_vec3 tool_tip; /* world position of the tool's tip */
  /* health of the last step */
  tb_health health;
  /* the energy-growth detector (tb_sim_step) */
  double total_mass;    /* sum of the lumped masses */
  double load_max;      /* largest scene load seen: sum |f_i| + M |g| */
  double energy0;       /* the model's energy at creation */
  double energy_driven; /* largest energy seen while prescribed nodes were moving */
  int moving;           /* prescribed nodes moved since the last energy check */
  double energy;        /* the model's energy at the last check (NAN: none) */
  double energy_bound;  /* the bound it was held to (0: not checked: driven or no energy) */
} tb_sim;

/* Builds the scene's mesh (or copies `mesh` when not NULL), the model with
 * settings mset (NULL: the model's defaults) and the scene's sets. */
int tb_sim_create(tb_sim *s, const char *scene, const tb_sim_def *def, const char *model,
                  const tb_settings *mset, const tb_mesh *mesh, tb_error *err);
/* The scene's rest mesh alone (to share one mesh among several models). */
int tb_sim_mesh(const char *scene, const tb_sim_def *def, tb_mesh *out, tb_error *err);
/* One step: the scene's inputs at t, the model's step, the health check.
 * A failed step or an unhealthy state returns -1 with the reason in err
 * ("unstable: NaN or inf (node 12)" or the model's own error). The health
 * check is tb_model_health (NaN/inf, velocity bound, inversion when
 * def.inversion) and, for models with an energy, energy growth: on check
 * steps (def.energy_every) the energy must stay within def.energy_factor
 * times a reference, else s->health says "energy growth (E = .., bound ..)".
 * The reference (bench/sim.c explains it) covers what the scene can put in:
 * the start energy, the work its loads can do, and the largest energy seen
 * while prescribed nodes were being moved (no check on such steps). */
int tb_sim_step(tb_sim *s, tb_error *err);
void tb_sim_destroy(tb_sim *s);
/* The scene's loads at time t without stepping: fills gravity, force
 * (scene forces only, no drag), nfixed/fixed/fixed_x (e.g. to pose the
 * same static problem to the reference solver). */
int tb_sim_loads(tb_sim *s, double t, tb_error *err);

/* Metrics of the current state against the rest mesh. */
typedef struct tb_sim_metrics {
  double max_disp;      /* largest |x - X| */
  double rms_disp;      /* root mean square of |x - X| over nodes */
  double volume_change; /* (V - V0) / V0 over the tets */
  double energy;        /* the model's (NAN where undefined) */
  double max_speed;     /* largest |v| */
  double com_z;         /* centre of mass height (unit node weights) */
  int inverted;         /* tets with signed volume <= 0 */
} tb_sim_metrics;
tb_sim_metrics tb_sim_measure(const tb_sim *s);

/* Writes the current surface (boundary triangles) as legacy VTK to
 * dir/frame_NNNNN.vtk; dir is created. */
int tb_sim_write_vtk(const tb_sim *s, const char *dir, int frame, tb_error *err);

#endif
