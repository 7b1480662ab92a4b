// Versions of CHOLMOD, FCL, Bullet (double precision), CGAL and TetGen, taken
// from each library's own version macros. The only C++ here is the includes:
// CGAL and Bullet headers are C++.
#include "tb_versions.h"

#include <cstdio>

#include <cholmod.h>
#include <CGAL/version.h>
#include <LinearMath/btScalar.h>
#include <fcl/config.h>

#ifndef TB_TETGEN_VERSION
#define TB_TETGEN_VERSION "unknown"
#endif

void tb_versions_get(char *cholmod, char *fcl, char *bullet, char *cgal, char *tetgen, size_t cap) {
  if (cap == 0) return;
  if (cholmod)
    std::snprintf(cholmod, cap, "%d.%d.%d", CHOLMOD_MAIN_VERSION, CHOLMOD_SUB_VERSION,
                  CHOLMOD_SUBSUB_VERSION);
  if (fcl) std::snprintf(fcl, cap, "%s", FCL_VERSION);
  // BT_BULLET_VERSION is major * 100 + minor, e.g. 324 for 3.24.
  if (bullet)
    std::snprintf(bullet, cap, "%d.%02d", BT_BULLET_VERSION / 100, BT_BULLET_VERSION % 100);
  if (cgal) std::snprintf(cgal, cap, "%s", CGAL_VERSION_STR);
  if (tetgen)
    std::snprintf(tetgen, cap, "%s", TB_TETGEN_VERSION[0] ? TB_TETGEN_VERSION : "unknown");
}
