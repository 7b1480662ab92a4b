/* Mesh file entry points: choose the reader or writer by the file's
 * extension (case-insensitive); a failed read leaves the mesh empty. */
#include <string.h>
#include <strings.h>

#include "io_internal.h"
#include "tb_mesh_io.h"

typedef struct reader {
  const char *ext;
  int (*fn)(const char *path, tb_build *b, tb_error *err);
} reader;
typedef struct writer {
  const char *ext;
  int (*fn)(const char *path, const tb_mesh *m, tb_error *err);
} writer;

static const reader readers[] = {{".obj", tb_read_obj},    {".off", tb_read_off},
                                 {".stl", tb_read_stl},    {".node", tb_read_tetgen},
                                 {".ele", tb_read_tetgen}, {".msh", tb_read_msh},
                                 {".vtu", tb_read_vtu},    {".vtk", tb_read_vtk}};
static const writer writers[] = {{".obj", tb_write_obj},    {".off", tb_write_off},
                                 {".stl", tb_write_stl},    {".node", tb_write_tetgen},
                                 {".ele", tb_write_tetgen}, {".vtk", tb_write_vtk},
                                 {".msh", tb_write_msh}};

/* The extension of the file name, with its dot, or "". */
static const char *extension(const char *path) {
  const char *slash = strrchr(path, '/'), *dot = strrchr(path, '.');
  return dot && (!slash || dot > slash + 1) ? dot : "";
}

/* The readers' contract, checked once more on what they return: every
 * coordinate tb_coord_ok, every index in range. A failure is a reader bug,
 * reported rather than passed on. */
static int check_read(const char *path, const tb_mesh *m, tb_error *err) {
  int tet, v;
  long e;
  if (tb_mesh_check_coords(m, path, err)) return -1;
  if (tb_mesh_bad_index(m, &tet, &e, &v))
    return tb_error_set(err, path, 0, "reader error: %s %ld uses vertex %d of %d",
                        tet ? "tetrahedron" : "triangle", e, v, m->nv);
  return 0;
}

int tb_mesh_read(const char *path, tb_mesh *m, tb_error *err) {
  const char *ext = extension(path);
  memset(m, 0, sizeof *m);
  for (size_t i = 0; i < sizeof readers / sizeof readers[0]; i++) {
    if (strcasecmp(ext, readers[i].ext)) continue;
    tb_build b;
    memset(&b, 0, sizeof b);
    if (readers[i].fn(path, &b, err) || check_read(path, &b.m, err)) {
      tb_build_free(&b);
      return -1;
    }
    *m = b.m;
    return 0;
  }
  return tb_error_set(err, path, 0,
                      "unknown mesh format '%s' (reads .obj .off .stl .node .ele .msh .vtu .vtk)",
                      ext);
}

int tb_mesh_write(const char *path, const tb_mesh *m, tb_error *err) {
  const char *ext = extension(path);
  for (size_t i = 0; i < sizeof writers / sizeof writers[0]; i++)
    if (!strcasecmp(ext, writers[i].ext)) return writers[i].fn(path, m, err);
  return tb_error_set(err, path, 0, "unknown mesh format '%s' (writes " TB_MESH_WRITES ")", ext);
}

int tb_mesh_writable(const char *path) {
  const char *ext = extension(path);
  for (size_t i = 0; i < sizeof writers / sizeof writers[0]; i++)
    if (!strcasecmp(ext, writers[i].ext)) return 1;
  return 0;
}
