/* How busy the machine was over a stretch of a run (report/tb_results.h):
 * the CPU time all processes took (/proc/stat: user, nice, system, irq,
 * softirq over every CPU), less this process's and its children's
 * (getrusage), is the time other processes took; over the wall time it is
 * the cores they kept busy. Also the hypervisor's steal, this process's
 * involuntary context switches, the load average and the frequency
 * governor. */
#include <math.h>
#include <stdio.h>
#include <string.h>
#include <sys/resource.h>
#include <unistd.h>

#include "tb_results.h"
#include "core/tb_threads.h"
#include "core/tb_timer.h"

static double tv(struct timeval t) { return (double)t.tv_sec + 1e-6 * (double)t.tv_usec; }

void tb_noise_mark_take(tb_noise_mark *m) {
  memset(m, 0, sizeof *m);
  m->wall_ns = tb_time_ns();
  struct rusage self, kids;
  getrusage(RUSAGE_SELF, &self);
  getrusage(RUSAGE_CHILDREN, &kids);
  m->self_s = tv(self.ru_utime) + tv(self.ru_stime) + tv(kids.ru_utime) + tv(kids.ru_stime);
  m->nivcsw = self.ru_nivcsw;
  FILE *f = fopen("/proc/stat", "r");
  unsigned long long v[8] = {0};
  if (f && fscanf(f, "cpu %llu %llu %llu %llu %llu %llu %llu %llu", &v[0], &v[1], &v[2], &v[3],
                  &v[4], &v[5], &v[6], &v[7]) == 8) {
    double hz = (double)sysconf(_SC_CLK_TCK);
    m->busy_s = (double)(v[0] + v[1] + v[2] + v[5] + v[6]) / hz; /* user nice system irq softirq */
    m->all_s = (double)(v[0] + v[1] + v[2] + v[3] + v[4] + v[5] + v[6] + v[7]) / hz;
    m->steal_s = (double)v[7] / hz;
    m->ok = 1;
  }
  if (f) fclose(f);
  f = fopen("/proc/loadavg", "r");
  if (!f || fscanf(f, "%lf", &m->load1) != 1) m->load1 = NAN;
  if (f) fclose(f);
}

tb_noise tb_noise_between(const tb_noise_mark *a, const tb_noise_mark *b, int threads) {
  tb_noise n;
  memset(&n, 0, sizeof n);
  n.cores = tb_threads_cores();
  n.seconds = (double)(b->wall_ns - a->wall_ns) * 1e-9;
  n.load1 = b->load1;
  n.known = a->ok && b->ok && n.seconds > 0;
  if (n.known) {
    double all = b->all_s - a->all_s;
    n.others = fmax(0, (b->busy_s - a->busy_s) - (b->self_s - a->self_s)) / n.seconds;
    n.steal = all > 0 ? (b->steal_s - a->steal_s) / all : 0;
  }
  n.switches = n.seconds > 0 ? (double)(b->nivcsw - a->nivcsw) / n.seconds : 0;
  char gov[64] = "";
  FILE *f = fopen("/sys/devices/system/cpu/cpu0/cpufreq/scaling_governor", "r");
  if (f && fgets(gov, sizeof gov, f)) n.scaling = strncmp(gov, "performance", 11) != 0;
  if (f) fclose(f);
  /* busy: the other processes left fewer cores than the threads asked for
   * (half a core of slack), or the hypervisor took over 5% */
  n.busy = n.known && (n.others + (threads > 0 ? threads : 1) > n.cores + 0.5 || n.steal > 0.05);
  return n;
}

void tb_noise_describe(const tb_noise *n, char *buf, size_t cap) {
  if (!n->known) {
    snprintf(buf, cap, "machine load unknown (no /proc/stat)");
    return;
  }
  snprintf(buf, cap,
           "%s: other processes kept %.2f of %d cores busy, steal %.1f%%, %.0f involuntary "
           "context switches a second, load average %.2f%s",
           n->busy ? "the machine was BUSY" : "the machine was quiet", n->others, n->cores,
           100 * n->steal, n->switches, n->load1, n->scaling ? ", CPU frequency scaling on" : "");
}
