/* `tissuebench tritri`: classifies triangle pairs with one method of the
 * table (collision/tb_tritri.h): one 0/1 per input pair on stdout, in
 * order; with --repeat K, the median CPU and wall time per pair on stderr
 * (timed on one thread). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "tb_cli.h"
#include "collision/tb_pairs.h"
#include "collision/tb_tritri.h"
#include "core/tb_threads.h"
#include "measure/tb_tritri_run.h"
#include "report/tb_results.h"

int tb_cmd_tritri(int argc, char **argv) {
  const char *method = NULL, *input = NULL;
  long repeat = 0;
  for (int i = 1; i < argc; i++) {
    if (!strcmp(argv[i], "--method") && i + 1 < argc)
      method = argv[++i];
    else if (!strcmp(argv[i], "--input") && i + 1 < argc)
      input = argv[++i];
    else if (!strcmp(argv[i], "--repeat") && i + 1 < argc) {
      char *end;
      repeat = strtol(argv[++i], &end, 10);
      if (*end || repeat < 1 || repeat > 1000000) {
        fprintf(stderr, "tissuebench tritri: --repeat needs a whole number in [1, 1e6]\n");
        return TB_EXIT_INPUT;
      }
    } else
      return tb_cli_bad_option("tritri", argv[i]);
  }
  int nm;
  const tb_tritri_method *all = tb_tritri_methods(&nm);
  if (method && !strcmp(method, "list")) {
    for (int i = 0; i < nm; i++) printf("%-13s %s\n", all[i].name, all[i].source);
    return TB_EXIT_OK;
  }
  const tb_tritri_method *m = method ? tb_tritri_find(method) : NULL;
  if (!m) {
    fprintf(stderr, "tissuebench tritri: %s (--method list)\n",
            method ? "unknown method" : "--method NAME is required");
    return TB_EXIT_INPUT;
  }
  tb_pairset set;
  tb_error err;
  int rc =
      input ? tb_pairs_read_file(input, &set, &err) : tb_pairs_read(stdin, "<stdin>", &set, &err);
  if (rc) {
    fprintf(stderr, "%s\n", err.msg);
    return TB_EXIT_INPUT;
  }
  unsigned char *out = malloc((size_t)set.n + 1);
  size_t nrep = (size_t)(repeat > 0 ? repeat : 1);
  double *samples = malloc(sizeof(double) * 2 * nrep), *wall = samples ? samples + nrep : NULL;
  if (!out || !samples) {
    fprintf(stderr, "tissuebench tritri: out of memory\n");
    tb_pairs_free(&set), free(out), free(samples);
    return TB_EXIT_FAIL;
  }
  int bad = tb_tritri_classify(m, &set, out);
  for (int i = 0; i < set.n; i++)
    fputs(out[i] == 1 ? "1\n" : (out[i] == 0 ? "0\n" : "?\n"), stdout);
  if (repeat > 0 && set.n > 0) {
    /* one thread: the CPU clock is this thread's (tb_clock) */
    int was = tb_threads_setting();
    tb_threads_set(1);
    double med = tb_tritri_time(m, &set, (int)repeat, samples, wall);
    tb_threads_set(was);
    fprintf(stderr,
            "%s: CPU time median %.2f ns/pair over %ld repetitions of %d pairs (wall median "
            "%.2f ns/pair, one thread)\n",
            m->name, med, repeat, set.n, tb_stats_of(wall, (int)repeat).median);
  }
  if (bad) fprintf(stderr, "tissuebench tritri: %s gave %d invalid answers\n", m->name, bad);
  tb_pairs_free(&set), free(out), free(samples);
  return bad ? TB_EXIT_FAIL : TB_EXIT_OK;
}
