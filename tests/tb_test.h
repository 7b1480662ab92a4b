/* A small test runner: each test file exports a table of cases; a case
 * passes when none of its checks fails. The runner prints one line per
 * failure, visible SKIP lines, and ends with "N passed, N failed, N skipped". */
#ifndef TB_TEST_H
#define TB_TEST_H

typedef struct tb_test_case {
  const char *name;
  void (*fn)(void);
} tb_test_case;

/* Records a failed check (and keeps going). */
void tb_test_fail(const char *file, int line, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));
/* Marks the running case skipped, with a reason printed as "SKIP: ...". */
void tb_test_skip(const char *fmt, ...) __attribute__((format(printf, 1, 2)));

#define TB_CHECK(cond)                                          \
  do {                                                          \
    if (!(cond)) tb_test_fail(__FILE__, __LINE__, "%s", #cond); \
  } while (0)
#define TB_CHECK_MSG(cond, ...)                                 \
  do {                                                          \
    if (!(cond)) tb_test_fail(__FILE__, __LINE__, __VA_ARGS__); \
  } while (0)
/* |a - b| <= tol */
#define TB_CHECK_NEAR(a, b, tol)                                                              \
  do {                                                                                        \
    double tb_a_ = (a), tb_b_ = (b);                                                          \
    if (!(fabs(tb_a_ - tb_b_) <= (tol)))                                                      \
      tb_test_fail(__FILE__, __LINE__, "%s = %.17g, %s = %.17g, tolerance %g", #a, tb_a_, #b, \
                   tb_b_, (double)(tol));                                                     \
  } while (0)

/* A fresh file in the run's temporary folder holding `content` (len bytes;
 * len < 0 means strlen). Returns its path (static storage per call slot). */
const char *tb_test_file(const char *name, const char *content, long len);
/* The run's temporary folder, and the built CLI binary and source root. */
const char *tb_test_tmpdir(void);
const char *tb_test_cli(void);
const char *tb_test_source_root(void);
/* Runs a shell command; returns its exit status (or -1) and copies up to
 * cap-1 bytes of its combined stdout+stderr into out (may be NULL). */
int tb_test_run(const char *cmd, char *out, int cap);

/* The whole file as a string (NULL when unreadable); the caller frees. */
char *tb_test_slurp(const char *path);
/* Reads path (tb_mesh_read) expecting failure with the message
 * "path:LINE: ...REASON..." (line 0: "path: ...") and an empty mesh. */
void tb_test_expect_read_error(const char *path, long line, const char *reason);
/* The same, the message naming file `in` (a partner file, or path itself);
 * line -1: any line or none. */
void tb_test_expect_read_error_in(const char *path, const char *in, long line, const char *reason);
/* A file that must not read: its name, content, the line blamed and the reason. */
typedef struct tb_test_bad_file {
  const char *name, *text;
  long line;
  const char *reason;
} tb_test_bad_file;
/* tb_test_expect_read_error on each, written with tb_test_file, up to a NULL name. */
void tb_test_expect_read_errors(const tb_test_bad_file *c);
/* name inside tb_test_tmpdir() (one of 4 rotating buffers). */
const char *tb_test_tmp_path(const char *name);
/* Field k (0-based) of a CSV line (quoted fields may hold commas) into out;
 * 0 when the line has fewer fields. */
int tb_test_csv_field(const char *line, int k, char *out, size_t cap);
/* Field k of the row of csv whose first field is name, as text ("" when
 * absent; valid until the next call). */
const char *tb_test_csv_cell(const char *csv, const char *name, int k);
/* The same as a number (NAN when absent or empty). */
double tb_test_csv_num(const char *csv, const char *name, int k);

/* Runs `tissuebench ARGS` (a shell fragment after the binary); returns its
 * exit code, its combined output in tb_test_out (64 KiB). */
extern char tb_test_out[1 << 16];
int tb_test_cli_run(const char *args);

/* The tables, one per test file. */
extern const tb_test_case tb_tests_core[];
extern const tb_test_case tb_tests_io[];
extern const tb_test_case tb_tests_io_hostile[];
extern const tb_test_case tb_tests_vtu[];
extern const tb_test_case tb_tests_mc[];
extern const tb_test_case tb_tests_results[];
extern const tb_test_case tb_tests_meshgen[];
extern const tb_test_case tb_tests_cli[];
extern const tb_test_case tb_tests_tetmesh[];
extern const tb_test_case tb_tests_tritri_fast[];
extern const tb_test_case tb_tests_tritri_exact[];
extern const tb_test_case tb_tests_refs[];
extern const tb_test_case tb_tests_tritri[];
extern const tb_test_case tb_tests_bvh[];
extern const tb_test_case tb_tests_refbvh[];
extern const tb_test_case tb_tests_collide[];
extern const tb_test_case tb_tests_models[];
extern const tb_test_case tb_tests_msm[];
extern const tb_test_case tb_tests_msm_vvs[];
extern const tb_test_case tb_tests_fem[];
extern const tb_test_case tb_tests_fem_corot[];
extern const tb_test_case tb_tests_sm[];
extern const tb_test_case tb_tests_pbd[];
extern const tb_test_case tb_tests_reference[];
extern const tb_test_case tb_tests_fidelity[];
extern const tb_test_case tb_tests_stability[];
extern const tb_test_case tb_tests_scenes[];
extern const tb_test_case tb_tests_render[];
extern const tb_test_case tb_tests_pbd_stiffness[];
extern const tb_test_case tb_tests_lod[];
extern const tb_test_case tb_tests_vvs_refine[];
extern const tb_test_case tb_tests_metaball[];
extern const tb_test_case tb_tests_metaball_cut[];
extern const tb_test_case tb_tests_carve[];
extern const tb_test_case tb_tests_softbody[];
extern const tb_test_case tb_tests_bullet_models[];
extern const tb_test_case tb_tests_butterfly[];
extern const tb_test_case tb_tests_sph[];
extern const tb_test_case tb_tests_meshless[];
extern const tb_test_case tb_tests_fold[];
extern const tb_test_case tb_tests_fold_tri[];
extern const tb_test_case tb_tests_organs[];
extern const tb_test_case tb_tests_metaball_model[];
extern const tb_test_case tb_tests_organ_cut[];
extern const tb_test_case tb_tests_cut_surface[];
extern const tb_test_case tb_tests_metaball_suite[];
extern const tb_test_case tb_tests_shard[];
extern const tb_test_case tb_tests_scaling[];
extern const tb_test_case tb_tests_fuzz_regressions[];
extern const tb_test_case tb_tests_layers[];
extern const tb_test_case tb_tests_verdicts[];
extern const tb_test_case tb_tests_cuts[];

#endif
