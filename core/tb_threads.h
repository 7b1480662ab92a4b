/* Worker threads for the parallel loops (OpenMP, Debian's libgomp). The
 * count never changes an answer: every parallel loop works on fixed,
 * disjoint partitions (e.g. tets of one colour, which share no node) and
 * reduces in a fixed order. */
#ifndef TB_THREADS_H
#define TB_THREADS_H

/* Starts the program again, once, with the thread pools of the libraries
 * (OpenMP, OpenBLAS) set up for n threads (n <= 0: one per core) through
 * the environment they read when they load (core/threads.c says what and
 * why); call it first in main with main's argv. Settings the user put in
 * the environment are kept. Returns only when the environment holds (or
 * the program cannot be run again). */
void tb_threads_environment(int n, char **argv);
/* Sets the count for every later parallel loop (at most the limit
 * tb_threads_environment set); n <= 0: automatic, one per core where a
 * model's steps gain from them (models/tb_model.h, tb_model_step). Returns
 * the count in effect. */
int tb_threads_set(int n);
/* 1 while the count is automatic (the start, or tb_threads_set(0)). */
int tb_threads_auto(void);
/* What tb_threads_set takes to restore the present setting: 0 when
 * automatic, else the count. */
int tb_threads_setting(void);
/* Runs what follows on the calling thread alone, every parallel region
 * (the libraries' too) until tb_threads_serial_end(the value returned):
 * for work too small to gain from threads. */
int tb_threads_serial_begin(void);
void tb_threads_serial_end(int was);
/* The count in effect (1 without OpenMP). */
int tb_threads(void);
/* Inside a parallel region: the calling thread's number (0 .. team - 1) and
 * the team's size; outside one: 0 and 1. */
int tb_thread_id(void);
int tb_threads_team(void);
/* Cores online. */
int tb_threads_cores(void);

#endif
