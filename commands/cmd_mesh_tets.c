/* `tissuebench mesh tetrahedralize IN --out OUT ...` and `tissuebench mesh close IN --out OUT`:
 * a user's closed surface to a tet mesh by TetGen (meshgen/tetmesh.c), with an optional local
 * repair of self-intersections, and the holes of an open surface capped (meshgen/cap.c). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "tb_cli.h"
#include "core/tb_mesh_io.h"
#include "core/tb_timer.h"
#include "meshgen/tb_meshgen.h"

/* Reads a triangle surface: a tet mesh is refused (its surface is tetrahedralised already). */
static int read_surface(const char *cmd, const char *in, tb_mesh *m) {
  tb_error err;
  if (tb_mesh_read(in, m, &err)) {
    fprintf(stderr, "%s\n", err.msg);
    return TB_EXIT_INPUT;
  }
  if (m->ntet || m->ntri < 1) {
    fprintf(stderr, "tissuebench mesh %s: %s: %s\n", cmd, in,
            m->ntet ? "a tet mesh already (give its surface)" : "no triangles");
    tb_mesh_free(m);
    return TB_EXIT_INPUT;
  }
  int dropped = tb_mesh_drop_unused(m);
  if (dropped > 0)
    printf("%s: %d unused vertex%s dropped\n", in, dropped, dropped == 1 ? "" : "es");
  return dropped < 0 ? TB_EXIT_FAIL : TB_EXIT_OK;
}

static int parse_positive(const char *what, const char *text, double *v) {
  if (tb_cli_parse_double(what, text, v)) return -1;
  if (*v <= 0) {
    fprintf(stderr, "tissuebench: %s: must be > 0, not '%s'\n", what, text);
    return -1;
  }
  return 0;
}

int tb_cmd_mesh_tetrahedralize(int argc, char **argv) {
  const char *in = NULL, *out = NULL;
  tb_tetmesh_opts o = tb_tetmesh_default_opts();
  int repair = 0;
  double tets = 0;
  for (int i = 1; i < argc; i++) {
    const char *a = argv[i], *v = i + 1 < argc ? argv[i + 1] : NULL;
    if (!strcmp(a, "--out") && v)
      out = argv[++i];
    else if (!strcmp(a, "--quality") && v) {
      if (tb_cli_parse_double("--quality", argv[++i], &o.quality)) return TB_EXIT_INPUT;
    } else if (!strcmp(a, "--max-volume") && v) {
      if (parse_positive("--max-volume", argv[++i], &o.max_volume)) return TB_EXIT_INPUT;
    } else if (!strcmp(a, "--tets") && v) {
      if (parse_positive("--tets", argv[++i], &tets)) return TB_EXIT_INPUT;
      if (tets != floor(tets) || tets > 1e8) {
        fprintf(stderr, "tissuebench: --tets: a whole number up to 1e8, not '%s'\n", v);
        return TB_EXIT_INPUT;
      }
      o.tets = (int)tets;
    } else if (!strcmp(a, "--split-surface"))
      o.split_surface = 1;
    else if (!strcmp(a, "--repair"))
      repair = 1;
    else if (a[0] != '-' && !in)
      in = a;
    else
      return tb_cli_bad_option("mesh tetrahedralize", a);
  }
  if (!in || !out) {
    fprintf(stderr,
            "usage: tissuebench mesh tetrahedralize IN --out OUT [--quality R] "
            "[--max-volume V | --tets N] [--split-surface] [--repair]\n");
    return TB_EXIT_INPUT;
  }
  if (o.max_volume > 0 && o.tets > 0) {
    fprintf(stderr, "tissuebench mesh tetrahedralize: give --max-volume or --tets, not both\n");
    return TB_EXIT_INPUT;
  }
  if (!(o.quality >= 1.1 && o.quality <= 100)) {
    fprintf(stderr,
            "tissuebench mesh tetrahedralize: --quality %g: a radius-edge bound in "
            "[1.1, 100] (TetGen's q; smaller is better shaped)\n",
            o.quality);
    return TB_EXIT_INPUT;
  }
  if (!tb_mesh_writable(out)) {
    fprintf(stderr, "tissuebench mesh tetrahedralize: %s: unknown extension (.node .vtk .msh)\n",
            out);
    return TB_EXIT_INPUT;
  }
  tb_mesh surf, tets_mesh;
  int rc = read_surface("tetrahedralize", in, &surf);
  if (rc) return rc;
  tb_error err;
  if (repair) {
    double moved;
    int nmoved, left = tb_surface_untangle(&surf, 8, &moved, &nmoved, &err);
    if (left < 0) {
      fprintf(stderr, "tissuebench mesh tetrahedralize: %s\n", err.msg);
      tb_mesh_free(&surf);
      return TB_EXIT_FAIL;
    }
    if (nmoved)
      printf(
          "repair: %d vertices moved (at most %.3g mean edge lengths), %d crossing pairs "
          "left\n",
          nmoved, moved, left);
  }
  printf("surface: %d vertices, %d triangles, volume %.9g\n", surf.nv, surf.ntri,
         fabs(tb_mesh_volume(&surf)));
  uint64_t t0 = tb_time_ns();
  if (tb_tetmesh(&surf, in, &o, &tets_mesh, &err)) {
    fprintf(stderr, "tissuebench mesh tetrahedralize: %s%s\n", err.msg,
            strstr(err.msg, "self-intersecting") && !repair
                ? " (tissuebench mesh info lists the pairs; --repair moves the vertices near them)"
                : "");
    tb_mesh_free(&surf);
    return TB_EXIT_INPUT;
  }
  double wall = 1e-9 * (double)(tb_time_ns() - t0); /* TetGen runs in a child process */
  tb_tet_shape sh = tb_tet_mesh_shape(&tets_mesh);
  printf("tets: %d vertices, %d tets, %d boundary triangles, volume %.9g (%.3g s wall)\n",
         tets_mesh.nv, tets_mesh.ntet, tets_mesh.ntri, tb_mesh_volume(&tets_mesh), wall);
  printf(
      "shape: dihedral angles %.2f-%.2f degrees, radius-edge ratio at most %.3g (the bound %g "
      "holds for the tets TetGen refines, not for slivers or tets at sharp surface angles)\n",
      sh.min_dihedral, sh.max_dihedral, sh.max_radius_edge, o.quality);
  if (sh.min_dihedral < 5 && !o.split_surface)
    printf(
        "note: dihedral angles below 5 degrees; --split-surface lets TetGen add points on the "
        "surface (same shape) to avoid them\n");
  rc = TB_EXIT_OK;
  if (tb_mesh_write(out, &tets_mesh, &err)) {
    fprintf(stderr, "tissuebench mesh tetrahedralize: %s\n", err.msg);
    rc = TB_EXIT_FAIL;
  } else
    printf("wrote %s\n", out);
  tb_mesh_free(&surf), tb_mesh_free(&tets_mesh);
  return rc;
}

int tb_cmd_mesh_close(int argc, char **argv) {
  const char *in = NULL, *out = NULL;
  for (int i = 1; i < argc; i++) {
    if (!strcmp(argv[i], "--out") && i + 1 < argc)
      out = argv[++i];
    else if (argv[i][0] != '-' && !in)
      in = argv[i];
    else
      return tb_cli_bad_option("mesh close", argv[i]);
  }
  if (!in || !out) {
    fprintf(stderr, "usage: tissuebench mesh close IN --out OUT\n");
    return TB_EXIT_INPUT;
  }
  if (!tb_mesh_writable(out)) {
    fprintf(stderr, "tissuebench mesh close: %s: unknown extension (" TB_MESH_WRITES ")\n", out);
    return TB_EXIT_INPUT;
  }
  tb_mesh m;
  int rc = read_surface("close", in, &m), loops = 0;
  if (rc) return rc;
  tb_error err;
  int nv = m.nv, ntri = m.ntri;
  if (tb_mesh_close(&m, &loops, &err)) {
    fprintf(stderr, "tissuebench mesh close: %s: %s\n", in, err.msg);
    tb_mesh_free(&m);
    return TB_EXIT_INPUT;
  }
  printf("%s: %d hole%s capped (%d new vertices, %d new triangles); volume %.9g\n", in, loops,
         loops == 1 ? "" : "s", m.nv - nv, m.ntri - ntri, tb_mesh_volume(&m));
  if (tb_mesh_write(out, &m, &err)) {
    fprintf(stderr, "tissuebench mesh close: %s\n", err.msg);
    rc = TB_EXIT_FAIL;
  } else
    printf("wrote %s\n", out);
  tb_mesh_free(&m);
  return rc;
}
