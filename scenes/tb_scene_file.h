/* A scene described in an INI file (parsed with libinih): the organ mesh,
 * the model and its settings, fixed nodes, loads, prescribed motions,
 * contact objects (a ground plane with Coulomb friction, a rigid instrument
 * moving along keyframes), the time step, duration and output. The file
 * format is documented in scenes/README.md; the built-in scenes are files in
 * scenes/ too.
 *
 * Numbers in every section may name a scene parameter of [scene] (dt,
 * duration, amplitude, release, nodes, gravity, ...), optionally scaled:
 * `amplitude`, `0.5*release`, `-amplitude`. They are evaluated when the
 * scene is built, after command-line overrides, so one file serves every
 * resolution and load a suite asks for. */
#ifndef TB_SCENE_FILE_H
#define TB_SCENE_FILE_H

#include "core/tb_error.h"
#include "core/tb_math.h"

/* A number: k * parameter (param < 0: the constant k). */
typedef struct tb_expr {
  double k;
  int param;
} tb_expr;

/* Node selectors; a selection is the union of its selectors (optionally
 * only surface nodes). Node ids are 0-based in the mesh file's node order. */
enum {
  TB_SEL_IDS,      /* ids = 3, 39, 64  or  id_file = file (whitespace/comma separated) */
  TB_SEL_BOX,      /* box = x0,y0,z0, x1,y1,z1 (inclusive) */
  TB_SEL_FRACTION, /* box_fraction = the same as fractions of the mesh's bounding box
                      (0 and 1 reach past the box's faces) */
  TB_SEL_PLANE,    /* plane = px,py,pz, nx,ny,nz: nodes with (x - p).n <= 0 */
  TB_SEL_SPHERE,   /* sphere = cx,cy,cz, r: nodes within distance r of c */
  TB_SEL_PATCH     /* patch = dx,dy,dz, f: surface nodes within f * (bounding-box
                      diagonal) of the surface node farthest along d */
};

typedef struct tb_selector {
  int kind, line;
  tb_expr v[6];
  int nids, *ids;
} tb_selector;

typedef struct tb_selection {
  int n;
  tb_selector *sel;
  int surface_only; /* surface = 1: only nodes on the surface triangles */
  int line;         /* the section's first line */
} tb_selection;

/* A keyframe: time, translation (or distance along `direction`), rotation
 * (axis and angle in degrees, about the motion's centre). */
typedef struct tb_keyframe {
  tb_expr t;
  tb_expr move[3]; /* translation, or move[0] = distance when a direction is given */
  tb_expr axis[3], angle;
  int line;
} tb_keyframe;

/* A rigid motion over time: piecewise linear between keyframes (rotation
 * angles linear about a shared axis, else quaternion slerp), held after the
 * last one. */
typedef struct tb_motion {
  int nkey;
  tb_keyframe *key;
  int has_direction;
  tb_expr direction[3]; /* keyframes give a distance along this (normalised) */
  tb_expr centre[3];    /* rotation centre (relative to the origin) */
} tb_motion;

typedef struct tb_scene_force {
  tb_selection where;
  tb_expr value[3];
  int per_node;        /* each = ...: every node gets value; total = ...: shared equally */
  int has_value;       /* one of them was given */
  tb_expr start, stop; /* acts while start <= t <= stop (stop < 0: forever) */
} tb_scene_force;

typedef struct tb_scene_move {
  tb_selection where;
  tb_motion motion;
  int has_release;
  tb_expr release; /* let go after this time (the `hold` of the driver overrides) */
} tb_scene_move;

typedef struct tb_scene_ground {
  tb_expr point[3], normal[3];
  tb_expr mu_s, mu_k, restitution;
  tb_expr settle;         /* seconds the body settles onto it before t = 0 (scenes/sim.c) */
  tb_expr axis[3], angle; /* `rotate`: the plane turned about the origin (as the mesh's) */
  int line;
} tb_scene_ground;

/* Where a mesh comes from: a file, or a generator with settings. */
typedef struct tb_mesh_source {
  char path[1024];   /* resolved file path, or "" */
  char prefer[1024]; /* `prefer`: this file when it could be read (else the generator), or "" */
  tb_expr prefer_axis[3], prefer_angle; /* `prefer_rotate`: turns the preferred file alone */
  char generator[32];                   /* liver, beam, sphere, instrument */
  int nset;
  char setkey[12][32];
  tb_expr setval[12];
  /* placed after loading: x' = R(axis, angle) (scale x) + translate */
  tb_expr scale, axis[3], angle, translate[3];
  int has_bottom; /* `bottom`: then translated so its bounding box's bottom centre is here */
  tb_expr bottom[3];
  int line;
} tb_mesh_source;

typedef struct tb_scene_tool {
  tb_mesh_source mesh;
  int origin_extreme; /* origin at the rest surface node farthest along origin[] */
  tb_expr origin[3];  /* a point, or the direction for origin_extreme */
  tb_expr offset[3];  /* added to the origin */
  tb_motion motion;   /* the tool's pose relative to origin + offset */
  tb_expr margin;     /* contact margin (distance kept from the tool's surface) */
  tb_expr friction;   /* Coulomb coefficient on the tool's surface (0: frictionless) */
  int close;          /* `close = 1`: an open mesh's holes are capped (meshgen's tb_mesh_close) */
  int line;
} tb_scene_tool;

/* Scene parameters: the [scene] section's numbers any value may name. */
enum {
  TB_P_DT,
  TB_P_DURATION,
  TB_P_AMPLITUDE,
  TB_P_RELEASE,
  TB_P_NODES,
  TB_P_GRAVITY,
  TB_P_VMAX,
  TB_P_INVERSION,
  TB_P_DRAG,
  TB_P_ENERGY_FACTOR,
  TB_P_ENERGY_EVERY,
  TB_P_REST_SPEED,
  TB_P_GROUND,
  TB_P_COUNT
};
extern const char *const tb_scene_param_names[TB_P_COUNT];

#define TB_SCENE_MAX_ITEMS 16
#define TB_SCENE_MAX_SETTINGS 24

/* A scalpel: its edge runs along the path at constant speed from `start`
 * (at the first point) to `stop` (at the last), the blade's depth fixed. */
#define TB_SCENE_MAX_CUTS 8 /* (scene_file.c names 8 in a message) */
typedef struct tb_scene_cut {
  int line, npoint;
  char name[32];                        /* the section's name after "cut" ("" for [cut]) */
  tb_expr point[TB_SCENE_MAX_ITEMS][3]; /* the blade edge's path, in order */
  tb_expr depth[3];                     /* the blade's depth vector */
  tb_expr start, stop;
} tb_scene_cut;

typedef struct tb_scene_desc {
  char path[1024]; /* the file ("" for a description built in code) */
  char name[64], summary[256];
  double param[TB_P_COUNT]; /* defaults from [scene] */
  int param_given[TB_P_COUNT];
  tb_vec3 gravity_dir; /* unit; gravity = param[TB_P_GRAVITY] * gravity_dir */
  unsigned long long seed;
  tb_mesh_source mesh;
  char model[32]; /* default model ("" : none, --model must say) */
  int nmodel_set;
  char model_set[TB_SCENE_MAX_SETTINGS][288]; /* "key=value": key < 32, value < 256 (tb_model.h) */
  int model_set_line[TB_SCENE_MAX_SETTINGS];
  int nfix;
  tb_selection fix[TB_SCENE_MAX_ITEMS];
  int nforce;
  tb_scene_force force[TB_SCENE_MAX_ITEMS];
  int nmove;
  tb_scene_move move[TB_SCENE_MAX_ITEMS];
  int has_ground;
  tb_scene_ground ground;
  int has_tool;
  tb_scene_tool tool;
  int ncut; /* [cut] and [cut NAME] sections: scalpels (models that can be cut) */
  tb_scene_cut cut[TB_SCENE_MAX_CUTS];
  double frame_interval; /* [output] every: seconds between frames (0: 1/30 s) */
  tb_selection probe;    /* [output] selectors: nodes whose displacement the summary reports */
} tb_scene_desc;

/* Reads a scene file. Errors: "FILE:LINE: reason" (unknown section or key,
 * bad value, a key given twice, a missing mesh file, ...). */
int tb_scene_desc_load(tb_scene_desc *d, const char *path, tb_error *err);
/* An empty description (defaults: dt 0.01, duration 1, gravity 0 along -z). */
void tb_scene_desc_init(tb_scene_desc *d);
void tb_scene_desc_free(tb_scene_desc *d);
/* Sets parameter `name` (a tb_scene_param_names entry); -1 when unknown. */
int tb_scene_param_index(const char *name);

/* Parses a selector value (as `--fix`/`--fix-box` give) into sel, e.g. kind
 * TB_SEL_IDS and "3,39,64"; path/line name the origin in errors. */
int tb_selector_parse(tb_selector *sel, int kind, const char *value, const char *path, int line,
                      const char *base_dir, tb_error *err);

/* A mesh or id file named in a scene: relative to dir (the scene file's
 * folder; "" for the working directory), or `data:REST` for
 * ../shared/data/REST (or $TB_DATA_DIR/REST). Fails with *why set when no
 * file is named, or it cannot be read or is a folder. */
int tb_scene_resolve_path(const char *dir, const char *value, char *out, size_t cap,
                          const char **why);

/* Evaluates an expression with the given parameter values. */
static inline double tb_expr_eval(tb_expr e, const double *param) {
  return e.param < 0 ? e.k : e.k * param[e.param];
}

/* The vector of three expressions. */
static inline tb_vec3 tb_expr_vec(const tb_expr e[3], const double *param) {
  return tb_v3(tb_expr_eval(e[0], param), tb_expr_eval(e[1], param), tb_expr_eval(e[2], param));
}

/* The rotation of a `rotate`-like key (axis, angle in degrees). Returns 1
 * with R, 0 for angle 0 (R the identity), -1 for a zero axis. */
static inline int tb_expr_rotation(const tb_expr axis[3], tb_expr angle, const double *param,
                                   tb_mat3 *R) {
  double a = tb_expr_eval(angle, param);
  tb_vec3 k = tb_expr_vec(axis, param);
  *R = tb_m3_identity();
  if (a == 0) return 0;
  if (!(tb_len(k) > 0)) return -1;
  *R = tb_m3_rotation(k, a * (M_PI / 180.0));
  return 1;
}

#endif
