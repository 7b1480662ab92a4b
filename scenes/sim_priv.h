/* Private to the scene driver (the files of scenes/): building a scene's meshes,
 * resolving node selections, evaluating motions, contact. */
#ifndef TB_SIM_PRIV_H
#define TB_SIM_PRIV_H

#include "tb_collider.h"
#include "tb_sim.h"

/* A prescribed rigid motion resolved to numbers (keyframes evaluated). */
typedef struct tb_sim_motion {
  int nkey;
  double *t;     /* keyframe times */
  tb_vec3 *move; /* translation (or (distance, 0, 0) with a direction) */
  tb_vec3 *axis; /* unit rotation axis */
  double *angle; /* radians */
  int has_direction;
  tb_vec3 direction, centre;
} tb_sim_motion;

/* A selected node set with what acts on it. */
typedef struct tb_sim_group {
  int n, *ids;
  tb_vec3 value;        /* force per node */
  double start, stop;   /* force: active window */
  double release;       /* move: let go after (INFINITY: never) */
  tb_sim_motion motion; /* move */
} tb_sim_group;

/* A scalpel of the scene resolved to numbers; state 0 before, 1 cutting,
 * 2 done; the path handed last; what its cut did. */
typedef struct tb_sim_blade {
  int n, line;
  tb_vec3 *path, *now, depth, last;
  double start, stop;
  int state, last_n;
  tb_cut_stats stats;
} tb_sim_blade;

/* The driver's own state of a simulation (tb_sim.priv). */
typedef struct tb_sim_priv {
  double param[TB_P_COUNT]; /* the scene's parameters, resolved */
  char *on_surface;         /* per node: used by a surface triangle */
  tb_vec3 lo, hi;           /* the rest mesh's bounding box */
  int nforce, nmove;
  tb_sim_group *forces, *moves;
  /* the instrument: its mesh in its own frame, pose per step, contact */
  tb_mesh tool;        /* local coordinates */
  tb_vec3 *tool_x;     /* world positions at the current pose */
  tb_vec3 tool_origin; /* origin + offset */
  tb_sim_motion tool_motion;
  double tool_margin, tool_friction;
  tb_mat3 tool_R; /* the current pose: x = R x_local + t */
  tb_vec3 tool_t;
  tb_mesh tool_surface; /* the model's surface the collider was built on (not owned) */
  unsigned long surface_version;
  int *slot; /* per node: its entry in the correction buffers, or -1 */
  tb_collider *collider;
  char *contact;   /* per node: in contact with the tool last step */
  tb_vec3 *x_prev; /* positions before the step (friction) */
  /* rest: positions at the start of the current window (TB_SIM_REST_WINDOW s),
   * its start time (NAN before the first step), and the largest node
   * speed averaged over the last completed window (NAN before one) */
  tb_vec3 *x_window;
  double window_t0, window_speed;
  int *ids_buf; /* scratch for contact corrections */
  tb_vec3 *xc_buf, *vc_buf;
  double *depth_buf, *keep_buf;
  /* the scalpels ([cut], scenes/cut.c): one a model cuts with at a time */
  int nblade, active; /* active: the blade cutting now, -1 none */
  tb_sim_blade *blade;
  tb_cut_stats cut_stats; /* what the last cut did */
  int nforce_points;      /* points the force array holds beyond the mesh's nodes */
  /* points a cut made inside a [fix] region: held where the cut left them,
   * like the nodes the region selected (ascending, all beyond the mesh's) */
  int nheld_new;
  int *held_new;
  tb_vec3 *held_new_x;
  /* the energy-growth detector (tb_sim_step) */
  double total_mass;
  double settle; /* [ground] settle: seconds of settling before t = 0 at most */
  double load_max;
  double energy0;
  double energy_driven;
  int moving;
} tb_sim_priv;

/* The mesh a source names, with the scene's parameters (file, or generator
 * with settings; the liver's `nodes` and the beam's `cells` shorthands). */
int tb_sim_build_mesh(const tb_mesh_source *src, const char *scene_path, const double *param,
                      uint64_t seed, tb_mesh *out, tb_error *err);

/* The nodes a selection picks on the rest mesh, ascending and unique,
 * malloc'ed; errors (an id out of range, nothing selected) name the scene
 * file's line. Returns the count, or -1. */
/* 1 when a region selector of sel (box, fraction, plane, sphere; not ids
 * or patch, which name the mesh's own nodes) takes the point x. */
int tb_sim_select_point(const tb_sim *s, const tb_selection *sel, tb_vec3 x);
int tb_sim_select(const tb_sim *s, const tb_selection *sel, const char *what, int **out,
                  tb_error *err);

/* Resolves a description's motion with the parameters; frees with tb_sim_motion_free. */
int tb_sim_motion_make(const tb_motion *m, const double *param, tb_sim_motion *out, tb_error *err);
void tb_sim_motion_free(tb_sim_motion *m);
/* The rigid motion at time t applied to rest point x. */
tb_vec3 tb_sim_motion_apply(const tb_sim_motion *m, double t, tb_vec3 x);

/* Contact (scenes/contact.c): sets up the ground and the instrument, and
 * corrects the model's state after a step. */
int tb_sim_contact_setup(tb_sim *s, tb_error *err);
int tb_sim_contact(tb_sim *s, tb_error *err);
void tb_sim_contact_free(tb_sim *s);
/* Before the model's step at time t: last step's instrument contacts are
 * prescribed on the instrument's surface. */
int tb_sim_contact_prestep(tb_sim *s, double t, tb_error *err);
/* Poses the instrument at time t (world positions in s->tool_x). */
void tb_sim_tool_pose(tb_sim *s, double t, tb_mat3 *R, tb_vec3 *tr);

/* The scalpel (scenes/cut.c): checks and resolves [cut] after the model
 * exists; before a step at time t (the step's end) BEGIN and MOVE; after
 * it, END once t reaches stop. */
int tb_sim_cut_setup(tb_sim *s, tb_error *err);
int tb_sim_cut_before(tb_sim *s, double t, tb_error *err);
int tb_sim_cut_after(tb_sim *s, double t, tb_error *err);
void tb_sim_cut_free(tb_sim *s);

#endif
