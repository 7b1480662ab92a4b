/* `tissuebench mesh info FILE`, `tissuebench mesh subdivide IN --levels N --out OUT` and
 * `tissuebench mesh NAME`: inspect a mesh file (or a .sph sphere file), refine a closed surface
 * with the modified butterfly scheme (Bao 2006 §3.1, core/tb_butterfly.h), or generate one of the
 * project's meshes (meshgen/tb_meshgen.h). Each generator is one table entry with named numeric
 * settings. */
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "tb_cli.h"
#include "collision/tb_bvh.h"
#include "core/tb_butterfly.h"
#include "core/tb_mesh_io.h"
#include "meshgen/tb_generators.h"
#include "meshgen/tb_meshgen.h"

/* ---- mesh info ---- */
static void print_info(FILE *f, const char *name, const tb_mesh *m) {
  tb_mesh surf = *m;
  int *bnd = NULL;
  if (m->ntet && !m->ntri) { /* judge a tet mesh by its boundary */
    surf.ntri = tb_mesh_tet_boundary(m, &bnd);
    surf.tri = bnd;
  }
  tb_mesh_topo t = tb_mesh_topology(&surf);
  tb_vec3 lo, hi;
  tb_mesh_bbox(m, &lo, &hi);
  fprintf(f, "mesh        %s\n", name);
  fprintf(f, "vertices    %d\n", m->nv);
  fprintf(f, "triangles   %d%s\n", m->ntri,
          bnd ? " (none in the file; boundary of the tets below)" : "");
  fprintf(f, "tets        %d\n", m->ntet);
  if (m->ntet) {
    int *e = NULL, *fa = NULL;
    fprintf(f, "tet edges   %d\n", tb_mesh_edges(m, &e));
    fprintf(f, "tet faces   %d\n", tb_mesh_tet_faces(m, &fa));
    fprintf(f, "min tet vol %.6g\n", tb_mesh_min_tet_volume(m));
    free(e), free(fa);
  }
  if (m->nskipped) fprintf(f, "skipped     %d elements of other types\n", m->nskipped);
  fprintf(f, "bbox        [%.6g %.6g %.6g] - [%.6g %.6g %.6g]\n", lo.x, lo.y, lo.z, hi.x, hi.y,
          hi.z);
  fprintf(f, "surface     %d triangles, %d edges, %d components, Euler %d\n", surf.ntri, t.nedges,
          t.components, t.euler);
  fprintf(f, "closed      %s (%d boundary edges)\n", t.closed ? "yes" : "no", t.boundary_edges);
  fprintf(f, "manifold    %s (%d non-manifold edges, %d non-manifold vertices, %d degenerate)\n",
          t.manifold ? "yes" : "no", t.nonmanifold_edges, t.nonmanifold_verts, t.degenerate_tris);
  fprintf(f, "oriented    %s (%d edges traversed twice the same way)\n",
          t.misoriented_edges ? "no" : "yes", t.misoriented_edges);
  fprintf(f, "volume      %.9g%s\n", tb_mesh_volume(m),
          m->ntet ? " (sum of tet volumes)" : (t.closed ? "" : " (surface not closed)"));
  tb_pairlist self = {0, 0, NULL};
  tb_error err;
  if (surf.ntri > 0 && tb_collide_self(surf.x, surf.tri, surf.ntri, &self, &err) == 0) {
    fprintf(f, "self-intersecting %d triangle pair%s", self.n, self.n == 1 ? "" : "s");
    for (int k = 0; k < self.n && k < 5; k++)
      fprintf(f, "%s%d-%d", k ? ", " : " (0-based: ", self.ij[2 * k], self.ij[2 * k + 1]);
    fprintf(f, "%s\n", self.n > 5 ? ", ...)" : self.n ? ")" : "");
  } else if (surf.ntri > 0)
    fprintf(f, "self-intersecting unknown (%s)\n", err.msg);
  tb_pairlist_free(&self);
  free(bnd);
}

static int mesh_info(int argc, char **argv) {
  if (argc != 2) {
    fprintf(stderr, "usage: tissuebench mesh info FILE\n");
    return TB_EXIT_INPUT;
  }
  size_t len = strlen(argv[1]);
  if (len > 4 && !strcmp(argv[1] + len - 4, ".sph")) return tb_spheres_info(argv[1], NULL, 64);
  tb_mesh m;
  tb_error err;
  if (tb_mesh_read(argv[1], &m, &err)) {
    fprintf(stderr, "%s\n", err.msg);
    return TB_EXIT_INPUT;
  }
  print_info(stdout, argv[1], &m);
  tb_mesh_free(&m);
  return TB_EXIT_OK;
}

/* ---- mesh subdivide ---- */
/* N levels of the modified butterfly scheme. A tet mesh is refused: the tet mesh's boundary
 * would leave the interior vertices unused, and the refined surface would no longer match
 * the tets. Level 0 is checked with the file's name, so bad surfaces print "FILE: reason". */
static int mesh_subdivide(int argc, char **argv) {
  const char *in = NULL, *out = NULL, *levels = NULL;
  for (int i = 1; i < argc; i++) {
    if (!strcmp(argv[i], "--levels") && i + 1 < argc)
      levels = argv[++i];
    else if (!strcmp(argv[i], "--out") && i + 1 < argc)
      out = argv[++i];
    else if (argv[i][0] != '-' && !in)
      in = argv[i];
    else {
      return tb_cli_bad_option("mesh subdivide", argv[i]);
    }
  }
  if (!in || !out || !levels) {
    fprintf(stderr, "usage: tissuebench mesh subdivide IN --levels N --out OUT\n");
    return TB_EXIT_INPUT;
  }
  if (!tb_mesh_writable(out)) {
    fprintf(stderr, "tissuebench mesh subdivide: %s: unknown extension (" TB_MESH_WRITES ")\n",
            out);
    return TB_EXIT_INPUT;
  }
  char *end;
  long n = strtol(levels, &end, 10);
  if (end == levels || *end || n < 1 || n > 6) {
    fprintf(stderr, "tissuebench mesh subdivide: --levels '%s': give a whole number in [1, 6]\n",
            levels);
    return TB_EXIT_INPUT;
  }
  tb_mesh m;
  tb_error err;
  if (tb_mesh_read(in, &m, &err)) {
    fprintf(stderr, "%s\n", err.msg);
    return TB_EXIT_INPUT;
  }
  tb_halfedge he;
  int bad = 0;
  if (m.ntet)
    bad = tb_error_set(&err, in, 0,
                       "a tet mesh (%d tets): subdivide a closed triangle surface (e.g. the "
                       "liver's --part surface)",
                       m.ntet);
  else if (!tb_halfedge_build(&he, m.nv, m.ntri, m.tri, in, &err)) {
    for (int v = 0; v < m.nv && !bad; v++)
      if (tb_halfedge_valence(&he, v) < 3)
        bad = tb_error_set(&err, in, 0,
                           "vertex %d has valence 2 (two triangles on the same three vertices)", v);
    tb_halfedge_free(&he);
  } else
    bad = 1;
  if (!bad && (double)m.ntri * (1 << (2 * n)) * 3 > INT_MAX)
    bad = tb_error_set(&err, in, 0, "%d triangles: %ld levels would give too many", m.ntri, n);
  if (bad) {
    fprintf(stderr, "%s\n", err.msg);
    tb_mesh_free(&m);
    return TB_EXIT_INPUT;
  }
  printf("level  vertices  triangles\n");
  printf("%5d  %8d  %9d\n", 0, m.nv, m.ntri);
  for (int l = 1; l <= n; l++) {
    tb_mesh next;
    if (tb_butterfly(&m, &next, NULL, &err)) {
      fprintf(stderr, "tissuebench mesh subdivide: level %d: %s\n", l, err.msg);
      tb_mesh_free(&m);
      return TB_EXIT_FAIL;
    }
    tb_mesh_free(&m);
    m = next;
    printf("%5d  %8d  %9d\n", l, m.nv, m.ntri);
  }
  int rc = TB_EXIT_OK;
  if (tb_mesh_write(out, &m, &err)) {
    fprintf(stderr, "tissuebench mesh subdivide: %s\n", err.msg);
    rc = TB_EXIT_FAIL;
  } else
    printf("wrote %s\n", out);
  tb_mesh_free(&m);
  return rc;
}

/* ---- generation ---- */
static int write_edges(const char *path, const tb_mesh *m, tb_error *err) {
  int *e = NULL, n = tb_mesh_edges(m, &e);
  FILE *f = fopen(path, "w");
  if (n < 0 || !f) {
    free(e);
    if (f) fclose(f);
    return tb_error_set(err, path, 0, "cannot write");
  }
  fprintf(f, "# %d edges, 0-based vertex indices\n", n);
  for (int i = 0; i < n; i++) fprintf(f, "%d %d\n", e[2 * i], e[2 * i + 1]);
  free(e);
  int bad = ferror(f);
  if (fclose(f) || bad) return tb_error_set(err, path, 0, "write failed");
  return 0;
}

/* `--KEY VALUE` for a setting KEY of g (dashes for underscores: --surface-verts 8128 is --set
 * surface_verts=8128). Returns 1 when applied, 0 when a is no setting of g, -1 on a bad value. */
static int setting_option(const tb_generator *g, const char *a, const char *v, double *p) {
  char kv[256];
  size_t len = strlen(a);
  if (strncmp(a, "--", 2) || len < 3 || len + strlen(v) >= sizeof kv) return 0;
  for (size_t i = 2; i <= len; i++) kv[i - 2] = a[i] == '-' ? '_' : a[i];
  for (int k = 0; k < TB_GEN_MAX_PARAMS && g->params[k].key; k++)
    if (!strcmp(g->params[k].key, kv)) {
      strcat(kv, "=");
      strcat(kv, v);
      return tb_generator_set(g, p, kv) ? -1 : 1;
    }
  return 0;
}

static int mesh_generate(int argc, char **argv) {
  const char *name = argv[0], *out = NULL, *part = NULL;
  int stats = 0;
  const tb_generator *g = tb_generator_find(name);
  if (!g) {
    fprintf(stderr, "tissuebench: unknown mesh '%s' (tissuebench mesh list)\n", name);
    return TB_EXIT_INPUT;
  }
  double p[TB_GEN_MAX_PARAMS];
  tb_generator_defaults(g, p);
  for (int i = 1; i < argc; i++) {
    const char *a = argv[i];
    if (!strcmp(a, "--stats"))
      stats = 1;
    else if (!strcmp(a, "--out") && i + 1 < argc)
      out = argv[++i];
    else if (!strcmp(a, "--part") && i + 1 < argc)
      part = argv[++i];
    else if (!strcmp(a, "--set") && i + 1 < argc) {
      if (tb_generator_set(g, p, argv[++i])) return TB_EXIT_INPUT;
    } else {
      int set = i + 1 < argc ? setting_option(g, a, argv[i + 1], p) : 0;
      if (set < 0) return TB_EXIT_INPUT;
      if (set == 0) {
        char cmd[96];
        snprintf(cmd, sizeof cmd, "mesh %s", name);
        return tb_cli_bad_option(cmd, a);
      }
      i++;
    }
  }
  tb_mesh_part which = TB_PART_DEFAULT;
  if (part && tb_mesh_part_parse(part, &which)) {
    fprintf(stderr, "tissuebench mesh: unknown part '%s' (tets, surface, faces, edges)\n", part);
    return TB_EXIT_INPUT;
  }
  if (!out && !stats) {
    fprintf(stderr, "tissuebench mesh %s: give --out FILE and/or --stats\n", name);
    return TB_EXIT_INPUT;
  }
  if (out && which != TB_PART_EDGES && !tb_mesh_writable(out)) {
    fprintf(stderr,
            "tissuebench mesh %s: %s: unknown extension (" TB_MESH_WRITES
            "; .edges with "
            "--part edges)\n",
            name, out);
    return TB_EXIT_INPUT;
  }
  tb_gen_result r;
  tb_error err;
  /* the generators are functions of their settings: a failure is the settings' fault */
  int bad = which == TB_PART_SURFACE ? tb_generator_run_surface(g, p, &r, &err)
                                     : tb_generator_run(g, p, &r, &err);
  if (!bad && (tb_mesh_check_coords(&r.surface, name, &err) ||
               tb_mesh_check_coords(&r.volume, name, &err))) {
    tb_gen_result_free(&r);
    bad = 1;
  }
  if (bad) {
    fprintf(stderr, "tissuebench mesh %s: %s\n", name, err.msg);
    return TB_EXIT_INPUT;
  }
  int rc = TB_EXIT_OK;
  if (stats) tb_gen_result_print(stdout, g, p, &r);
  if (out) {
    int e;
    if (which == TB_PART_EDGES)
      e = write_edges(out, r.volume.nv ? &r.volume : &r.surface, &err);
    else {
      tb_mesh m;
      e = tb_gen_result_part(&r, which, &m, &err);
      if (!e) {
        e = tb_mesh_write(out, &m, &err);
        tb_mesh_free(&m); /* written or not */
      }
    }
    if (e) {
      fprintf(stderr, "tissuebench mesh %s: %s\n", name, err.msg);
      rc = TB_EXIT_FAIL;
    }
  }
  tb_gen_result_free(&r);
  return rc;
}

int tb_cmd_mesh(int argc, char **argv) {
  if (argc < 2) {
    fprintf(stderr,
            "usage: tissuebench mesh info FILE | mesh tetrahedralize IN --out OUT | mesh close IN "
            "--out "
            "OUT | mesh subdivide IN --levels N --out OUT | mesh "
            "spheres IN --count N --out OUT.sph | mesh spheres --info X.sph [--surface IN] | mesh "
            "NAME ... | mesh list\n");
    return TB_EXIT_INPUT;
  }
  if (!strcmp(argv[1], "info")) return mesh_info(argc - 1, argv + 1);
  if (!strcmp(argv[1], "subdivide")) return mesh_subdivide(argc - 1, argv + 1);
  if (!strcmp(argv[1], "spheres")) return tb_cmd_mesh_spheres(argc - 1, argv + 1);
  if (!strcmp(argv[1], "tetrahedralize")) return tb_cmd_mesh_tetrahedralize(argc - 1, argv + 1);
  if (!strcmp(argv[1], "close")) return tb_cmd_mesh_close(argc - 1, argv + 1);
  if (!strcmp(argv[1], "list")) {
    if (argc > 2) return tb_cli_bad_option("mesh list", argv[2]);
    tb_generator_list(stdout);
    return TB_EXIT_OK;
  }
  return mesh_generate(argc - 1, argv + 1);
}
