// TetGen 1.5 (libtet, TETLIBRARY) behind the C function tb_tetgen(): a
// closed triangle surface in, a tetrahedral mesh out.
//
// TetGen reports failures by throwing an int, but on some inputs (a
// self-intersecting surface, for one) it then crashes while freeing its own
// memory. So each call runs in a forked child that sends the mesh back
// through a pipe: a throw, a crash or an exit() inside TetGen becomes a
// tb_error in the caller, never the caller's crash.
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <csignal>
#include <cstdlib>
#include <cstring>
#include <string>
#include <utility>
#include <vector>

#include <tetgen.h>

extern "C" {
#include "tb_meshgen.h"
}

static const char *tetgen_reason(int code) {
  switch (code) {
    case 1:
      return "out of memory";
    case 2:
      return "internal error";
    case 3:
      return "a self-intersection was detected in the surface";
    case 4:
      return "a very small input feature size was detected";
    case 5:
      return "two very close input facets were detected";
    case 10:
      return "an input error was detected";
    default:
      return "failed";
  }
}

static bool write_all(int fd, const void *p, size_t n) {
  const char *c = static_cast<const char *>(p);
  while (n > 0) {
    ssize_t w = write(fd, c, n);
    if (w < 0 && errno == EINTR) continue;
    if (w <= 0) return false;
    c += w, n -= (size_t)w;
  }
  return true;
}

static bool read_all(int fd, void *p, size_t n) {
  char *c = static_cast<char *>(p);
  while (n > 0) {
    ssize_t r = read(fd, c, n);
    if (r < 0 && errno == EINTR) continue;
    if (r <= 0) return false;
    c += r, n -= (size_t)r;
  }
  return true;
}

// The child: tetrahedralise, then send {code, nv, ntet, points, tets}.
static void child(const tb_mesh *surf, const std::string &sw, int fd) {
  int head[3] = {0, 0, 0};
  try {
    tetgenio in, res;
    in.firstnumber = 0;
    in.numberofpoints = surf->nv;
    in.pointlist = new REAL[3 * (size_t)surf->nv];
    for (int i = 0; i < surf->nv; i++) {
      in.pointlist[3 * i] = surf->x[i].x;
      in.pointlist[3 * i + 1] = surf->x[i].y;
      in.pointlist[3 * i + 2] = surf->x[i].z;
    }
    in.numberoffacets = surf->ntri;
    in.facetlist = new tetgenio::facet[(size_t)surf->ntri];
    for (int t = 0; t < surf->ntri; t++) {
      tetgenio::facet &f = in.facetlist[t];
      tetgenio::init(&f);
      f.numberofpolygons = 1;
      f.polygonlist = new tetgenio::polygon[1];
      tetgenio::init(&f.polygonlist[0]);
      f.polygonlist[0].numberofvertices = 3;
      f.polygonlist[0].vertexlist = new int[3];
      for (int j = 0; j < 3; j++) f.polygonlist[0].vertexlist[j] = surf->tri[3 * t + j];
    }
    std::vector<char> buf(sw.begin(), sw.end());
    buf.push_back(0);
    tetrahedralize(buf.data(), &in, &res);
    if (res.numberofcorners != 4 || res.numberoftetrahedra <= 0) {
      head[0] = -1;
      write_all(fd, head, sizeof head);
      return;
    }
    head[1] = res.numberofpoints, head[2] = res.numberoftetrahedra;
    write_all(fd, head, sizeof head) &&
        write_all(fd, res.pointlist, sizeof(REAL) * 3 * (size_t)head[1]) &&
        write_all(fd, res.tetrahedronlist, sizeof(int) * 4 * (size_t)head[2]);
  } catch (int code) {
    head[0] = code > 0 ? code : 2;
    write_all(fd, head, sizeof head);
  } catch (...) {
    head[0] = 1;
    write_all(fd, head, sizeof head);
  }
}

extern "C" int tb_tetgen(const tb_mesh *surf, const char *switches, tb_mesh *out, tb_error *err) {
  std::memset(out, 0, sizeof *out);
  if (surf->nv < 4 || surf->ntri < 4)
    return tb_error_set(err, "tetgen", 0, "the surface needs at least 4 vertices and 4 triangles");
  std::string sw = std::string(switches ? switches : "") + "Qz";
  int fd[2];
  if (pipe(fd)) return tb_error_set(err, "tetgen", 0, "pipe: %s", std::strerror(errno));
  fflush(nullptr);
  pid_t pid = fork();
  if (pid < 0) {
    close(fd[0]), close(fd[1]);
    return tb_error_set(err, "tetgen", 0, "fork: %s", std::strerror(errno));
  }
  if (pid == 0) {
    close(fd[0]);
    child(surf, sw, fd[1]);
    close(fd[1]);
    _exit(0);
  }
  close(fd[1]);
  int head[3] = {0, 0, 0};
  bool ok = read_all(fd[0], head, sizeof head) && head[0] == 0;
  if (ok) {
    out->nv = head[1], out->ntet = head[2];
    std::vector<double> pts(3 * (size_t)out->nv);
    out->x = static_cast<tb_vec3 *>(std::malloc(sizeof(tb_vec3) * (size_t)out->nv));
    out->tet = static_cast<int *>(std::malloc(sizeof(int) * 4 * (size_t)out->ntet));
    ok = out->x && out->tet && read_all(fd[0], pts.data(), sizeof(double) * pts.size()) &&
         read_all(fd[0], out->tet, sizeof(int) * 4 * (size_t)out->ntet);
    for (int i = 0; ok && i < out->nv; i++)
      out->x[i] = tb_v3(pts[3 * i], pts[3 * i + 1], pts[3 * i + 2]);
  }
  close(fd[0]);
  int status = 0;
  while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  if (!ok) {
    tb_mesh_free(out);
    if (head[0] <= 0 && (WIFSIGNALED(status) || WEXITSTATUS(status) != 0))
      return tb_error_set(err, "tetgen", 0,
                          "TetGen crashed (%s %d), as it does on self-intersecting or degenerate "
                          "surfaces",
                          WIFSIGNALED(status) ? "signal" : "exit status",
                          WIFSIGNALED(status) ? WTERMSIG(status) : WEXITSTATUS(status));
    if (head[0] > 0)
      return tb_error_set(err, "tetgen", 0, "TetGen error %d: %s", head[0], tetgen_reason(head[0]));
    if (head[0] < 0) return tb_error_set(err, "tetgen", 0, "TetGen produced no linear tetrahedra");
    return tb_error_set(err, "tetgen", 0, "TetGen exited without a mesh (status %d)", status);
  }
  // Orient every tet positively (TetGen's convention is the mirror of ours).
  for (int t = 0; t < out->ntet; t++) {
    int *v = out->tet + 4 * t;
    for (int j = 0; j < 4; j++)
      if (v[j] < 0 || v[j] >= out->nv) {
        tb_mesh_free(out);
        return tb_error_set(err, "tetgen", 0, "TetGen returned an index out of range");
      }
    if (tb_tet_volume(out->x[v[0]], out->x[v[1]], out->x[v[2]], out->x[v[3]]) < 0)
      std::swap(v[2], v[3]);
  }
  out->ntri = tb_mesh_tet_boundary(out, &out->tri);
  if (out->ntri < 0) {
    tb_mesh_free(out);
    return tb_error_set(err, "tetgen", 0, "out of memory");
  }
  return 0;
}
