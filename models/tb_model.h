/* Deformation models behind one interface. A model is one file defining a
 * tb_model_class (a small table of functions) and one entry in the table of
 * models/model.c; scenes and suites never switch on a model's name.
 *
 * Every model built so far works on the nodes of a tet mesh (shape
 * matching treats them as particles and may ignore the tets), with lumped
 * node masses from the density and the tet volumes; the interface also
 * serves models whose points are not the mesh's nodes (npoints, surface)
 * and contact response between steps (correct). A step advances the state by dt under
 * gravity, external node forces and prescribed (Dirichlet) node positions:
 * a prescribed node ends the step exactly at its position, with the
 * velocity that moved it there. */
#ifndef TB_MODEL_H
#define TB_MODEL_H

#include <math.h>
#include <stddef.h>
#include <stdio.h>

#include "core/tb_error.h"
#include "core/tb_mesh.h"

/* ---- settings ----
 * A model declares its own settings as one table of tb_setting (key, type,
 * default, range, one-line doc) in its own file, over its own settings
 * struct. Callers pass key=value text in a tb_settings; tb_model_create
 * fills the model's struct from the table's defaults, then the user's
 * values, each parsed and range-checked against the table. `simulate
 * --set`, `simulate --list` and docs/reference.md's lists come from the tables. */
#define TB_SETTINGS_MAX 32
#define TB_SETTING_TEXT_MAX 256 /* a value's text, and a FILE setting's field, with its NUL */
typedef struct tb_settings {
  int n;
  struct {
    char key[32];
    char value[TB_SETTING_TEXT_MAX];
  } kv[TB_SETTINGS_MAX];
} tb_settings;

/* Empty: every model's defaults. */
void tb_settings_init(tb_settings *s);
/* Syntax only ("key=value"; the model checks key and value at create);
 * replaces an earlier value of the same key; an error when full or when the
 * key or value is too long. */
int tb_settings_set(tb_settings *s, const char *key_eq_value, tb_error *err);
/* key=v with v printed %.17g (reads back exactly). */
int tb_settings_setd(tb_settings *s, const char *key, double v, tb_error *err);

typedef enum {
  TB_SETTING_REAL,
  TB_SETTING_INT,
  TB_SETTING_CHOICE,
  TB_SETTING_FILE
} tb_setting_type;
/* tb_setting.open: which bounds of [lo, hi] are excluded. */
enum { TB_OPEN_LO = 1, TB_OPEN_HI = 2 };

/* One entry of a model's settings table. REAL is a double in the model's
 * struct, INT and CHOICE an int (CHOICE: the index into choices; the value
 * text is a name or the index), FILE a char[TB_SETTING_TEXT_MAX] holding a
 * file name as given ("" by default: none; the model reads the file). */
typedef struct tb_setting {
  const char *key;
  tb_setting_type type;
  size_t offset;       /* into the model's own settings struct */
  double def, lo, hi;  /* default and range, inclusive unless open says (CHOICE: index) */
  const char *choices; /* CHOICE: "rigid|linear|quadratic" */
  const char *doc;     /* one line */
  int open;            /* TB_OPEN_LO | TB_OPEN_HI: that bound is excluded */
} tb_setting;

/* Table entries over the model's settings struct T, whose field has the
 * key's name: a real in [lo, hi] (open: TB_OPEN_*), a whole number in
 * [lo, hi], a choice of "a|b|c" (hi: the last index). */
#define TB_SETTING_R(T, key, def, lo, hi, open, doc) \
  { #key, TB_SETTING_REAL, offsetof(T, key), def, lo, hi, NULL, doc, open }
#define TB_SETTING_I(T, key, def, lo, hi, doc) \
  { #key, TB_SETTING_INT, offsetof(T, key), def, lo, hi, NULL, doc, 0 }
#define TB_SETTING_C(T, key, def, hi, choices, doc) \
  { #key, TB_SETTING_CHOICE, offsetof(T, key), def, 0, hi, choices, doc, 0 }
#define TB_SETTING_F(T, key, doc) \
  { #key, TB_SETTING_FILE, offsetof(T, key), 0, 0, 0, NULL, doc, 0 }

/* Table fragments the models share. Every model takes the mass settings;
 * node_mass_def is its default (msm, sm: 1, the thesis's unit masses). */
#define TB_SETTINGS_MASS(T, node_mass_def)                                         \
  TB_SETTING_R(T, density, 1.0, 0.0, HUGE_VAL, 0,                                  \
               "mass per volume: node mass = density * (volume of its tets) / 4"), \
      TB_SETTING_R(T, node_mass, node_mass_def, 0.0, HUGE_VAL, 0,                  \
                   "> 0: every node gets this mass instead (0: from density)")
/* Young's modulus up to 1e20: beyond it a stiffness matrix's entries
 * overflow on small elements. */
#define TB_SETTING_YOUNG(T, doc) TB_SETTING_R(T, E, 3000.0, 0.0, 1e20, TB_OPEN_LO, doc)
#define TB_SETTINGS_MATERIAL(T)           \
  TB_SETTING_YOUNG(T, "Young's modulus"), \
      TB_SETTING_R(T, nu, 0.3, -1.0, 0.5, TB_OPEN_LO | TB_OPEN_HI, "Poisson ratio")

/* A rigid ground: the plane (x - p).n >= 0 (n unit), Coulomb friction with
 * static mu_s >= kinetic mu_k, normal restitution in [0, 1]. */
typedef struct tb_ground {
  tb_vec3 p, n;
  double mu_s, mu_k, restitution;
} tb_ground;

/* What one step receives. */
typedef struct tb_step {
  double dt;
  tb_vec3 gravity;      /* acceleration applied to every node */
  const tb_vec3 *force; /* nv external node forces, or NULL */
  int nfixed;
  const int *fixed;       /* prescribed nodes, strictly ascending */
  const tb_vec3 *fixed_x; /* their positions at the end of the step */
  /* The scene's ground, or NULL. A model whose class sets own_ground
   * projects it inside its step (with friction and restitution); for the
   * others the scene corrects the state after the step (scenes/contact.c). */
  const tb_ground *ground;
} tb_step;

/* The current surface of a model: nv points x (the model's points for tet
 * models), ntri triangles. version changes whenever nv, ntri or tri change
 * (a cut, a remesh), so a collision hierarchy refits while it is the same
 * and rebuilds when it is not. x0: the rest positions of the nv points
 * when the model has points beyond the mesh's nodes (msm-vvs's finer
 * levels); NULL: the points are the rest mesh's nodes. */
typedef struct tb_surface {
  int nv, ntri;
  const tb_vec3 *x;
  const int *tri;
  unsigned long version;
  const tb_vec3 *x0;
} tb_surface;

/* ---- cutting ----
 * A scalpel whose edge has moved along path[0 .. npath) with the blade's
 * fixed depth vector (the folded plane of cutting/tb_fold.h: piece k is
 * path[k] + s (path[k+1] - path[k]) + t depth, s, t in [0, 1]). BEGIN starts
 * a cut; MOVE gives the whole path so far (npath >= 2; the blade's position
 * last); the steps between MOVEs run the cut phase; END says the blade has
 * left: the model's volume and surface are split and closed, so npoints
 * may grow and the surface's version changes. */
typedef enum { TB_CUT_BEGIN = 0, TB_CUT_MOVE = 1, TB_CUT_END = 2 } tb_cut_kind;
typedef struct tb_cut_event {
  tb_cut_kind kind;
  int npath;
  const tb_vec3 *path;
  tb_vec3 depth;
} tb_cut_event;
/* What a cut did, filled at END (counts are 0 where a model has no such
 * thing). */
typedef struct tb_cut_stats {
  int removed, created;        /* volume elements (spheres) removed; made anew */
  double removed_r, created_r; /* their mean radii */
  int points, uncovered;       /* the intermediate point set; points no new sphere covers */
  int split_tris, crack_tris;  /* surface triangles split; crack triangles made */
  int new_points;              /* points (surface vertices) added */
  int components;              /* connected pieces of the surface after the cut */
} tb_cut_stats;

/* Spheres of a sphere-based model, for pictures and checks: n centres and
 * radii, alive flags (removed spheres keep their index), nlinks links (2
 * nlinks indices), and for each of the model's nbound points the spheres
 * its skin follows (up to 3; -1 for none). */
typedef struct tb_model_spheres {
  int n, nlinks;
  const tb_vec3 *c;
  const double *r;
  const unsigned char *alive;
  const int *links;
  int nbound;
  const int (*bound)[3];
} tb_model_spheres;

/* Groups of a model's points, for pictures (shape matching's clusters):
 * group[i] is point i's first group (ascending), -1 for none; n points,
 * ngroups groups. */
typedef struct tb_model_groups {
  int n, ngroups;
  const int *group;
} tb_model_groups;

typedef struct tb_model_class {
  const char *name;
  const char *summary;
  /* its settings table and the size of the struct the table describes */
  const tb_setting *settings;
  int nsettings;
  size_t settings_size;
  /* Builds the model from a tet mesh (copied; mesh may be freed after);
   * settings points at the model's own struct, filled from the table's
   * defaults and then the user's values (already range-checked). */
  void *(*create)(const tb_mesh *mesh, const void *settings, tb_error *err);
  /* Advances one step; a failure (e.g. a matrix that is not positive
   * definite) returns non-zero with err filled in. */
  int (*step)(void *self, const tb_step *in, tb_error *err);
  const tb_vec3 *(*positions)(const void *self);
  const tb_vec3 *(*velocities)(const void *self);
  /* Elastic potential + kinetic energy, or NAN where a model has no energy. */
  double (*energy)(const void *self);
  void (*destroy)(void *self);
  /* Lumped point masses, npoints of them. */
  const double *(*masses)(const void *self);
  /* Current number of points (NULL: the mesh's nodes); fixes, forces and
   * correct index these. */
  int (*npoints)(const void *self);
  /* Current surface (NULL: the rest mesh's boundary triangles over the
   * current positions, version 0). */
  tb_surface (*surface)(const void *self);
  /* Overwrites positions and velocities of points ids[0..n) between steps
   * (contact response); x or v may be NULL to leave that one as it is. */
  void (*correct)(void *self, int n, const int *ids, const tb_vec3 *x, const tb_vec3 *v);
  /* 1: the step handles tb_step.ground itself (position-based models
   * project it with their constraints); owns_ground, when set, decides
   * per instance instead (a setting of the model). */
  int own_ground;
  int (*owns_ground)(const void *self);
  /* 1: create also takes a closed triangle surface without tets (the
   * surface models); scenes refuse a surface mesh for the others. */
  int surface_mesh;
  /* Cutting (NULL: the model cannot be cut): one event; stats (may be
   * NULL) is filled at END. */
  int (*cut)(void *self, const tb_cut_event *ev, tb_cut_stats *stats, tb_error *err);
  /* A tet model that cuts by removing tets: per tet of the rest mesh, in
   * its order, 0 once a cut removed it (NULL: all alive). */
  const unsigned char *(*tets_alive)(const void *self);
  /* What pictures of the model's structure show (render --structure):
   * its spheres and their links, or its point groups (NULL: it has none;
   * with neither, the tet edges). */
  tb_model_spheres (*spheres)(const void *self);
  tb_model_groups (*groups)(const void *self);
  /* 1: another library's solver (Bullet), a peer in the tables, not ours */
  int peer;
} tb_model_class;

/* The table of models (models/model.c). */
extern const tb_model_class *const tb_model_classes[];
extern const int tb_model_count;
const tb_model_class *tb_model_find(const char *name);

/* Steps compared each way when the thread count is automatic, and how
 * often the comparison is made again (tb_model_step). */
#define TB_MODEL_PROBES 3
#define TB_MODEL_REPROBE 1024

/* A model instance: its class, the data, the rest mesh's node count and
 * boundary triangles (the default surface). */
typedef struct tb_model {
  const tb_model_class *cls;
  void *self;
  int nv;
  int ntri;
  int *tri;
  /* the threads a step takes when the count is automatic (tb_model_step) */
  long steps;
  int serial;
  double probe[2][TB_MODEL_PROBES]; /* wall ms of probing steps: all threads, one */
} tb_model;

/* Creates model `name` (see tb_model_find) with settings set (NULL: the
 * model's defaults). An unknown key for that model, a bad value or one out
 * of range is an error naming the key and the model. */
int tb_model_create(tb_model *m, const char *name, const tb_mesh *mesh, const tb_settings *set,
                    tb_error *err);
/* The same checks without a mesh (e.g. for command-line input). */
int tb_model_check_settings(const char *name, const tb_settings *set, tb_error *err);
/* The effective value of key for model name: set's value, else the
 * default (CHOICE: the index). -1 when the model has no such key (or the
 * value does not parse, or it is a FILE setting), 0 otherwise. */
int tb_model_setting(const char *name, const tb_settings *set, const char *key, double *out);
/* 1 when model `name` has a setting `key` (of any type), else 0. */
int tb_model_has_setting(const char *name, const char *key);
/* 1 when some model's setting `key` is a FILE one (a scene resolves its
 * value as a path), else 0. */
int tb_model_file_setting(const char *key);
/* One line per key: key, type, default, range, doc. */
void tb_model_print_settings(FILE *f, const tb_model_class *c);

/* One step. When the thread count is automatic (tb_threads_auto) and more
 * than one, a model takes threads only where they make its steps faster:
 * after the first step, TB_MODEL_PROBES steps on all threads and as many
 * on one alternate, and the faster by median wall time is kept (again
 * every TB_MODEL_REPROBE steps). The answer is the same either way; an
 * explicit count (tb_threads_set) is used as given. */
int tb_model_step(tb_model *m, const tb_step *in, tb_error *err);
const tb_vec3 *tb_model_positions(const tb_model *m);
const tb_vec3 *tb_model_velocities(const tb_model *m);
double tb_model_energy(const tb_model *m);
const double *tb_model_masses(const tb_model *m);
int tb_model_npoints(const tb_model *m);
tb_surface tb_model_surface(const tb_model *m);
void tb_model_correct(tb_model *m, int n, const int *ids, const tb_vec3 *x, const tb_vec3 *v);
/* A cut event (see tb_cut_event); an error for a model that cannot be cut,
 * an event out of order, or a path with fewer than 2 points at MOVE. */
int tb_model_cut(tb_model *m, const tb_cut_event *ev, tb_cut_stats *stats, tb_error *err);
/* Per tet of the rest mesh: 0 once a cut removed it; NULL when all are
 * there (see tb_model_class.tets_alive). */
const unsigned char *tb_model_tets_alive(const tb_model *m);
/* 1 when the model's class can be cut. */
int tb_model_can_cut(const tb_model *m);
/* 1 when the model's step handles the scene's ground itself (own_ground). */
int tb_model_owns_ground(const tb_model *m);
void tb_model_destroy(tb_model *m);

/* ---- helpers the models share (models/model_util.c) ---- */
/* Every tet's nodes in range and its volume positive (also with node_mass,
 * which skips the volumes); the error names the first bad tet. */
int tb_check_tets(const tb_mesh *mesh, tb_error *err);
/* The closed surface a surface model simulates (surface_mesh): a tet
 * mesh's boundary triangles (tets checked), else the mesh's own triangles,
 * in range and forming a closed, oriented 2-manifold; *tri malloc'ed.
 * Returns the triangle count, or -1 with err naming the model. */
int tb_model_surface_triangles(const tb_mesh *mesh, const char *model, int **tri, tb_error *err);
/* Lumped node masses into mass[nv]: node_mass > 0 for every node, else
 * density * (sum of its tets' volumes) / 4; tets with non-positive volume
 * are an error naming the tet. */
int tb_lumped_masses(const tb_mesh *mesh, double density, double node_mass, double *mass,
                     tb_error *err);
/* A spatially coherent order of n points (recursive coordinate bisection:
 * halves at the median of the longest side of each half's box, down to
 * leaves of a few points), so every contiguous run of the order is compact
 * and its first half/second half split is a plane; order[r] is the point
 * at rank r. Deterministic (ties by index). Returns 0, or -1 out of memory. */
int tb_spatial_order(const tb_vec3 *x, int n, int *order);
/* Rotation R closest to A (polar decomposition A = R S, det R = +1, also for
 * singular or inverted A: the smallest singular direction is flipped). */
tb_mat3 tb_m3_polar(tb_mat3 a);
/* The same rotation by Higham's scaled Newton iteration (about 3x faster);
 * inverted, singular or non-finite A go to tb_m3_polar. */
tb_mat3 tb_m3_polar_newton(tb_mat3 a);
/* Eigen-decomposition of a symmetric matrix: a = V diag(w) V^T, w ascending,
 * V's columns the eigenvectors (Jacobi rotations). */
void tb_m3_sym_eigen(tb_mat3 a, double w[3], tb_mat3 *v);
/* Inverse; returns 0 when |det| <= tiny * (scale)^3. */
int tb_m3_inverse(tb_mat3 a, tb_mat3 *inv);

/* Coulomb friction of a ground contact (models/ground.c): n contact nodes
 * ids[k] whose positions p[k] the ground has put on its plane, depth[k] the
 * normal correction it made over the step, x0 the positions at the step's
 * start, mass per node. Static friction is decided for the contact as a
 * whole; p[k] loses its tangential displacement when it sticks, else that
 * displacement is shortened by mu_k depth[k]; keep[k] gets the share kept
 * (0 when stuck), for the tangential velocity. Returns 1 when it sticks. */
int tb_ground_friction(const tb_ground *g, int n, const int *ids, const double *depth,
                       const tb_vec3 *x0, const double *mass, tb_vec3 *p, double *keep);

/* Colours of the tets (models/tet_colour.c): tets of one colour share no
 * node. order[start[c] .. start[c+1]) are colour c's tets (malloc'ed, in mesh
 * order within a colour). */
int tb_tet_colours(const tb_mesh *mesh, int *ncolours, int **order, int **start, tb_error *err);

/* A schedule for parallel Gauss-Seidel sweeps (models/tet_slabs.c): the
 * nodes cut into nslabs slabs, numbered again slab by slab (internal node n
 * is mesh node old[n]; mesh node m is internal nw[m]), the tets (mesh ids)
 * in order[] by task, task q's tets order[task[q] .. task[q+1]), and phase
 * p's tasks phase[p] .. phase[p+1]: tasks of one phase share no node, and
 * the phases run one after another. At most max_slabs slabs; 1 (a single
 * task) for meshes too small to share. */
typedef struct tb_tet_slabs {
  int nslabs, ntasks;
  int *old, *nw, *order, *task;
  int phase[5];
  /* task q's conflicts conf[conf_start[q] .. conf_start[q+1]): the tasks of
   * other phases that share a node with it, ascending */
  int *conf_start, *conf;
} tb_tet_slabs;
int tb_tet_slabs_build(const tb_mesh *mesh, int max_slabs, tb_tet_slabs *s, tb_error *err);
/* The phase task q belongs to. */
int tb_tet_slabs_phase(const tb_tet_slabs *s, int q);
/* The slabs the position-based models' sweeps use at most: 64 keeps 32
 * tasks a phase for 32 threads. */
#define TB_SWEEP_SLABS 64
void tb_tet_slabs_free(tb_tet_slabs *s);

/* ---- blow-up detection (every suite and the CLI check each run) ---- */
typedef struct tb_health {
  int ok;
  char reason[96]; /* "NaN or inf", "inverted elements (n)", "velocity beyond bound" ... */
} tb_health;
/* Checks positions for NaN/inf, velocities against vmax (<= 0: no bound)
 * and, when inversion is non-zero, tets for inversion (signed volume <= 0
 * in x while positive at rest). */
tb_health tb_model_health(const tb_mesh *rest, const tb_vec3 *x, const tb_vec3 *v, double vmax,
                          int inversion);

#endif
