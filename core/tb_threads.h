/* Worker threads for the parallel loops (OpenMP, Debian's libgomp). The
 * count never changes an answer: every parallel loop works on fixed,
 * disjoint partitions (e.g. tets of one colour, which share no node) and
 * reduces in a fixed order. */
#ifndef TB_THREADS_H
#define TB_THREADS_H

/* Sets the count for every later parallel loop; n <= 0: one per core.
 * Returns the count in effect. */
int tb_threads_set(int n);
/* The count in effect (1 without OpenMP). */
int tb_threads(void);
/* Cores online. */
int tb_threads_cores(void);

#endif
