/* Simulation scenes: a mesh, a deformation model (models/tb_model.h) and
 * what the scene does to it over time (fixed nodes, loads, prescribed
 * motions, a ground with friction, an instrument). A scene is a file
 * (scenes/README.md; the built-in ones are scenes/NAME.ini) or a
 * description built in code (the CLI's quick form). `simulate` and every
 * suite run scenes through this driver, which checks the model's health
 * every step so no blown-up run is reported as a result. */
#ifndef TB_SIM_H
#define TB_SIM_H

#include <stdint.h>

#include "tb_collider.h"
#include "tb_scene_file.h"
#include "models/tb_model.h"

/* Overrides of a scene file's [scene] parameters. tb_sim_def_init leaves
 * every field unset (the file's value is used); a set field is used as it
 * is: 0 means 0 (no gravity, no load), or is rejected where it makes no
 * sense (dt, duration). */
typedef struct tb_sim_def {
  double dt;            /* time step */
  double duration;      /* simulated time */
  double amplitude;     /* the scene's load or motion magnitude (its file says which) */
  double release;       /* the time prescribed motions let go */
  int nodes;            /* mesh resolution (liver: target tet-mesh vertices; beam: cells along x) */
  double gravity;       /* magnitude, along the file's gravity_direction (default -z) */
  double vmax;          /* health: velocity bound (0: 100 * scene size / duration) */
  int inversion;        /* 1: an inverted tet stops the run (0: only counted) */
  double drag;          /* ambient viscous drag: force -drag * m_i * v_i on every node */
  double energy_factor; /* health: the energy bound is this times the reference */
  int energy_every;     /* the energy is checked on the first this-many steps, then on every
                           this-many-th (1: every step) */
  double rest_speed;    /* at rest: largest node speed below this times the scene size per s */
  int ground;           /* 0: the file's [ground] is left out (1: kept) */
  uint64_t seed;        /* 0: the file's seed */
} tb_sim_def;

/* Every field unset. */
void tb_sim_def_init(tb_sim_def *def);
/* Sets one of the fields above from "key=value". Returns 1 when the key is
 * not a scene key (the caller then tries the model's keys), 0 when set, -1
 * on a bad value. */
int tb_sim_def_set(tb_sim_def *def, const char *key_eq_value, tb_error *err);

/* The built-in scenes (scenes/NAME.ini), by name. */
const char *const *tb_sim_scene_names(int *count);
/* The built-in scene's summary, or NULL when `name` is not one. */
const char *tb_sim_scene_summary(const char *name);
/* The file of a scene: a built-in name, or the path itself. */
void tb_sim_scene_path(const char *scene, char *out, size_t cap);

/* State of one simulation: what callers read (the hot arrays belong to
 * the model); the driver's own bookkeeping (the instrument's pose and
 * collider, contact buffers, the scalpel, the rest and energy detectors)
 * is behind priv (scenes/sim_priv.h). */
typedef struct tb_sim {
  tb_scene_desc desc; /* the scene as read */
  const char *name;   /* desc.name */
  tb_sim_def def;     /* effective parameters */
  tb_mesh mesh;       /* rest mesh (boundary triangles included) */
  tb_model model;
  tb_settings settings; /* the model's settings: the file's, then the caller's */
  double t;
  long steps;
  double size; /* diagonal of the rest bounding box */
  /* what the next step receives (tb_sim_loads) */
  tb_vec3 gravity;
  int nfixed;
  int *fixed;
  tb_vec3 *fixed_x;
  tb_vec3 *force;
  char *mark;         /* per node: prescribed this step */
  tb_vec3 *target;    /* per node: its prescribed position */
  const double *mass; /* the model's lumped node masses */
  /* the scene's node sets */
  int nanchor, *anchor;            /* fixed nodes, ascending */
  int ndriven, *driven;            /* nodes of [move] and [force] sections, ascending */
  int nprobe, *probe;              /* [output]'s nodes (the summary reports their displacement) */
  double probe_peak, probe_peak_t; /* largest |mean probe displacement| over the run, when */
  int hold; /* 1: moves are not let go at their release (held until cleared) */
  /* ground: a plane with Coulomb friction and restitution */
  int has_ground;
  tb_ground ground;
  int ground_off;       /* the scene's [ground] turned off (ground = 0): drawn, not acting */
  int meshed_nv, meshed_ntri; /* a surface given to a tet model: its used vertices and
                                 triangles (TetGen meshed it); 0: none */
  long settle_steps;    /* [ground] settle: the steps taken before t = 0 (0: none) */
  double settle_motion; /* the largest node motion of the last of them */
  /* the instrument (tb_sim_instrument poses it); its contacts at the last step */
  int has_tool;
  tb_pairlist pairs; /* (body surface triangle, instrument triangle), sorted */
  int ncontact;      /* body nodes in contact with it */
  /* penetration: of the last step (after the contact response) and the largest over the run */
  double pen_ground, pen_tool, pen_ground_max, pen_tool_max;
  double pen_tool_before_max; /* largest depth inside the tool before the response */
  /* health of the last step, the model's energy and its bound */
  tb_health health;
  double energy;
  double energy_bound;
  struct tb_sim_priv *priv;
} tb_sim;

/* Builds scene `scene` (a built-in name or a scene file) with overrides
 * def (NULL: none), model `model` (NULL: the file's [model] name) with
 * settings `set` added to the file's (NULL: none). With `mesh` non-NULL the
 * scene uses a copy of it instead of building its own. */
int tb_sim_create(tb_sim *s, const char *scene, const tb_sim_def *def, const char *model,
                  const tb_settings *set, const tb_mesh *mesh, tb_error *err);
/* The same from a description (taken over: freed with the simulation). */
int tb_sim_create_desc(tb_sim *s, tb_scene_desc *desc, const tb_sim_def *def, const char *model,
                       const tb_settings *set, const tb_mesh *mesh, tb_error *err);
/* The scene's rest mesh alone (to share one mesh among several models). */
int tb_sim_mesh(const char *scene, const tb_sim_def *def, tb_mesh *out, tb_error *err);
/* One step: the scene's inputs at t, the model's step, contact, the health
 * check. A failed step or an unhealthy state returns -1 with the reason in
 * err ("unstable: NaN or inf (node 12)" or the model's own error). Health:
 * tb_model_health (NaN/inf, velocity bound, inversion when def.inversion)
 * and, for models with an energy, energy growth beyond def.energy_factor
 * times a reference (scenes/sim.c explains it). */
int tb_sim_step(tb_sim *s, tb_error *err);
void tb_sim_destroy(tb_sim *s);
/* The scene's loads at time t without stepping: fills gravity, force
 * (scene forces only, no drag), nfixed/fixed/fixed_x. */
int tb_sim_loads(tb_sim *s, double t, tb_error *err);
/* The model's step input from the loads tb_sim_loads left (dt, gravity,
 * forces, prescribed nodes, the ground when the scene has one). */
tb_step tb_sim_step_input(const tb_sim *s);

/* The instrument at the current time in world coordinates (posed now);
 * 0 when the scene has none. */
int tb_sim_instrument(tb_sim *s, tb_mesh *out);
/* The body's surface triangles crossing the instrument at the last step
 * (each once, ascending), malloc'ed into *tri (3 per triangle): returns
 * how many, 0 without an instrument, or -1 out of memory. */
int tb_sim_contact_triangles(const tb_sim *s, int **tri);

/* Lets every prescribed motion go now (clears hold): the next step's
 * nodes are free. */
void tb_sim_let_go(tb_sim *s);

/* Metrics of the current state against the rest mesh. */
typedef struct tb_sim_metrics {
  double max_disp; /* largest |x - X| */
  int max_disp_node;
  double rms_disp;      /* root mean square of |x - X| over nodes */
  double volume_change; /* (V - V0) / V0 over the tets (no tets: the volume the surface encloses) */
  double energy;        /* the model's (NAN where undefined) */
  double max_speed;     /* largest |v| */
  double com_z;         /* centre of mass height (unit node weights) */
  int inverted;         /* tets with signed volume <= 0 */
} tb_sim_metrics;
tb_sim_metrics tb_sim_measure(const tb_sim *s);
/* The largest volume change a stable run of this model's material may
 * show: the change under a uniaxial strain of 50%, (1 - 2 nu) / 2, at least
 * 5% (nu 0.3 for a model without a Poisson ratio: 20%). */
double tb_sim_volume_tolerance(const tb_sim *s);
/* 1 when the state, though finite and within the health bounds, is broken:
 * inverted tets, a volume change beyond tb_sim_volume_tolerance, or an
 * energy above its bound; why gets the reasons ("114 inverted tets, volume
 * -16.9% (tolerance 20%)"). A run that ends so is `degraded`, not
 * `stable`. */
int tb_sim_degraded(const tb_sim *s, char *why, size_t cap);
/* At rest: the largest node speed, averaged over the last completed window
 * of TB_SIM_REST_WINDOW s (its displacement over the window's length), is
 * below def.rest_speed * size (per s); before a window has passed, the
 * current largest node speed. The average lets a node that jitters in
 * place from step to step (an unconverged iterative solver) count as at
 * rest, and no motion slower than the window escapes it. */
#define TB_SIM_REST_WINDOW 0.1
int tb_sim_at_rest(const tb_sim *s, double *speed, double *tol);

/* ParaView output (scenes/output.c): the current state as one .vtu per
 * object (body, a tet model's current surface, instrument posed now,
 * ground) and dir/frame_NNNNN.vtm naming them as blocks; dir created. The
 * body carries point data displacement, velocity, fixed and driven, and
 * cell data equivalent_green_strain, von_mises_stress (models with E and
 * nu) and inverted. tb_sim_write_pvd writes dir/frames.pvd (the .vtm files
 * with their times) and one NAME.pvd per object. */
int tb_sim_write_frame(tb_sim *s, const char *dir, int frame, tb_error *err);
/* Per tet of the current state (arrays of ntet, any may be NULL): the
 * equivalent Green strain, the von Mises stress of S = lambda tr(E) I +
 * 2 mu E (NAN for models without E and nu), inverted (signed volume <= 0).
 * Returns 1 when the model has a stress (E and nu). */
int tb_sim_tet_fields(const tb_sim *s, double *strain, double *vm, unsigned char *inv);
int tb_sim_write_pvd(const tb_sim *s, const char *dir, int nframes, const double *times,
                     tb_error *err);
/* The model's current surface (cut, or refined) into path, by extension
 * (core/tb_mesh_io.h's writers: .obj, .off, .stl, .vtk). */
int tb_sim_write_surface(const tb_sim *s, const char *path, tb_error *err);

#endif
