/* Private to the scene driver (the files of scenes/): building a scene's meshes,
 * resolving node selections, evaluating motions, contact. */
#ifndef TB_SIM_PRIV_H
#define TB_SIM_PRIV_H

#include "tb_sim.h"

/* The mesh a source names, with the scene's parameters (file, or generator
 * with settings; the liver's `nodes` and the beam's `cells` shorthands). */
int tb_sim_build_mesh(const tb_mesh_source *src, const char *scene_path, const double *param,
                      uint64_t seed, tb_mesh *out, tb_error *err);

/* The nodes a selection picks on the rest mesh, ascending and unique,
 * malloc'ed; errors (an id out of range, nothing selected) name the scene
 * file's line. Returns the count, or -1. */
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
