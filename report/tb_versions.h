/* Versions of the reference libraries tissuebench is built against, read
 * from their headers at compile time (TetGen from the Debian package, passed
 * by meson as TB_TETGEN_VERSION). A C interface to report/versions.cpp. */
#ifndef TB_VERSIONS_H
#define TB_VERSIONS_H

#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

/* Fills each buffer (cap bytes, always terminated) with a version string:
 * CHOLMOD "3.0.14", FCL "0.7.0", Bullet "3.24", CGAL "5.5.1", TetGen as the
 * package reports it, or "unknown". */
void tb_versions_get(char *cholmod, char *fcl, char *bullet, char *cgal, char *tetgen, size_t cap);

#ifdef __cplusplus
}
#endif

#endif
