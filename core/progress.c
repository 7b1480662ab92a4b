/* A one-line progress bar on stderr, redrawn in place with '\r', shown only
 * when stderr is a terminal so logs and pipes stay clean. The line is ended
 * when done reaches total; "\033[K" clears what a longer line left. */
#include <stdio.h>
#include <string.h>
#include <unistd.h>

#include "tb_results.h"

#define BAR_WIDTH 30

void tb_progress(const char *label, long done, long total) {
  /* The last drawn state, to skip redraws that would change nothing. */
  static char last_label[64];
  static int last_permille = -1;
  if (total <= 0 || !isatty(STDERR_FILENO)) return;
  if (done < 0) done = 0;
  if (done > total) done = total;
  if (!label) label = "";
  int permille = (int)((double)done / (double)total * 1000.0);
  int finished = done == total;
  if (permille == last_permille && !finished &&
      strncmp(label, last_label, sizeof last_label - 1) == 0)
    return;
  last_permille = finished ? -1 : permille;
  snprintf(last_label, sizeof last_label, "%s", finished ? "" : label);

  char bar[BAR_WIDTH + 1];
  int filled = permille * BAR_WIDTH / 1000;
  for (int i = 0; i < BAR_WIDTH; i++) bar[i] = i < filled ? '#' : '.';
  bar[BAR_WIDTH] = 0;
  fprintf(stderr, "\r%s [%s] %3d%% (%ld/%ld)\033[K%s", label, bar, permille / 10, done, total,
          finished ? "\n" : "");
  fflush(stderr);
}
