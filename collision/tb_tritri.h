/* Triangle-triangle intersection tests, one function per method, served
 * through one table. Semantics for every method: triangles are closed sets;
 * touching at a point or along an edge counts as intersecting; a zero-area
 * triangle is the segment or point it spans. A published method that is
 * inexact on degenerate input is implemented faithfully (its wrong answers
 * show in the correctness table), never patched with another method. */
#ifndef TB_TRITRI_H
#define TB_TRITRI_H

#include "core/tb_math.h"

/* 1 when the closed triangles p and q intersect, else 0. */
typedef int (*tb_tritri_fn)(const tb_vec3 p[3], const tb_vec3 q[3]);

typedef struct tb_tritri_method {
  const char *name;
  const char *source; /* paper or library it follows */
  tb_tritri_fn test;
  int exact; /* claims the right answer on every input (checked against cgal) */
} tb_tritri_method;

/* The table: our methods, then those registered (the reference libraries'
 * fcl, bullet and cgal: reference/tb_oracles.h), in the order registered. */
const tb_tritri_method *tb_tritri_methods(int *count);
const tb_tritri_method *tb_tritri_find(const char *name);
/* Adds m (copied; its strings and function must outlive the table) after
 * the methods there. Returns 0 (also when the same name and test are there
 * already), -1 when its name names another test or the table is full. */
int tb_tritri_register(const tb_tritri_method *m);

/* ---- our methods (collision/tritri_*.c) ---- */
int tb_tritri_moller(const tb_vec3 p[3], const tb_vec3 q[3]); /* Moller 1997 */
int tb_tritri_yuhe(const tb_vec3 p[3],
                   const tb_vec3 q[3]); /* Yu & He 2013, as the thesis describes it */
int tb_tritri_improved(const tb_vec3 p[3],
                       const tb_vec3 q[3]); /* the thesis's improved test, §4.4.2 */
int tb_tritri_guigue(const tb_vec3 p[3],
                     const tb_vec3 q[3]); /* Devillers-Guigue 2002, double predicates */
int tb_tritri_guigue_exact(const tb_vec3 p[3],
                           const tb_vec3 q[3]);              /* the same with exact predicates */
int tb_tritri_exact(const tb_vec3 p[3], const tb_vec3 q[3]); /* ours: exact, filtered, fastest */
/* Batched exact test for BVH leaves: out[i] = tb_tritri_exact(p + 3i, q + 3i). */
void tb_tritri_exact_batch(const tb_vec3 *p, const tb_vec3 *q, int n, unsigned char *out);

#endif
