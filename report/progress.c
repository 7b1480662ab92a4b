/* A one-line progress bar on stderr, redrawn in place with '\r' when stderr
 * is a terminal; into a log or a pipe the same line is written whole, once a
 * minute at most, so a long run is never silent and a log stays short: label, bar,
 * percent, done/total, time elapsed and an estimate of the time left, and
 * a long item's latest heartbeat note. The bookkeeping (tb_progress_update)
 * and the line (tb_progress_format) are pure functions of the time given,
 * tested directly; tb_progress and tb_progress_tick feed them the clock.
 * The line is ended when done reaches total; "\033[K" clears what a longer
 * line left. */
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "tb_results.h"
#include "core/tb_timer.h"

#define BAR_WIDTH 24
#define REDRAW_S 0.25 /* at most four redraws a second between items */
#define LOG_S 60.0    /* not a terminal: a line a minute at most ($TB_PROGRESS_LOG_S overrides) */

int tb_progress_update(tb_progress_run *r, const char *label, long done, long total, double now) {
  if (!label) label = "";
  if (done < 0) done = 0;
  int same = r->active && strncmp(label, r->label, sizeof r->label - 1) == 0;
  if (!r->active && r->total > 0 && r->done == r->total && done >= total &&
      strncmp(label, r->label, sizeof r->label - 1) == 0)
    return 0;                                                 /* the end again: already drawn */
  if (same && r->total > 0 && total > 0 && total != r->total) /* keep the run's total */
    done = (long)((double)done / (double)total * (double)r->total + 0.5);
  if (same && r->total <= 0 && total > 0) same = 0; /* the total became known: a new run */
  if (!same || done < r->done) {                    /* a new run */
    memset(r, 0, sizeof *r);
    snprintf(r->label, sizeof r->label, "%s", label);
    r->total = total > 0 ? total : 0;
    r->start = now;
    r->last_draw = -1;
    r->active = 1;
  }
  if (r->total > 0 && done > r->total) done = r->total;
  double t = now - r->start;
  int grew = done > r->done;
  long permille_old = r->total > 0 ? r->done * 1000 / r->total : r->done;
  if (grew) {
    r->done = done;
    r->t_done = t;
    r->note[0] = 0; /* a note belongs to the item it was made in */
  }
  long permille = r->total > 0 ? r->done * 1000 / r->total : r->done;
  int finished = r->total > 0 && r->done == r->total;
  if (finished) r->active = 0;
  return r->last_draw < 0 || finished || permille != permille_old || t - r->last_draw >= REDRAW_S;
}

double tb_progress_eta(const tb_progress_run *r, double now) {
  if (r->total <= 0 || r->done <= 0) return -1;
  /* seconds an item: as the finished ones took, or more when the current
   * one has already taken longer (items differ: msm is fast, fem slow) */
  double elapsed = now - r->start, per = r->t_done / (double)r->done;
  double with_current = elapsed / (double)(r->done + 1);
  if (with_current > per) per = with_current;
  long left = r->total - r->done;
  if (left <= 0) return 0;
  double current = per - (elapsed - r->t_done); /* the current item's remainder */
  return (current > 0 ? current : 0) + per * (double)(left - 1);
}

/* m:ss, or h:mm:ss from an hour on. */
static void clock_text(char *buf, size_t cap, double s) {
  long t = s > 0 ? (long)(s + 0.5) : 0;
  if (t >= 3600)
    snprintf(buf, cap, "%ld:%02ld:%02ld", t / 3600, t / 60 % 60, t % 60);
  else
    snprintf(buf, cap, "%ld:%02ld", t / 60, t % 60);
}

const char *tb_progress_format(char *buf, size_t cap, const tb_progress_run *r, double now) {
  if (!buf || cap == 0) return buf;
  char el[24], left[24];
  clock_text(el, sizeof el, now - r->start);
  size_t n;
  if (r->total > 0) {
    char bar[BAR_WIDTH + 1];
    long permille = r->done * 1000 / r->total;
    int filled = (int)(permille * BAR_WIDTH / 1000);
    for (int i = 0; i < BAR_WIDTH; i++) bar[i] = i < filled ? '#' : '.';
    bar[BAR_WIDTH] = 0;
    double eta = tb_progress_eta(r, now);
    if (eta < 0)
      snprintf(left, sizeof left, "?");
    else
      clock_text(left, sizeof left, eta);
    n = (size_t)snprintf(buf, cap, "%s [%s] %3ld%% (%ld/%ld) %s elapsed, %s%s left", r->label, bar,
                         permille / 10, r->done, r->total, el,
                         r->done == r->total || eta < 0 ? "" : "~", left);
  } else {
    n = (size_t)snprintf(buf, cap, "%s: %ld done, %s elapsed", r->label, r->done, el);
  }
  if (r->note[0] && n < cap) snprintf(buf + n, cap - n, " | %s", r->note);
  return buf;
}

static tb_progress_run run; /* the bar on stderr */
static int run_tty;         /* stderr is a terminal (checked when a run begins) */
static double last_log;     /* not a terminal: when the last line was written (s since start) */
static double log_every = LOG_S;

static double now_s(void) { return (double)tb_time_ns() * 1e-9; }

/* Not a terminal: the line once LOG_S has passed since the last one (or the run's start). */
static void log_line(double now) {
  if (now - run.start - last_log < log_every) return;
  char line[320];
  tb_progress_format(line, sizeof line, &run, now);
  fprintf(stderr, "%s\n", line);
  fflush(stderr);
  last_log = now - run.start;
}

static void draw(double now, int end) {
  char line[320];
  tb_progress_format(line, sizeof line, &run, now);
  fprintf(stderr, "\r%s\033[K%s", line, end ? "\n" : "");
  fflush(stderr);
  run.last_draw = now - run.start;
}

void tb_progress(const char *label, long done, long total) {
  int was_active = run.active;
  char was_label[sizeof run.label];
  memcpy(was_label, run.label, sizeof was_label);
  double now = now_s();
  int redraw = tb_progress_update(&run, label, done, total, now);
  if (run.last_draw < 0) { /* a new run */
    if (was_active && run_tty && strcmp(was_label, run.label)) fputc('\n', stderr);
    run_tty = isatty(STDERR_FILENO);
    last_log = 0;
    const char *e = getenv("TB_PROGRESS_LOG_S");
    log_every = e && *e ? atof(e) : LOG_S;
  }
  if (redraw && run_tty) draw(now, !run.active);
  if (!run_tty) {
    if (run.last_draw < 0) run.last_draw = 0;
    log_line(now);
  }
}

void tb_progress_done(void) {
  if (!run.active) return;
  run.active = 0;
  if (run_tty) draw(now_s(), 1);
}

void tb_progress_tick(const char *fmt, ...) {
  if (!run.active) return;
  double now = now_s();
  if (!run_tty && now - run.start - last_log < log_every) return;
  if (run_tty && now - run.start - run.last_draw < REDRAW_S) return;
  if (fmt) { /* formatted only when drawn */
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(run.note, sizeof run.note, fmt, ap);
    va_end(ap);
  }
  if (run_tty)
    draw(now, 0);
  else
    log_line(now);
}
