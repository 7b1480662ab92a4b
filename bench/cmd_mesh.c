/* `tissuebench mesh info FILE` and `tissuebench mesh NAME`: inspect a mesh
 * file, or generate one of the project's meshes (tools/tb_meshgen.h). Each
 * generator is one table entry with named numeric settings. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "tb_cli.h"
#include "tb_mesh_io.h"
#include "tb_meshgen.h"
#include "tb_generators.h"

/* ---- mesh info ---- */
void tb_mesh_print_info(FILE *f, const char *name, const tb_mesh *m) {
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
  free(bnd);
}

static int mesh_info(int argc, char **argv) {
  if (argc != 2) {
    fprintf(stderr, "usage: tissuebench mesh info FILE\n");
    return TB_EXIT_INPUT;
  }
  tb_mesh m;
  tb_error err;
  if (tb_mesh_read(argv[1], &m, &err)) {
    fprintf(stderr, "%s\n", err.msg);
    return TB_EXIT_INPUT;
  }
  tb_mesh_print_info(stdout, argv[1], &m);
  tb_mesh_free(&m);
  return TB_EXIT_OK;
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
      fprintf(stderr, "tissuebench mesh %s: unknown or incomplete option '%s'\n", name, a);
      return TB_EXIT_INPUT;
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
  tb_gen_result r;
  tb_error err;
  if (tb_generator_run(g, p, &r, &err)) {
    fprintf(stderr, "tissuebench mesh %s: %s\n", name, err.msg);
    return TB_EXIT_FAIL;
  }
  int rc = TB_EXIT_OK;
  if (stats) tb_gen_result_print(stdout, g, p, &r);
  if (out) {
    tb_mesh m;
    int e = which == TB_PART_EDGES ? 0 : tb_gen_result_part(&r, which, &m, &err);
    if (!e)
      e = which == TB_PART_EDGES ? write_edges(out, r.volume.nv ? &r.volume : &r.surface, &err)
                                 : tb_mesh_write(out, &m, &err);
    if (which != TB_PART_EDGES && !e) tb_mesh_free(&m);
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
    fprintf(stderr, "usage: tissuebench mesh info FILE | mesh NAME ... | mesh list\n");
    return TB_EXIT_INPUT;
  }
  if (!strcmp(argv[1], "info")) return mesh_info(argc - 1, argv + 1);
  if (!strcmp(argv[1], "list")) {
    tb_generator_list(stdout);
    return TB_EXIT_OK;
  }
  return mesh_generate(argc - 1, argv + 1);
}
