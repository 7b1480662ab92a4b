/* Colouring of a tet mesh for parallel Gauss-Seidel: tets of one colour
 * share no node, so projecting them in parallel writes disjoint nodes and
 * gives the same result as projecting them one after another, for any
 * number of threads. Greedy first fit in the mesh's tet order (Jones &
 * Plassmann's sequential baseline), colours kept as bit sets per node. */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "tb_model.h"

enum { WORDS = 4, MAX_COLOURS = 64 * WORDS };

int tb_tet_colours(const tb_mesh *mesh, int *ncolours, int **order, int **start, tb_error *err) {
  int nt = mesh->ntet;
  uint64_t *used = calloc((size_t)mesh->nv * WORDS, sizeof *used);
  int *colour = malloc(sizeof(int) * (size_t)(nt ? nt : 1));
  int *count = calloc(MAX_COLOURS + 1, sizeof(int));
  *order = malloc(sizeof(int) * (size_t)(nt ? nt : 1));
  *start = NULL;
  if (!used || !colour || !count || !*order) {
    free(used), free(colour), free(count), free(*order), *order = NULL;
    return tb_error_set(err, "colouring", 0, "out of memory (%d tets)", nt);
  }
  int nc = 0;
  for (int t = 0; t < nt; t++) {
    const int *e = mesh->tet + 4 * t;
    uint64_t busy[WORDS] = {0};
    for (int k = 0; k < 4; k++)
      for (int w = 0; w < WORDS; w++) busy[w] |= used[(size_t)e[k] * WORDS + w];
    int c = 0;
    while (c < MAX_COLOURS && (busy[c / 64] >> (c % 64) & 1u)) c++;
    if (c == MAX_COLOURS) {
      free(used), free(colour), free(count), free(*order), *order = NULL;
      return tb_error_set(err, "colouring", 0, "tet %d needs more than %d colours", t, MAX_COLOURS);
    }
    for (int k = 0; k < 4; k++) used[(size_t)e[k] * WORDS + c / 64] |= (uint64_t)1 << (c % 64);
    colour[t] = c, count[c + 1]++;
    if (c + 1 > nc) nc = c + 1;
  }
  *start = malloc(sizeof(int) * (size_t)(nc + 1));
  if (!*start) {
    free(used), free(colour), free(count), free(*order), *order = NULL;
    return tb_error_set(err, "colouring", 0, "out of memory");
  }
  for (int c = 0; c < nc; c++) count[c + 1] += count[c];
  memcpy(*start, count, sizeof(int) * (size_t)(nc + 1));
  for (int t = 0; t < nt; t++) (*order)[count[colour[t]]++] = t;
  *ncolours = nc;
  free(used), free(colour), free(count);
  return 0;
}
