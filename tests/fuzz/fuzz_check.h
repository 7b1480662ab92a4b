/* The readers' contract that the libFuzzer harnesses (tests/fuzz/) and the
 * regression test (tests/test_fuzz_regressions.c) check, on error
 * the result is empty and the message starts with the file's name ("FILE: "
 * or "FILE:LINE: "); on success every coordinate is finite and every index
 * is in range. Each check returns 0 when it holds, else -1 with `why` saying
 * what broke. */
#ifndef TB_FUZZ_CHECK_H
#define TB_FUZZ_CHECK_H

#include <stddef.h>
#include <stdint.h>

#include "collision/tb_pairs.h"
#include "core/tb_error.h"
#include "core/tb_mesh.h"
#include "core/tb_spheres.h"
#include "measure/tb_points.h"

/* The message of a failed read of `path` (for a TetGen .node, the .ele or
 * .face read beside it may be the file named instead). */
int tb_fuzz_check_error(const char *path, const tb_error *err, char *why, size_t cap);
/* A mesh reader's result (rc its return value). */
int tb_fuzz_check_mesh(const char *path, int rc, const tb_mesh *m, const tb_error *err, char *why,
                       size_t cap);
int tb_fuzz_check_spheres(const char *path, int rc, const tb_spheres *s, const tb_error *err,
                          char *why, size_t cap);
int tb_fuzz_check_pairs(const char *path, int rc, const tb_pairset *p, const tb_error *err,
                        char *why, size_t cap);
int tb_fuzz_check_points(const char *path, int rc, const tb_point *p, int n, const tb_error *err,
                         char *why, size_t cap);

/* One harness: a reader fed with one input. */
typedef struct tb_fuzz_target {
  const char *name; /* the harness is fuzz_<name> */
  const char *ext;  /* the extension its input file gets */
  const char *what; /* for --list and the README */
  /* Reads the input the harness wrote to `path`; 0 when the contract held. */
  int (*run)(const char *path, char *why, size_t cap);
} tb_fuzz_target;

/* The table of harnesses, *n entries. */
const tb_fuzz_target *tb_fuzz_targets(int *n);
/* NULL when there is no such harness. */
const tb_fuzz_target *tb_fuzz_target_find(const char *name);
/* Writes the input into a file of the process's own temporary folder (the
 * TetGen harness splits it into .node, .ele and .face at the lines "#@ele"
 * and "#@face") and runs the target on it. 0 when the contract held, -1
 * with why when it broke, -2 when the file could not be written. */
int tb_fuzz_run(const tb_fuzz_target *t, const uint8_t *data, size_t size, char *why, size_t cap);
/* 1 when the reader of the last tb_fuzz_run accepted its input. */
int tb_fuzz_accepted(void);

#endif
