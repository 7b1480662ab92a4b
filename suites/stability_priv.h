/* What the two parts of `figure stability` share: the models and their
 * stiffness axes, how a run's end is classified, a growing text buffer.
 * Part 1 (maps) is suites/suite_stability.c, part 2 (large deformations)
 * suites/suite_deform.c, part 3 (msm-vvs over ks x kd) suites/suite_stability_vvs.c. */
#ifndef TB_STABILITY_PRIV_H
#define TB_STABILITY_PRIV_H

#include <stddef.h>
#include <stdint.h>

#include "tb_suites.h"
#include "report/tb_results.h"

typedef struct tb_stab_model {
  const char *name, *key, *label; /* model, its settings key, axis label */
  double lo, hi;
  int logy;
  double ref;      /* stiffness at which the tip load is the beam's default (0: load fixed) */
  int integer;     /* the key is a whole number (iterations): the axis is rounded */
  const char *tag; /* the map's file names, map_<tag>; NULL: the model's name. A model with
                      two maps (two keys) has one entry each; part 2 runs it once. */
  const char *kvs; /* further settings of the map ("force=linear"), or NULL */
  int peer;        /* 1: a Bullet peer: a smaller grid in quick mode, not in part 2 */
} tb_stab_model;
extern const tb_stab_model tb_stab_models[];
extern const int tb_stab_nmodels;

#define TB_STAB_NODE_MASS 1.0 /* unit node masses, as the thesis's mass-spring demo */

/* Why a run stopped (the map's colours). */
enum { ST_STABLE, ST_NAN, ST_ENERGY, ST_INVERTED, ST_VELOCITY, ST_FAILED, ST_COUNT };
/* The code of a detector's reason ("NaN ...", "energy ...", ...). */
int tb_stab_classify(const char *reason);
extern const char *const tb_stab_status_names[ST_COUNT]; /* "stable", "NaN or inf", ... */

typedef struct tb_stab_cell {
  int code;
  double t;         /* simulated time reached */
  char reason[200]; /* the detector's or the model's words */
} tb_stab_cell;

/* Steps a created sim to its duration (or the first failure) into c. */
struct tb_sim;
void tb_stab_run(struct tb_sim *s, tb_stab_cell *c);
/* Largest eigenvalue of M^-1/2 A M^-1/2 on the free nodes (power iteration),
 * A the rest stiffness of the springs (springs = 1) or the Kelvin damping
 * (springs = 0; kd (v_j - v_i) per edge), both per unit coefficient; the
 * edges are pairs of the sim's rest mesh nodes. */
double tb_stab_largest_eigen(const struct tb_sim *s, const int *edges, int ne, int springs,
                             uint64_t seed);

/* A growing text buffer; bad is set when out of memory. */
typedef struct tb_stab_text {
  char *s;
  size_t len, cap;
  int bad;
} tb_stab_text;
void tb_stab_text_add(tb_stab_text *b, const char *fmt, ...) __attribute__((format(printf, 2, 3)));

/* The entry's file tag (tag, or the model's name). */
const char *tb_stab_tag(const tb_stab_model *m);
/* Whether part 2 runs entry m: the first entry of its model, and the model
 * is `only` (NULL: every model). */
int tb_stab_deform_runs(const tb_stab_model *m, const char *only);

/* Part 3: msm-vvs over ks x kd on the pressed sphere (suites/suite_stability_vvs.c). */
int tb_stab_vvs(tb_suite *su, const tb_suite_opts *o, tb_error *err);
#define TB_STAB_VVS "msm-vvs" /* part 3's model, for --model */

/* Part 2: every model (or only the model named `only`) x stretch, twist, crush. */
int tb_stab_deform(tb_suite *su, const tb_suite_opts *o, const char *only, tb_error *err);

#endif
