/* The mesh generators as a table: each has named numeric settings with
 * defaults, a run function, and the documents' counts to print beside ours. */
#ifndef TB_GENERATORS_H
#define TB_GENERATORS_H

#include <stdint.h>
#include <stdio.h>

#include "core/tb_error.h"
#include "core/tb_mesh.h"

#define TB_GEN_MAX_PARAMS 8

typedef struct tb_gen_param {
  const char *key;
  double value; /* default */
  int integer;  /* must be a whole number */
  const char *doc;
  const char *const *names; /* NULL, or names of the values 0, 1, ... (NULL-terminated) */
} tb_gen_param;

/* Counts of a generated mesh (0 where not applicable). */
typedef struct tb_gen_counts {
  int surface_verts, surface_tris;
  int verts, tets, faces, edges;
} tb_gen_counts;

typedef struct tb_gen_result {
  tb_mesh surface; /* closed triangle surface (empty for beams) */
  tb_mesh volume;  /* tet mesh with its boundary triangles (empty for surfaces) */
  double ms;       /* generation time */
} tb_gen_result;

typedef struct tb_generator {
  const char *name, *summary;
  tb_gen_param params[TB_GEN_MAX_PARAMS];
  int (*run)(const double *p, tb_gen_result *r, tb_error *err);
  /* the documents' counts for these settings; returns 0 when they have none */
  int (*paper)(const double *p, tb_gen_counts *c, const char **source);
  /* the surface alone, for --part surface (NULL: run); fills r->surface */
  int (*surface)(const double *p, tb_gen_result *r, tb_error *err);
} tb_generator;

typedef enum tb_mesh_part {
  TB_PART_DEFAULT, /* tets when there are any, else the surface */
  TB_PART_TETS,
  TB_PART_SURFACE,
  TB_PART_FACES, /* every face of the tets: the thesis's collision model */
  TB_PART_EDGES
} tb_mesh_part;

const tb_generator *tb_generator_find(const char *name);
void tb_generator_list(FILE *f);
void tb_generator_defaults(const tb_generator *g, double *p);
/* "key=value" (for a named setting, "key=name" or the value's number);
 * prints the error and returns -1 on a bad key or value. */
int tb_generator_set(const tb_generator *g, double *p, const char *kv);
int tb_generator_run(const tb_generator *g, const double *p, tb_gen_result *r, tb_error *err);
/* The surface only where the generator has a surface-only path (the liver:
 * no TetGen, and its vertex count made exact, tb_liver_surface_exact),
 * else tb_generator_run. */
int tb_generator_run_surface(const tb_generator *g, const double *p, tb_gen_result *r,
                             tb_error *err);
void tb_gen_result_free(tb_gen_result *r);
tb_gen_counts tb_gen_result_counts(const tb_gen_result *r);
/* Prints our counts beside the documents' (and closed/manifold checks). */
void tb_gen_result_print(FILE *f, const tb_generator *g, const double *p, const tb_gen_result *r);
/* A new mesh holding the chosen part (not for TB_PART_EDGES). */
int tb_gen_result_part(const tb_gen_result *r, tb_mesh_part part, tb_mesh *out, tb_error *err);
int tb_mesh_part_parse(const char *s, tb_mesh_part *part);

#endif
