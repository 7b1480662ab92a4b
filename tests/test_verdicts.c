/* What makes a verdict trustworthy: the median's interval and the paired
 * ratio (report/estimate.c) against hand-computed order statistics, the
 * three-way verdict, the machine-load measurement (report/noise.c) with a
 * busy child process, the stopwatch's CPU clock, threads that never change
 * an answer (automatic, explicit, serial sections), and the end states a
 * run is given (stable, degraded, an input error). No timing is asserted. */
#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include "tb_test.h"
#include "core/tb_threads.h"
#include "core/tb_timer.h"
#include "report/tb_results.h"
#include "scenes/tb_sim.h"

/* ---- estimates ---- */

static void median_interval(void) {
  /* n = 10: P(Bin(10, 1/2) <= 1) = 0.0107, <= 2: 0.0547, so j = 2: [x(2), x(9)] */
  const double x[10] = {10, 9, 8, 7, 6, 5, 4, 3, 2, 1};
  tb_est e = tb_median_est(x, 10);
  TB_CHECK(e.n == 10 && e.value == 5.5 && e.lo == 2 && e.hi == 9);
  /* n = 6: P(X <= 0) = 0.0156: j = 1, the range */
  const double y[6] = {3, 1, 2, 6, 5, 4};
  e = tb_median_est(y, 6);
  TB_CHECK(e.value == 3.5 && e.lo == 1 && e.hi == 6);
  /* n = 20: P(X <= 5) = 0.0207, <= 6: 0.0577: j = 6, [x(6), x(15)] */
  double z[20];
  for (int i = 0; i < 20; i++) z[i] = i + 1;
  e = tb_median_est(z, 20);
  TB_CHECK(e.lo == 6 && e.hi == 15 && e.value == 10.5);
  /* non-finite samples are left out */
  const double w[4] = {1, NAN, INFINITY, 3};
  e = tb_median_est(w, 4);
  TB_CHECK(e.n == 2 && e.value == 2);
  e = tb_median_est(NULL, 0);
  TB_CHECK(e.n == 0 && isnan(e.value));
}

static void paired_ratio(void) {
  /* a machine that slows down through the run: the pairs keep the ratio */
  double a[8], b[8];
  for (int i = 0; i < 8; i++) b[i] = 1.0 + i, a[i] = 2 * b[i];
  tb_est r = tb_ratio_est(a, b, 8);
  TB_CHECK(r.n == 8 && r.value == 2 && r.lo == 2 && r.hi == 2);
  a[3] = -1; /* a pair with a non-positive side is left out */
  r = tb_ratio_est(a, b, 8);
  TB_CHECK(r.n == 7 && r.value == 2);
}

static void three_way_verdict(void) {
  char buf[200];
  tb_est e = {0.21, 0.205, 0.22, 9};
  TB_CHECK(tb_verdict(e, 0.2, 1) == TB_MET && !strcmp(tb_verdict_text(e, 0.2, 1, buf, 200), "met"));
  TB_CHECK(tb_verdict(e, 0.2, 0) == TB_NOT_MET);
  e = (tb_est){0.21, 0.18, 0.23, 9}; /* the interval holds the goal */
  TB_CHECK(tb_verdict(e, 0.2, 1) == TB_NOISE && tb_verdict(e, 0.2, 0) == TB_NOISE);
  tb_verdict_text(e, 0.2, 1, buf, sizeof buf);
  TB_CHECK_MSG(strstr(buf, "inconclusive (noise") && strstr(buf, "0.18-0.23"), "%s", buf);
  e = (tb_est){0.5, 0.5, 0.5, 1}; /* one repetition decides nothing */
  TB_CHECK(tb_verdict(e, 0.2, 1) == TB_NOISE);
  TB_CHECK(strstr(tb_verdict_text(e, 0.2, 1, buf, sizeof buf), "1 repetition"));
}

/* ---- the machine's load ---- */

static void noise_sees_a_busy_child(void) {
  tb_noise_mark a, b;
  tb_noise_mark_take(&a);
  pid_t child = fork();
  if (child == 0) { /* spins for 0.8 s of wall time */
    uint64_t end = tb_time_ns() + 800000000ull;
    volatile double s = 0;
    while (tb_time_ns() < end) s += 1;
    _exit(0);
  }
  TB_CHECK(child > 0);
  struct timespec ts = {0, 800000000L};
  nanosleep(&ts, NULL);
  tb_noise_mark_take(&b); /* before the wait: the child is another process */
  if (child > 0) waitpid(child, NULL, 0);
  tb_noise n = tb_noise_between(&a, &b, tb_threads_cores());
  TB_CHECK_MSG(n.known, "no /proc/stat");
  TB_CHECK_MSG(n.others > 0.4, "others %.2f cores while a child spun", n.others);
  TB_CHECK_MSG(n.busy, "a spinning process beside all-core work is busy (others %.2f)", n.others);
  char text[300];
  tb_noise_describe(&n, text, sizeof text);
  TB_CHECK_MSG(strstr(text, "BUSY") && strstr(text, "cores busy"), "%s", text);
}

static void clock_counts_cpu_not_sleep(void) {
  int was = tb_threads_setting();
  tb_threads_set(1);
  tb_clock c = tb_clock_start();
  struct timespec ts = {0, 200000000L};
  nanosleep(&ts, NULL);
  double wall, cpu;
  tb_clock_ms(&c, &wall, &cpu);
  TB_CHECK_MSG(wall >= 190 && cpu < 50, "sleeping 200 ms: wall %.1f ms, CPU %.1f ms", wall, cpu);
  TB_CHECK(!c.process);
  tb_threads_set(was);
}

/* ---- threads ---- */

static void thread_settings(void) {
  int was = tb_threads_setting();
  tb_threads_set(1);
  TB_CHECK(tb_threads() == 1 && !tb_threads_auto() && tb_threads_setting() == 1);
  tb_threads_set(0);
  TB_CHECK(tb_threads_auto() && tb_threads_setting() == 0);
  int n = tb_threads();
  int s = tb_threads_serial_begin();
  TB_CHECK(tb_threads() == 1); /* every region on the calling thread */
  tb_threads_serial_end(s);
  TB_CHECK(tb_threads() == n);
  tb_threads_set(was);
}

/* pbd-stvk on the stretched liver (the probing rounds included): automatic,
 * one thread, two threads give the same positions bit for bit. */
static void automatic_threads_same_answer(void) {
  int was = tb_threads_setting();
  tb_vec3 *x[3] = {NULL, NULL, NULL};
  int nv = 0;
  for (int k = 0; k < 3; k++) {
    tb_threads_set(k == 0 ? 0 : k);
    tb_sim_def sd;
    tb_sim_def_init(&sd);
    sd.nodes = 300;
    tb_sim s;
    tb_error err;
    if (tb_sim_create(&s, "liver-stretch", &sd, "pbd-stvk", NULL, NULL, &err)) {
      TB_CHECK_MSG(0, "%s", err.msg);
      break;
    }
    for (int q = 0; q < 2 * TB_MODEL_PROBES + 6; q++) TB_CHECK(tb_sim_step(&s, &err) == 0);
    nv = s.mesh.nv;
    x[k] = malloc(sizeof(tb_vec3) * (size_t)nv);
    if (x[k]) memcpy(x[k], tb_model_positions(&s.model), sizeof(tb_vec3) * (size_t)nv);
    tb_sim_destroy(&s);
  }
  TB_CHECK(x[0] && x[1] && x[2]);
  if (x[0] && x[1] && x[2])
    TB_CHECK(!memcmp(x[0], x[1], sizeof(tb_vec3) * (size_t)nv) &&
             !memcmp(x[0], x[2], sizeof(tb_vec3) * (size_t)nv));
  for (int k = 0; k < 3; k++) free(x[k]);
  tb_threads_set(was);
}

/* `--threads 1` is one thread everywhere: the process has no other thread
 * while it runs fem-corot's exact path (CHOLMOD's own regions included). */
static void one_thread_is_one_thread(void) {
  char cmd[1024];
  snprintf(cmd, sizeof cmd,
           "'%s' simulate --scene liver-stretch --model fem-corot --steps 1000 "
           "--threads 1 >/dev/null 2>&1 & pid=$!; sleep 1; "
           "n=$(ls /proc/$pid/task 2>/dev/null | wc -l); kill $pid 2>/dev/null; wait $pid; "
           "echo tasks=$n",
           tb_test_cli());
  char out[256];
  tb_test_run(cmd, out, sizeof out);
  TB_CHECK_MSG(strstr(out, "tasks=1\n"), "threads of a --threads 1 run: %s", out);
}

/* ---- end states ---- */

static void degraded_is_not_stable(void) {
  int rc = tb_test_cli_run("simulate --scene beam-crush --model msm --threads 1");
  TB_CHECK_MSG(rc == 3, "exit %d: %s", rc, tb_test_out);
  TB_CHECK_MSG(strstr(tb_test_out, "status: degraded (") && strstr(tb_test_out, "inverted tet") &&
                   !strstr(tb_test_out, "status: stable"),
               "%s", tb_test_out);
  rc = tb_test_cli_run("simulate --scene beam --model fem --threads 1");
  TB_CHECK_MSG(
      rc == 0 && strstr(tb_test_out, "status: stable") && strstr(tb_test_out, " ms CPU (wall "),
      "exit %d: %s", rc, tb_test_out);
  rc = tb_test_cli_run("simulate --help");
  TB_CHECK(rc == 0 && strstr(tb_test_out, "degraded") && strstr(tb_test_out, "exits 3"));
}

/* Input errors are found before the first step, with the file's line. */
static void input_errors_not_unstable(void) {
  const char *p = tb_test_file("inf-dt.ini",
                               "[scene]\ndt = inf\nduration = 1\n[mesh]\ngenerate = beam\n"
                               "[model]\nname = fem\n",
                               -1);
  char args[1200];
  snprintf(args, sizeof args, "simulate --scene '%s'", p);
  int rc = tb_test_cli_run(args);
  TB_CHECK_MSG(rc == 2 && strstr(tb_test_out, "inf-dt.ini:2:") && !strstr(tb_test_out, "unstable"),
               "exit %d: %s", rc, tb_test_out);
  rc = tb_test_cli_run("simulate --scene beam --model fem --set E=1e308");
  TB_CHECK_MSG(rc == 2 && strstr(tb_test_out, "E") && strstr(tb_test_out, "range"), "exit %d: %s",
               rc, tb_test_out);
  p = tb_test_file("parallel-cut.ini",
                   "[scene]\ndt = 0.01\nduration = 0.5\n[mesh]\ngenerate = steak\n"
                   "[model]\nname = metaball\n[cut]\npoint = 0,-5,2\npoint = 0,5,2\n"
                   "depth = 0,3,0\nstart = 0.1\nstop = 0.3\n",
                   -1);
  snprintf(args, sizeof args, "simulate --scene '%s'", p);
  rc = tb_test_cli_run(args);
  TB_CHECK_MSG(rc == 2 && strstr(tb_test_out, "parallel-cut.ini:") &&
                   strstr(tb_test_out, "parallel") && !strstr(tb_test_out, "unstable"),
               "exit %d: %s", rc, tb_test_out);
}

const tb_test_case tb_tests_verdicts[] = {
    {"median_interval", median_interval},
    {"paired_ratio", paired_ratio},
    {"three_way_verdict", three_way_verdict},
    {"noise_sees_a_busy_child", noise_sees_a_busy_child},
    {"clock_counts_cpu_not_sleep", clock_counts_cpu_not_sleep},
    {"thread_settings", thread_settings},
    {"automatic_threads_same_answer", automatic_threads_same_answer},
    {"one_thread_is_one_thread", one_thread_is_one_thread},
    {"degraded_is_not_stable", degraded_is_not_stable},
    {"input_errors_not_unstable", input_errors_not_unstable},
    {NULL, NULL},
};
