/* The layers (docs/architecture.md), checked on the source tree: the layer
 * table of meson.build read as the build reads it; every quoted include of
 * a library folder names its own folder's header bare or a lower folder's
 * header by folder, never a private header of another folder; no folder
 * holds more than a quarter of the non-test lines. The build itself refuses
 * an upward include (each layer's include path) and an upward call
 * (scripts/check-layers.sh); this adds what a compiler cannot see. */
#include <dirent.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "tb_test.h"

#define MAX_LAYERS 16
#define NAME 32

typedef struct layer {
  char name[NAME];
  int nbelow;
  char below[MAX_LAYERS][NAME];
  long lines;
} layer;

/* The quoted words of text[a, b) into w (at most max). */
static int words(const char *a, const char *b, char w[][NAME], int max) {
  int n = 0;
  for (const char *p = a; p < b && n < max; p++) {
    if (*p != '\'') continue;
    const char *q = memchr(p + 1, '\'', (size_t)(b - p - 1));
    if (!q) break;
    snprintf(w[n++], NAME, "%.*s", (int)(q - p - 1), p + 1);
    p = q;
  }
  return n;
}

/* meson.build's layer_below = { 'name': ['below', ...], ... }. */
static int read_layers(layer *l) {
  char path[1024];
  snprintf(path, sizeof path, "%s/meson.build", tb_test_source_root());
  char *text = tb_test_slurp(path);
  if (!text) return -1;
  char *p = strstr(text, "layer_below = {"), *end = p ? strstr(p, "\n}") : NULL;
  int n = 0;
  for (char *q = p ? p + 15 : NULL; q && q < end && n < MAX_LAYERS;) {
    char *colon = strstr(q, "': ["), *close = colon ? strchr(colon, ']') : NULL;
    if (!colon || colon > end || !close) break;
    char *open = colon;
    while (open > q && open[-1] != '\'') open--;
    snprintf(l[n].name, NAME, "%.*s", (int)(colon - open), open);
    l[n].nbelow = words(colon + 4, close, l[n].below, MAX_LAYERS);
    l[n].lines = 0;
    n++;
    q = close + 1;
  }
  free(text);
  return n;
}

static int is_source(const char *f) {
  size_t n = strlen(f);
  return (n > 2 && (!strcmp(f + n - 2, ".c") || !strcmp(f + n - 2, ".h"))) ||
         (n > 4 && !strcmp(f + n - 4, ".cpp"));
}

static int is_private(const char *header) {
  return strstr(header, "_priv.h") || strstr(header, "_internal.h");
}

static int exists(const char *root, const char *dir, const char *file) {
  char p[1024];
  struct stat st;
  snprintf(p, sizeof p, "%s/%s/%s", root, dir, file);
  return stat(p, &st) == 0;
}

/* Checks one file of layer l; returns its lines. */
static long check_file(const layer *all, int n, const layer *l, const char *file) {
  const char *root = tb_test_source_root();
  char path[1024];
  snprintf(path, sizeof path, "%s/%s/%s", root, l->name, file);
  char *text = tb_test_slurp(path);
  TB_CHECK_MSG(text != NULL, "cannot read %s", path);
  if (!text) return 0;
  long lines = 0;
  for (char *line = text; line && *line;) {
    char *next = strchr(line, '\n');
    if (next) *next++ = 0;
    lines++;
    char inc[256];
    if (sscanf(line, " #include \"%255[^\"]\"", inc) == 1) {
      char *slash = strchr(inc, '/');
      if (!slash) {
        TB_CHECK_MSG(exists(root, l->name, inc),
                     "%s/%s: \"%s\" is not a header of %s/ (another folder's header is "
                     "included by folder and name)",
                     l->name, file, inc, l->name);
      } else {
        *slash = 0;
        const char *dir = inc, *header = slash + 1;
        int allowed = 0, known = 0;
        for (int k = 0; k < l->nbelow; k++) allowed |= !strcmp(l->below[k], dir);
        for (int k = 0; k < n; k++) known |= !strcmp(all[k].name, dir);
        TB_CHECK_MSG(strcmp(dir, l->name), "%s/%s: its own folder's %s is included bare", l->name,
                     file, header);
        TB_CHECK_MSG(!known || allowed || !strcmp(dir, l->name),
                     "%s/%s includes %s/%s: %s/ is not below %s/", l->name, file, dir, header, dir,
                     l->name);
        TB_CHECK_MSG(!is_private(header), "%s/%s includes %s/%s, private to %s/", l->name, file,
                     dir, header, dir);
        TB_CHECK_MSG(exists(root, dir, header), "%s/%s includes %s/%s, which does not exist",
                     l->name, file, dir, header);
      }
    }
    line = next;
  }
  free(text);
  return lines;
}

static void includes_go_down(void) {
  layer l[MAX_LAYERS];
  int n = read_layers(l);
  TB_CHECK_MSG(n >= 8, "meson.build's layer_below: %d layers read", n);
  long total = 0;
  for (int i = 0; i < n; i++) {
    for (int k = 0; k < l[i].nbelow; k++) { /* below means listed earlier */
      int earlier = 0;
      for (int j = 0; j < i; j++) earlier |= !strcmp(l[j].name, l[i].below[k]);
      TB_CHECK_MSG(earlier, "layer %s uses %s, which is not a layer before it", l[i].name,
                   l[i].below[k]);
    }
    char dir[1024];
    snprintf(dir, sizeof dir, "%.900s/%.31s", tb_test_source_root(), l[i].name);
    DIR *d = opendir(dir);
    TB_CHECK_MSG(d != NULL, "no folder %s", dir);
    int files = 0;
    for (struct dirent *e; d && (e = readdir(d));)
      if (is_source(e->d_name)) l[i].lines += check_file(l, n, &l[i], e->d_name), files++;
    if (d) closedir(d);
    TB_CHECK_MSG(files > 0, "layer %s has no sources", l[i].name);
    total += l[i].lines;
  }
  /* the consumers outside the library count towards the whole */
  static const char *const outside[] = {"microbench"};
  for (size_t k = 0; k < sizeof outside / sizeof outside[0]; k++) {
    layer o = {{0}, 0, {{0}}, 0};
    snprintf(o.name, NAME, "%s", outside[k]);
    for (int i = 0; i < n; i++) snprintf(o.below[o.nbelow++], NAME, "%.31s", l[i].name);
    char dir[1024];
    snprintf(dir, sizeof dir, "%s/%s", tb_test_source_root(), o.name);
    DIR *d = opendir(dir);
    for (struct dirent *e; d && (e = readdir(d));)
      if (is_source(e->d_name)) total += check_file(l, n, &o, e->d_name);
    if (d) closedir(d);
  }
  for (int i = 0; i < n; i++) {
    printf("  %-10s %6ld lines, %4.1f%%\n", l[i].name, l[i].lines, 100.0 * l[i].lines / total);
    TB_CHECK_MSG(4 * l[i].lines <= total, "%s/ holds %ld of %ld non-test lines (over a quarter)",
                 l[i].name, l[i].lines, total);
  }
}

const tb_test_case tb_tests_layers[] = {
    {"includes_go_down", includes_go_down},
    {NULL, NULL},
};
