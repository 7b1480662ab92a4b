/* Where tissuebench finds its own files at run time (scenes, scripts, the
 * designed triangle pairs, the field's shared data) and where results go by
 * default, so a copied, moved or installed build reads and writes its own
 * tree, never the one it was compiled in. */
#ifndef TB_PATHS_H
#define TB_PATHS_H

/* The folder holding scenes/, scripts/ and tests/data/, the first of:
 * $TB_DATA_DIR; the checkout the running program sits in (the executable's
 * folder's parent when it holds scenes/); an installed share/tissuebench
 * beside the executable's bin/; the source tree the build was configured
 * from (a build folder outside its checkout); ".". */
const char *tb_root(void);
/* The field's data (SOFA's meshes, FCL's, the JGT pairs; may be absent):
 * $TB_SHARED_DATA, else ../shared/data beside the root. */
const char *tb_shared_data(void);
/* Where results go when --results is not given: ROOT/results when the root
 * is a checkout (it has meson.build), else ./results (an installed copy). */
const char *tb_results_dir(void);
/* "BASE/REL", the same pointer for the same two strings, valid until the
 * program ends (a small table; thread-safe). */
const char *tb_path_in(const char *base, const char *rel);

#endif
