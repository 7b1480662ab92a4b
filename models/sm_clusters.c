/* Clusters for meshless shape matching (thesis §3.4.4 "3. cluster-based
 * deformation"; Müller et al. 2005 §4.4): overlapping spherical regions
 * around centres picked by farthest-point sampling (the thesis's "50
 * clusters, region radius 1"), or, for a tet mesh, one cluster per node made
 * of the node and its tet neighbours. The result is a CSR list, each
 * cluster's members ascending. */
#include <stdlib.h>
#include <string.h>

#include "tb_sm.h"

void tb_sm_clusters_free(tb_sm_clusters *c) {
  free(c->start);
  free(c->node);
  memset(c, 0, sizeof *c);
}

static double dist2(tb_vec3 a, tb_vec3 b) {
  tb_vec3 d = tb_sub(a, b);
  return tb_dot(d, d);
}

/* Farthest-point sampling: the first centre is the node nearest the
 * centroid, each next one the node farthest from the centres so far (lowest
 * index on ties). near[i] receives the nearest centre of node i. */
static void farthest_points(const tb_mesh *mesh, int k, int *centre, int *near, double *dmin) {
  int nv = mesh->nv;
  tb_vec3 c = tb_v3(0, 0, 0);
  for (int i = 0; i < nv; i++) c = tb_add(c, mesh->x[i]);
  c = tb_scale(c, 1.0 / nv);
  int first = 0;
  for (int i = 1; i < nv; i++)
    if (dist2(mesh->x[i], c) < dist2(mesh->x[first], c)) first = i;
  centre[0] = first;
  for (int i = 0; i < nv; i++) dmin[i] = dist2(mesh->x[i], mesh->x[first]), near[i] = 0;
  for (int j = 1; j < k; j++) {
    int far = 0;
    for (int i = 1; i < nv; i++)
      if (dmin[i] > dmin[far]) far = i;
    centre[j] = far;
    for (int i = 0; i < nv; i++) {
      double d = dist2(mesh->x[i], mesh->x[far]);
      if (d < dmin[i]) dmin[i] = d, near[i] = j;
    }
  }
}

static int build_regions(const tb_mesh *mesh, int clusters, double radius, tb_sm_clusters *out) {
  int nv = mesh->nv, k = clusters < nv ? clusters : nv;
  out->n = k;
  out->start = malloc(sizeof(int) * (size_t)(k + 1));
  if (!out->start) return -1;
  if (k == 1) { /* the whole body */
    out->node = malloc(sizeof(int) * (size_t)nv);
    if (!out->node) return -1;
    out->start[0] = 0, out->start[1] = nv;
    for (int i = 0; i < nv; i++) out->node[i] = i;
    return 0;
  }
  int *centre = malloc(sizeof(int) * (size_t)k), *near = malloc(sizeof(int) * (size_t)nv);
  double *dmin = malloc(sizeof(double) * (size_t)nv);
  char *inside = calloc((size_t)nv, 1);
  int rc = -1;
  if (!centre || !near || !dmin || !inside) goto done;
  farthest_points(mesh, k, centre, near, dmin);
  double r2 = radius * radius;
  long total = 0;
  for (int i = 0; i < nv; i++) {
    for (int c = 0; c < k; c++)
      if (dist2(mesh->x[i], mesh->x[centre[c]]) <= r2) inside[i] = 1, total++;
    if (!inside[i]) total++; /* joins its nearest centre's cluster */
  }
  if (total > 0x7fffffffL) goto done;
  out->node = malloc(sizeof(int) * (size_t)total);
  if (!out->node) goto done;
  int n = 0;
  for (int c = 0; c < k; c++) {
    out->start[c] = n;
    tb_vec3 xc = mesh->x[centre[c]];
    for (int i = 0; i < nv; i++)
      if (dist2(mesh->x[i], xc) <= r2 || (!inside[i] && near[i] == c)) out->node[n++] = i;
  }
  out->start[k] = n;
  rc = 0;
done:
  free(centre), free(near), free(dmin), free(inside);
  return rc;
}

static int build_tets(const tb_mesh *mesh, tb_sm_clusters *out) {
  int nv = mesh->nv, *edges = NULL;
  int ne = tb_mesh_edges(mesh, &edges);
  if (ne < 0) return -1;
  out->n = nv;
  out->start = calloc((size_t)nv + 1, sizeof(int));
  out->node = malloc(sizeof(int) * ((size_t)nv + 2 * (size_t)ne));
  int *fill = malloc(sizeof(int) * (size_t)nv);
  if (!out->start || !out->node || !fill) {
    free(edges), free(fill);
    return -1;
  }
  for (int e = 0; e < 2 * ne; e++) out->start[edges[e] + 1]++;
  for (int i = 0; i < nv; i++) out->start[i + 1] += out->start[i] + 1; /* + the node itself */
  for (int i = 0; i < nv; i++) out->node[out->start[i]] = i, fill[i] = out->start[i] + 1;
  for (int e = 0; e < ne; e++) {
    int a = edges[2 * e], b = edges[2 * e + 1];
    out->node[fill[a]++] = b;
    out->node[fill[b]++] = a;
  }
  for (int c = 0; c < nv; c++) { /* insertion sort: members ascending */
    int *m = out->node + out->start[c], len = out->start[c + 1] - out->start[c];
    for (int j = 1; j < len; j++) {
      int v = m[j], t = j;
      for (; t > 0 && m[t - 1] > v; t--) m[t] = m[t - 1];
      m[t] = v;
    }
  }
  free(edges), free(fill);
  return 0;
}

int tb_sm_clusters_build(const tb_mesh *mesh, int cluster_mode, int clusters, double radius,
                         tb_sm_clusters *out, tb_error *err) {
  memset(out, 0, sizeof *out);
  if (mesh->nv < 1) return tb_error_set(err, "sm", 0, "the mesh has no nodes");
  for (int i = 0; i < mesh->nv; i++)
    if (!tb_isfinite3(mesh->x[i]))
      return tb_error_set(err, "sm", 0, "node %d has a non-finite position", i);
  for (int t = 0; t < 4 * mesh->ntet; t++)
    if (mesh->tet[t] < 0 || mesh->tet[t] >= mesh->nv)
      return tb_error_set(err, "sm", 0, "tet %d has node index %d outside [0, %d)", t / 4,
                          mesh->tet[t], mesh->nv);
  int rc;
  if (cluster_mode == TB_CLUSTER_TETS) {
    if (mesh->ntet < 1)
      return tb_error_set(err, "sm", 0,
                          "cluster_mode=tets needs a tet mesh (this one has no tets; use "
                          "cluster_mode=regions for a point cloud)");
    rc = build_tets(mesh, out);
  } else if (cluster_mode == TB_CLUSTER_REGIONS) {
    if (clusters < 1 || !(radius > 0))
      return tb_error_set(err, "sm", 0, "regions need clusters >= 1 and radius > 0");
    rc = build_regions(mesh, clusters, radius, out);
  } else {
    return tb_error_set(err, "sm", 0, "bad cluster_mode %d", cluster_mode);
  }
  if (rc) {
    tb_sm_clusters_free(out);
    return tb_error_set(err, "sm", 0, "out of memory building the clusters");
  }
  return 0;
}
