/* The generator table behind `tissuebench mesh NAME` and the meshes suite:
 * liver (thesis §2.5), instrument, geodesic sphere (Bao 2006 table 1),
 * cantilever beam and the metaball patent's spleen, gallbladder and steak
 * (its table 1, meshgen/organs.c), each with its settings and the documents'
 * counts. */
#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "tb_generators.h"
#include "tb_meshgen.h"
#include "core/tb_timer.h"

/* ---- liver ---- */
static int liver_run(const double *p, tb_gen_result *r, tb_error *err) {
  tb_liver_def d = tb_liver_default_def();
  d.surface_verts = (int)p[0], d.tet_verts = (int)p[1], d.tets = (int)p[2], d.length = p[3];
  d.noise = p[4];
  d.seed = (uint64_t)p[5];
  if (tb_liver_surface(&d, &r->surface, err)) return -1;
  return tb_liver_tets(&d, &r->surface, &r->volume, err);
}
static int liver_paper(const double *p, tb_gen_counts *c, const char **src) {
  if ((int)p[0] == tb_organ_find("liver")->verts) {
    *c = (tb_gen_counts){(int)p[0], 0, 0, 0, 0, 0};
    *src = "metaball patent, table 1";
    return 1;
  }
  *c = (tb_gen_counts){725, 1448, 1206, 4230, 9313, 6288};
  *src = "thesis §2.5 (Amira marching cubes; QTetraMesher)";
  return 1;
}

/* --part surface: no TetGen, the vertex count exact */
static int liver_surface(const double *p, tb_gen_result *r, tb_error *err) {
  tb_liver_def d = tb_liver_default_def();
  d.surface_verts = (int)p[0], d.tet_verts = (int)p[1], d.tets = (int)p[2], d.length = p[3];
  d.noise = p[4];
  d.seed = (uint64_t)p[5];
  return tb_liver_surface_exact(&d, &r->surface, err);
}

/* ---- the metaball patent's organs (settings: verts, seed) ---- */
static int organ_run(const char *name, const double *p, tb_gen_result *r, tb_error *err) {
  return tb_organ_surface(name, (int)p[0], (uint64_t)p[1], &r->surface, err);
}
static int organ_paper(const char *name, tb_gen_counts *c, const char **src) {
  memset(c, 0, sizeof *c);
  c->surface_verts = tb_organ_find(name)->verts;
  *src = "metaball patent, table 1";
  return 1;
}
static int spleen_run(const double *p, tb_gen_result *r, tb_error *err) {
  return organ_run("spleen", p, r, err);
}
static int spleen_paper(const double *p, tb_gen_counts *c, const char **src) {
  (void)p;
  return organ_paper("spleen", c, src);
}
static int gallbladder_run(const double *p, tb_gen_result *r, tb_error *err) {
  return organ_run("gallbladder", p, r, err);
}
static int gallbladder_paper(const double *p, tb_gen_counts *c, const char **src) {
  (void)p;
  return organ_paper("gallbladder", c, src);
}
static int steak_run(const double *p, tb_gen_result *r, tb_error *err) {
  return organ_run("steak", p, r, err);
}
static int steak_paper(const double *p, tb_gen_counts *c, const char **src) {
  (void)p;
  return organ_paper("steak", c, src);
}

/* ---- instrument ---- */
static int instrument_run(const double *p, tb_gen_result *r, tb_error *err) {
  tb_instrument_def d = tb_instrument_default_def();
  d.length = p[0], d.radius = p[1], d.jaw_length = p[2], d.jaw_opening = p[3];
  d.segments = (int)p[4], d.shaft_rings = (int)p[5], d.jaw_rings = (int)p[6];
  return tb_instrument(&d, &r->surface, err);
}
static int instrument_paper(const double *p, tb_gen_counts *c, const char **src) {
  (void)p;
  *c = (tb_gen_counts){628, 1248, 0, 0, 0, 0};
  *src = "thesis §4.5 (instrument model)";
  return 1;
}

/* ---- sphere ---- */
static int sphere_run(const double *p, tb_gen_result *r, tb_error *err) {
  return tb_geosphere((int)p[0], p[1], &r->surface, err);
}
static int sphere_paper(const double *p, tb_gen_counts *c, const char **src) {
  *src = "Bao 2006 table 1";
  memset(c, 0, sizeof *c);
  if ((int)p[0] == 252)
    c->surface_verts = 252, c->surface_tris = 500;
  else if ((int)p[0] == 1002)
    c->surface_verts = 1002, c->surface_tris = 2000;
  return c->surface_verts != 0;
}

/* ---- beam ---- */
static int beam_run(const double *p, tb_gen_result *r, tb_error *err) {
  return tb_beam_with_split(p[0], p[1], p[2], (int)p[3], (int)p[4], (int)p[5], (tb_beam_split)p[6],
                            &r->volume, err);
}
static const char *const beam_splits[] = {"kuhn", "symmetric", NULL};

static const tb_generator generators[] = {
    {"liver",
     "synthetic CT volume -> marching cubes -> clean-up -> TetGen",
     {{"surface_verts", 725, 1,
       "target surface vertices (within 5%; 0: 725 (tets / 4230)^0.8, for tet_verts=0)", NULL},
      {"tet_verts", 1206, 1, "target tet-mesh vertices (within 10%; 0: only tets, within 2%)",
       NULL},
      {"tets", 4230, 1, "target tets (within 10%; 0: tet_verts * 4230 / 1206)", NULL},
      {"length", 10, 0, "extent along x", NULL},
      {"noise", 0.08, 0, "grey-value noise amplitude (relative to tissue)", NULL},
      {"seed", 1, 1, "noise seed", NULL}},
     liver_run,
     liver_paper,
     liver_surface},
    {"instrument",
     "grasper: shaft + lower jaw tube and hinged upper jaw tube (2 closed parts)",
     {{"length", 15, 0, "shaft length", NULL},
      {"radius", 0.25, 0, "shaft radius", NULL},
      {"jaw_length", 1.2, 0, "jaw length", NULL},
      {"jaw_opening", 0.5, 0, "angle between the jaws (radians)", NULL},
      {"segments", 16, 1, "segments around", NULL},
      {"shaft_rings", 24, 1, "rings of the shaft + lower jaw", NULL},
      {"jaw_rings", 15, 1, "rings of the upper jaw", NULL}},
     instrument_run,
     instrument_paper,
     NULL},
    {"sphere",
     "geodesic sphere, 10 f^2 + 2 vertices (252, 1002, ...)",
     {{"verts", 252, 1, "vertices: 10 f^2 + 2", NULL}, {"radius", 1, 0, "radius", NULL}},
     sphere_run,
     sphere_paper,
     NULL},
    {"beam",
     "box cantilever, cubes split into 6 tets each",
     {{"lx", 10, 0, "length (x)", NULL},
      {"ly", 1, 0, "width (y)", NULL},
      {"lz", 1, 0, "height (z)", NULL},
      {"nx", 20, 1, "cells along x", NULL},
      {"ny", 2, 1, "cells along y", NULL},
      {"nz", 2, 1, "cells along z", NULL},
      {"split", 0, 1,
       "kuhn: every cube alike (bends sideways); symmetric: mirrored about the y and z "
       "mid-planes (even ny, nz)",
       beam_splits}},
     beam_run,
     NULL,
     NULL},
    {"spleen",
     "metaball patent's spleen: flattened crescent, hilum groove (~6 x 2.7 x 1.6)",
     {{"verts", 1480, 1, "surface vertices, exact (patent: 1480)", NULL},
      {"seed", 1, 1, "grey-value noise seed", NULL}},
     spleen_run,
     spleen_paper,
     NULL},
    {"gallbladder",
     "metaball patent's gallbladder: pear-shaped sac, bent neck (~4.1 x 2.1 x 1.6)",
     {{"verts", 1415, 1, "surface vertices, exact (patent: 1415)", NULL},
      {"seed", 1, 1, "grey-value noise seed", NULL}},
     gallbladder_run,
     gallbladder_paper,
     NULL},
    {"steak",
     "metaball patent's steak: irregular rounded slab (~8 x 5 x 1.55)",
     {{"verts", 1266, 1, "surface vertices, exact (patent: 1266)", NULL},
      {"seed", 1, 1, "outline and grey-value noise seed", NULL}},
     steak_run,
     steak_paper,
     NULL},
};
static const int ngenerators = (int)(sizeof generators / sizeof generators[0]);

static int nparams(const tb_generator *g) {
  int n = 0;
  while (n < TB_GEN_MAX_PARAMS && g->params[n].key) n++;
  return n;
}

const tb_generator *tb_generator_find(const char *name) {
  for (int i = 0; i < ngenerators; i++)
    if (!strcmp(generators[i].name, name)) return &generators[i];
  return NULL;
}

void tb_generator_list(FILE *f) {
  for (int i = 0; i < ngenerators; i++) {
    const tb_generator *g = &generators[i];
    fprintf(f, "%s: %s\n", g->name, g->summary);
    for (int k = 0; k < nparams(g); k++) {
      const tb_gen_param *q = &g->params[k];
      if (q->names)
        fprintf(f, "  --set %s=%s\t%s\n", q->key, q->names[(int)q->value], q->doc);
      else
        fprintf(f, "  --set %s=%g\t%s\n", q->key, q->value, q->doc);
    }
  }
}

void tb_generator_defaults(const tb_generator *g, double *p) {
  for (int k = 0; k < TB_GEN_MAX_PARAMS; k++) p[k] = k < nparams(g) ? g->params[k].value : 0;
}

int tb_generator_set(const tb_generator *g, double *p, const char *kv) {
  const char *eq = strchr(kv, '=');
  for (int k = 0; eq && k < nparams(g); k++) {
    if (strlen(g->params[k].key) != (size_t)(eq - kv) || strncmp(g->params[k].key, kv, eq - kv))
      continue;
    int nnames = 0;
    for (const char *const *n = g->params[k].names; n && *n; n++, nnames++)
      if (!strcmp(*n, eq + 1)) return p[k] = nnames, 0;
    char *end;
    errno = 0;
    double v = strtod(eq + 1, &end);
    if (nnames && (end == eq + 1 || *end || !(v >= 0 && v < nnames) || v != floor(v))) {
      fprintf(stderr, "tissuebench mesh %s: %s is one of", g->name, g->params[k].key);
      for (int i = 0; i < nnames; i++) fprintf(stderr, " %s", g->params[k].names[i]);
      fprintf(stderr, ", not '%s'\n", eq + 1);
      return -1;
    }
    int integer = g->params[k].integer;
    if (end == eq + 1 || *end || isnan(v) || (integer && isfinite(v) && v != floor(v))) {
      fprintf(stderr, "tissuebench mesh %s: %s needs a %s, not '%s'\n", g->name, g->params[k].key,
              integer ? "whole number" : "number", eq + 1);
      return -1;
    }
    /* counts and seeds in [0, 1e9]; lengths and angles within the coordinates' bound */
    double lo = integer ? 0 : -TB_COORD_MAX, hi = integer ? 1e9 : TB_COORD_MAX;
    if (!(v >= lo && v <= hi)) {
      fprintf(stderr, "tissuebench mesh %s: %s = %s is out of range [%g, %g]\n", g->name,
              g->params[k].key, eq + 1, lo, hi);
      return -1;
    }
    p[k] = v;
    return 0;
  }
  fprintf(stderr, "tissuebench mesh %s: unknown setting '%s' (tissuebench mesh list)\n", g->name,
          kv);
  return -1;
}

int tb_generator_run(const tb_generator *g, const double *p, tb_gen_result *r, tb_error *err) {
  memset(r, 0, sizeof *r);
  uint64_t t0 = tb_time_ns();
  int rc = g->run(p, r, err);
  r->ms = (double)(tb_time_ns() - t0) * 1e-6;
  if (rc) tb_gen_result_free(r);
  return rc;
}

int tb_generator_run_surface(const tb_generator *g, const double *p, tb_gen_result *r,
                             tb_error *err) {
  if (!g->surface) return tb_generator_run(g, p, r, err);
  memset(r, 0, sizeof *r);
  uint64_t t0 = tb_time_ns();
  int rc = g->surface(p, r, err);
  r->ms = (double)(tb_time_ns() - t0) * 1e-6;
  if (rc) tb_gen_result_free(r);
  return rc;
}

void tb_gen_result_free(tb_gen_result *r) {
  tb_mesh_free(&r->surface);
  tb_mesh_free(&r->volume);
}

tb_gen_counts tb_gen_result_counts(const tb_gen_result *r) {
  tb_gen_counts c = {r->surface.nv, r->surface.ntri, r->volume.nv, r->volume.ntet, 0, 0};
  if (!r->surface.nv) c.surface_verts = 0, c.surface_tris = r->volume.ntri;
  if (r->volume.ntet) {
    int *f = NULL, *e = NULL;
    c.faces = tb_mesh_tet_faces(&r->volume, &f);
    c.edges = tb_mesh_edges(&r->volume, &e);
    free(f), free(e);
  }
  return c;
}

static void row(FILE *f, const char *what, int ours, int paper, int has_paper) {
  if (!ours && !paper) return;
  if (has_paper && paper)
    fprintf(f, "  %-20s %8d %8d %+7.1f%%\n", what, ours, paper, 100.0 * (ours - paper) / paper);
  else
    fprintf(f, "  %-20s %8d %8s\n", what, ours, "-");
}

void tb_gen_result_print(FILE *f, const tb_generator *g, const double *p, const tb_gen_result *r) {
  tb_gen_counts c = tb_gen_result_counts(r), d;
  const char *src = "";
  int has = g->paper && g->paper(p, &d, &src);
  if (!has) memset(&d, 0, sizeof d);
  fprintf(f, "%s (%.1f ms)%s%s\n  %-20s %8s %8s %8s\n", g->name, r->ms, has ? "; documents: " : "",
          src, "", "ours", "document", "diff");
  row(f, "surface vertices", c.surface_verts, d.surface_verts, has);
  row(f, "surface triangles", c.surface_tris, d.surface_tris, has);
  row(f, "tet-mesh vertices", c.verts, d.verts, has);
  row(f, "tets", c.tets, d.tets, has);
  row(f, "tet faces", c.faces, d.faces, has);
  row(f, "tet edges", c.edges, d.edges, has);
  const tb_mesh *m = r->surface.nv ? &r->surface : &r->volume;
  tb_mesh_topo t = tb_mesh_topology(m);
  fprintf(f, "  surface: %s, %s, %d component(s), Euler %d", t.closed ? "closed" : "open",
          t.manifold ? "manifold" : "NOT manifold", t.components, t.euler);
  if (r->volume.ntet) fprintf(f, "; min tet volume %.3g", tb_mesh_min_tet_volume(&r->volume));
  fprintf(f, "\n");
}

int tb_gen_result_part(const tb_gen_result *r, tb_mesh_part part, tb_mesh *out, tb_error *err) {
  const tb_mesh *vol = &r->volume, *surf = &r->surface;
  if (part == TB_PART_DEFAULT) part = vol->ntet ? TB_PART_TETS : TB_PART_SURFACE;
  memset(out, 0, sizeof *out);
  if ((part == TB_PART_TETS || part == TB_PART_FACES) && !vol->ntet)
    return tb_error_set(err, "mesh", 0, "this mesh has no tets");
  int rc = 0;
  if (part == TB_PART_TETS)
    rc = tb_mesh_copy(out, vol);
  else if (part == TB_PART_SURFACE) {
    rc = tb_mesh_copy(out, surf->nv ? surf : vol);
    free(out->tet);
    out->tet = NULL, out->ntet = 0;
  } else if (part == TB_PART_FACES) {
    tb_mesh m = *vol;
    m.tri = NULL, m.ntri = 0, m.tet = NULL, m.ntet = 0;
    rc = tb_mesh_copy(out, &m);
    if (!rc) {
      out->ntri = tb_mesh_tet_faces(vol, &out->tri);
      rc = out->ntri < 0;
    }
  } else {
    return tb_error_set(err, "mesh", 0, "edges are not a mesh part");
  }
  if (rc) {
    tb_mesh_free(out);
    return tb_error_set(err, "mesh", 0, "out of memory");
  }
  return 0;
}

int tb_mesh_part_parse(const char *s, tb_mesh_part *part) {
  static const char *names[] = {"default", "tets", "surface", "faces", "edges"};
  for (int i = 0; i < 5; i++)
    if (!strcmp(s, names[i])) return *part = (tb_mesh_part)i, 0;
  return -1;
}
