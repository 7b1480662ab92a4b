/* Meshless shape matching (models/sm.c): the clusters it matches and the
 * queries suites print (mean particles per cluster, thesis §3.5: 96). */
#ifndef TB_SM_H
#define TB_SM_H

#include "tb_model.h"
#include "core/tb_error.h"
#include "core/tb_mesh.h"

/* Shape-matching variants (Müller et al. 2005; thesis §3.4.4): the index
 * of sm_mode's choices. */
enum { TB_SM_RIGID = 0, TB_SM_LINEAR = 1, TB_SM_QUADRATIC = 2 };
/* Shape-matching clusters (cluster_mode's choices): overlapping spheres of
 * a radius around centres chosen by farthest-point sampling (thesis:
 * "region radius 1"), or one cluster per node made of the node and its tet
 * neighbours. */
enum { TB_CLUSTER_REGIONS = 0, TB_CLUSTER_TETS = 1 };

/* Clusters as a CSR list: cluster c holds node[start[c]] .. node[start[c+1]-1],
 * ascending. Every node is in at least one cluster. */
typedef struct tb_sm_clusters {
  int n;
  int *start; /* n + 1 offsets */
  int *node;  /* start[n] member node indices */
} tb_sm_clusters;

/* Builds the clusters cluster_mode asks for (models/sm_clusters.c):
 * TB_CLUSTER_REGIONS: min(clusters, nv) centres by farthest-point
 * sampling from the node nearest the centroid, members within radius of
 * a centre, nodes in no region added to the nearest centre's cluster;
 * clusters == 1 is one cluster of all nodes. TB_CLUSTER_TETS: one
 * cluster per node, the node and its tet neighbours (a mesh without tets is
 * an error). Same input, same clusters.
 * Note: two regions that share fewer than 3 non-collinear nodes are joined
 * by a hinge (a zero-energy mode: the body need not return to its rest
 * shape); on the liver, radius 1 with 50 centres overlaps widely. */
int tb_sm_clusters_build(const tb_mesh *mesh, int cluster_mode, int clusters, double radius,
                         tb_sm_clusters *out, tb_error *err);
void tb_sm_clusters_free(tb_sm_clusters *c);

/* Number of clusters and mean members per cluster of an sm model; -1 when m
 * is not an sm model. */
int tb_sm_cluster_stats(const tb_model *m, int *nclusters, double *mean_members);

#endif
