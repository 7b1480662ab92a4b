/* Gmsh .msh reader, ASCII: version 1 ($NOD, $ELM), 2.x ($MeshFormat,
 * $Nodes, $Elements) and 4.1 (entity blocks), after the Gmsh reference
 * manual's "MSH file format" section and its legacy-format appendix. Node
 * tags are arbitrary (possibly sparse) and mapped to 0-based indices through
 * a sorted table; tetrahedra (type 4) and triangles (type 2) are kept, other
 * elements are counted in nskipped; other sections are skipped. */
#include <limits.h>
#include <stdlib.h>
#include <string.h>

#include "io_internal.h"

typedef struct node_tag {
  long tag, line;
  int idx;
} node_tag;

typedef struct msh {
  tb_lex lx;
  tb_build *b;
  int version; /* 0 before any header, then 1, 2 or 4 */
  int have_nodes, have_elements;
  node_tag *tags;
  int ntags, captags;
} msh;

/* Nodes of element type t (Gmsh's numbering), 0 when unknown. */
static int type_nodes(long t) {
  static const signed char n[32] = {0, 2,  3,  4,  4, 8,  6,  5,  3,  6,  9, 10, 27, 18, 14, 1,
                                    8, 20, 15, 13, 9, 10, 12, 15, 15, 21, 4, 5,  6,  20, 35, 56};
  return t >= 1 && t < 32 ? n[t] : t == 92 ? 64 : t == 93 ? 125 : 0;
}

static int cmp_tag(const void *a, const void *b) {
  long x = ((const node_tag *)a)->tag, y = ((const node_tag *)b)->tag;
  return (x > y) - (x < y);
}

static int add_tag(msh *s, long tag, int idx) {
  node_tag *p = tb_io_grow(s->tags, &s->captags, (long)s->ntags + 1, sizeof *p);
  if (!p) return tb_lex_fail(&s->lx, "out of memory");
  s->tags = p;
  p[s->ntags++] = (node_tag){tag, s->lx.line, idx};
  return 0;
}

/* Reads "$End..." (or $ENDNOD, $ENDELM) closing a section. */
static int end_marker(msh *s, const char *end, const char *hint) {
  if (tb_lex_need(&s->lx, end)) return -1;
  const char *w = tb_lex_word(&s->lx);
  if (strcmp(w, end)) return tb_lex_fail(&s->lx, "expected %s, found '%.40s'%s", end, w, hint);
  return tb_lex_end(&s->lx);
}

/* Sorts the tag table once all nodes are in; duplicate tags are errors. */
static int finish_nodes(msh *s, const char *end) {
  if (end_marker(s, end, " (wrong node count?)")) return -1;
  qsort(s->tags, (size_t)s->ntags, sizeof *s->tags, cmp_tag);
  for (int i = 1; i < s->ntags; i++)
    if (s->tags[i].tag == s->tags[i - 1].tag) {
      s->lx.line = s->tags[i].line > s->tags[i - 1].line ? s->tags[i].line : s->tags[i - 1].line;
      return tb_lex_fail(&s->lx, "duplicate node tag %ld", s->tags[i].tag);
    }
  s->have_nodes = 1;
  return 0;
}

/* Reads the line holding item i of n (WHAT); a section end there is an error. */
static int data_line(msh *s, long i, long n, const char *what) {
  if (tb_lex_item(&s->lx, i, n, what)) return -1;
  if (s->lx.cur[strspn(s->lx.cur, " \t\r\v\f")] == '$')
    return tb_lex_fail(&s->lx, "section ends after %ld of %ld %ss (wrong count?)", i, n, what);
  return 0;
}

static int coords(msh *s, int nextra) {
  tb_vec3 x;
  double u;
  if (tb_lex_real(&s->lx, &x.x, "x coordinate") || tb_lex_real(&s->lx, &x.y, "y coordinate") ||
      tb_lex_real(&s->lx, &x.z, "z coordinate"))
    return -1;
  for (int k = 0; k < nextra; k++)
    if (tb_lex_real(&s->lx, &u, "parametric coordinate")) return -1;
  if (tb_lex_end(&s->lx)) return -1;
  return tb_lex_vert(&s->lx, s->b, x);
}

/* v1 and v2: "n", then n lines "tag x y z". */
static int nodes_v12(msh *s, const char *end) {
  long n, tag;
  if (tb_lex_need(&s->lx, "node count") || tb_lex_range(&s->lx, &n, 0, INT_MAX, "node count") ||
      tb_lex_end(&s->lx))
    return -1;
  for (long i = 0; i < n; i++)
    if (data_line(s, i, n, "node") || tb_lex_range(&s->lx, &tag, 1, LONG_MAX, "node tag") ||
        add_tag(s, tag, s->b->m.nv) || coords(s, 0))
      return -1;
  return finish_nodes(s, end);
}

/* v4.1: "blocks n min max", per block "dim entity parametric k", k tag
 * lines, then k coordinate lines (with dim parametric values). */
static int nodes_v4(msh *s) {
  long nblk, n, lo, hi, dim, ent, par, k, tag, total = 0, line;
  if (tb_lex_need(&s->lx, "node section header") ||
      tb_lex_range(&s->lx, &nblk, 0, INT_MAX, "block count") ||
      tb_lex_range(&s->lx, &n, 0, INT_MAX, "node count") || tb_lex_long(&s->lx, &lo, "min tag") ||
      tb_lex_long(&s->lx, &hi, "max tag") || tb_lex_end(&s->lx))
    return -1;
  line = s->lx.line;
  for (long blk = 0; blk < nblk; blk++) {
    if (data_line(s, blk, nblk, "node block") ||
        tb_lex_range(&s->lx, &dim, 0, 3, "entity dimension") ||
        tb_lex_long(&s->lx, &ent, "entity tag") ||
        tb_lex_range(&s->lx, &par, 0, 1, "parametric flag") ||
        tb_lex_range(&s->lx, &k, 0, INT_MAX - total, "block node count") || tb_lex_end(&s->lx))
      return -1;
    for (long i = 0; i < k; i++)
      if (data_line(s, i, k, "node tag") || tb_lex_range(&s->lx, &tag, 1, LONG_MAX, "node tag") ||
          tb_lex_end(&s->lx) || add_tag(s, tag, s->b->m.nv + (int)i))
        return -1;
    for (long i = 0; i < k; i++)
      if (data_line(s, i, k, "node coordinate") || coords(s, par ? (int)dim : 0)) return -1;
    total += k;
  }
  if (total != n) {
    s->lx.line = line;
    return tb_lex_fail(&s->lx, "header says %ld nodes, the blocks hold %ld", n, total);
  }
  return finish_nodes(s, "$EndNodes");
}

/* Reads nn node tags of an element of the given type from the current line;
 * keeps triangles and tets, counts the rest as skipped. */
static int element(msh *s, long type, long nn) {
  int v[4];
  long tag;
  if (type_nodes(type) && nn != type_nodes(type))
    return tb_lex_fail(&s->lx, "element type %ld has %d nodes, not %ld", type, type_nodes(type),
                       nn);
  for (long k = 0; k < nn; k++) {
    if (tb_lex_long(&s->lx, &tag, "node tag")) return -1;
    if (type != 2 && type != 4) continue;
    node_tag key = {tag, 0, 0}, *f = bsearch(&key, s->tags, (size_t)s->ntags, sizeof key, cmp_tag);
    if (!f) return tb_lex_fail(&s->lx, "element uses unknown node tag %ld", tag);
    v[k] = f->idx;
  }
  if (tb_lex_end(&s->lx)) return -1;
  if (type == 2 ? tb_build_tri(s->b, v[0], v[1], v[2]) : type == 4 ? tb_build_tet(s->b, v) : 0)
    return tb_lex_fail(&s->lx, "out of memory");
  if (type != 2 && type != 4) s->b->m.nskipped++;
  return 0;
}

/* v1 "id type phys elem nn nodes..." or v2 "id type ntags tags... nodes...". */
static int elements_v12(msh *s, const char *end) {
  long n, id, type, a, nt, t;
  if (tb_lex_need(&s->lx, "element count") ||
      tb_lex_range(&s->lx, &n, 0, INT_MAX, "element count") || tb_lex_end(&s->lx))
    return -1;
  for (long i = 0; i < n; i++) {
    if (data_line(s, i, n, "element") || tb_lex_long(&s->lx, &id, "element number") ||
        tb_lex_long(&s->lx, &type, "element type"))
      return -1;
    if (s->version == 1) {
      if (tb_lex_long(&s->lx, &a, "physical region") ||
          tb_lex_long(&s->lx, &a, "elementary region") ||
          tb_lex_range(&s->lx, &nt, 1, 1000, "node count") || element(s, type, nt))
        return -1;
      continue;
    }
    if (tb_lex_range(&s->lx, &nt, 0, 1000, "tag count")) return -1;
    for (long k = 0; k < nt; k++)
      if (tb_lex_long(&s->lx, &t, "element tag")) return -1;
    if (element(s, type, type_nodes(type) ? type_nodes(type) : tb_lex_left(&s->lx))) return -1;
  }
  return end_marker(s, end, " (wrong element count?)");
}

/* v4.1: "blocks n min max", per block "dim entity type k", k lines "tag nodes...". */
static int elements_v4(msh *s) {
  long nblk, n, lo, hi, dim, ent, type, k, tag, total = 0, line;
  if (tb_lex_need(&s->lx, "element section header") ||
      tb_lex_range(&s->lx, &nblk, 0, INT_MAX, "block count") ||
      tb_lex_range(&s->lx, &n, 0, INT_MAX, "element count") ||
      tb_lex_long(&s->lx, &lo, "min tag") || tb_lex_long(&s->lx, &hi, "max tag") ||
      tb_lex_end(&s->lx))
    return -1;
  line = s->lx.line;
  for (long blk = 0; blk < nblk; blk++) {
    if (data_line(s, blk, nblk, "element block") ||
        tb_lex_range(&s->lx, &dim, 0, 3, "entity dimension") ||
        tb_lex_long(&s->lx, &ent, "entity tag") || tb_lex_long(&s->lx, &type, "element type") ||
        tb_lex_range(&s->lx, &k, 0, INT_MAX - total, "block element count") || tb_lex_end(&s->lx))
      return -1;
    for (long i = 0; i < k; i++)
      if (data_line(s, i, k, "element") || tb_lex_long(&s->lx, &tag, "element tag") ||
          element(s, type, type_nodes(type) ? type_nodes(type) : tb_lex_left(&s->lx)))
        return -1;
    total += k;
  }
  if (total != n) {
    s->lx.line = line;
    return tb_lex_fail(&s->lx, "header says %ld elements, the blocks hold %ld", n, total);
  }
  return end_marker(s, "$EndElements", " (wrong element count?)");
}

static int mesh_format(msh *s) {
  double v;
  long type, size;
  if (tb_lex_need(&s->lx, "version line") || tb_lex_real(&s->lx, &v, "version") ||
      tb_lex_long(&s->lx, &type, "file type") || tb_lex_long(&s->lx, &size, "data size"))
    return -1;
  if (type != 0) return tb_lex_fail(&s->lx, "binary .msh not supported (file type %ld)", type);
  if (v >= 2 && v < 3)
    s->version = 2;
  else if (v >= 4.1 && v < 5)
    s->version = 4;
  else
    return tb_lex_fail(&s->lx, "unsupported .msh version %g (2.x and 4.1 read)", v);
  return tb_lex_end(&s->lx) || end_marker(s, "$EndMeshFormat", "") ? -1 : 0;
}

static int skip_section(msh *s, const char *name) {
  char end[80];
  snprintf(end, sizeof end, "$End%s", name + 1);
  for (;;) {
    if (tb_lex_need(&s->lx, end)) return -1;
    if (!strcmp(tb_lex_word(&s->lx), end)) return 0;
  }
}

static int section(msh *s, const char *w) {
  int v1 = !strcmp(w, "$NOD") || !strcmp(w, "$ELM");
  int nod = !strcmp(w, "$NOD") || !strcmp(w, "$Nodes");
  int elm = !strcmp(w, "$ELM") || !strcmp(w, "$Elements");
  if (w[0] != '$') return tb_lex_fail(&s->lx, "expected a $Section, found '%.40s'", w);
  if (!strcmp(w, "$MeshFormat"))
    return s->version == 1 ? tb_lex_fail(&s->lx,
                                         "$MeshFormat after legacy $NOD/$ELM sections: "
                                         "the legacy (version 1) and the new format mixed")
           : s->version    ? tb_lex_fail(&s->lx, "second $MeshFormat")
                           : mesh_format(s);
  if (!nod && !elm) return skip_section(s, w);
  if (tb_lex_end(&s->lx)) return -1;
  if (v1 && s->version == 0) s->version = 1;
  if (v1 && s->version != 1)
    return tb_lex_fail(&s->lx,
                       "legacy (version 1) section %s in a version %d file: the legacy and the "
                       "new format mixed",
                       w, s->version);
  if (s->version == 0)
    return tb_lex_fail(&s->lx, "%s without $MeshFormat before it (legacy files use $NOD/$ELM)", w);
  if (!v1 && s->version == 1)
    return tb_lex_fail(&s->lx,
                       "%s after legacy $NOD/$ELM sections: the legacy (version 1) and the new "
                       "format mixed",
                       w);
  if (nod && s->have_nodes) return tb_lex_fail(&s->lx, "second node section");
  if (elm && !s->have_nodes) return tb_lex_fail(&s->lx, "elements before nodes");
  if (elm && s->have_elements++) return tb_lex_fail(&s->lx, "second element section");
  if (s->version == 4) return nod ? nodes_v4(s) : elements_v4(s);
  if (nod) return nodes_v12(s, v1 ? "$ENDNOD" : "$EndNodes");
  return elements_v12(s, v1 ? "$ENDELM" : "$EndElements");
}

int tb_read_msh(const char *path, tb_build *b, tb_error *err) {
  msh s = {.b = b};
  int r = 0, rc = 0;
  if (tb_lex_open(&s.lx, path, 0, err)) return -1;
  while (rc == 0 && (r = tb_lex_line(&s.lx)) > 0) rc = section(&s, tb_lex_word(&s.lx));
  if (rc == 0 && r < 0) rc = -1;
  if (rc == 0) rc = tb_lex_done(&s.lx, b);
  free(s.tags);
  tb_lex_close(&s.lx);
  return rc;
}
