/* Sets of triangle pairs: the `tritri` line format (18 numbers per line:
 * p0 p1 p2 q0 q1 q2, anything strtod accepts, '#' comments, blank lines
 * skipped; an optional "# expect=0|1 label" comment carries the expected
 * answer), and the JGT Shen-2003 files (six lines of "x y z" per pair). */
#ifndef TB_PAIRS_H
#define TB_PAIRS_H

#include <stdio.h>

#include "core/tb_error.h"
#include "core/tb_math.h"

typedef struct tb_tripair {
  tb_vec3 p[3], q[3];
} tb_tripair;

typedef struct tb_pairset {
  int n, cap;
  tb_tripair *pairs;
  signed char *expect; /* per pair: 0, 1, or -1 when the line had no expect= */
  char **labels;       /* per pair: the text after expect=E (or NULL) */
} tb_pairset;

/* Reads the line format from f (named `name` in errors). Malformed lines
 * are "name:LINE: reason". */
int tb_pairs_read(FILE *f, const char *name, tb_pairset *set, tb_error *err);
int tb_pairs_read_file(const char *path, tb_pairset *set, tb_error *err);
/* The JGT format; each pair gets expect = `label` (1 for intersected.txt,
 * 0 for separated.txt). */
int tb_pairs_read_jgt(const char *path, int label, tb_pairset *set, tb_error *err);
/* Both files of the JGT folder: intersected.txt (expect 1) into *in and
 * separated.txt (expect 0) into *sep. Returns 0; 1 when the folder has no
 * intersected.txt (data absent); -1 on a read error. On non-zero both are
 * left empty and err says why. */
int tb_pairs_read_jgt_dir(const char *dir, tb_pairset *in, tb_pairset *sep, tb_error *err);
/* Appends one pair (expect -1 for unknown); -1 when out of memory. */
int tb_pairs_add(tb_pairset *set, const tb_tripair *pair, int expect);
void tb_pairs_free(tb_pairset *set);
/* Writes a pair as one line of the format, exactly ("%a" hex floats). */
void tb_pairs_write_line(FILE *f, const tb_tripair *pair);

#endif
