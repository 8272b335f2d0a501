/* Mesh topology by sorting edge triples (i < j, triangle), as on the
 * lecture's "Topological Construction" slide: after sorting, equal (i, j)
 * runs give the unique edges; a run of two gives a pair of neighbouring
 * triangles (used by bending); a run of one is a boundary edge. Line
 * segments (chains, OBJ `l`) add edges but no faces. */
#ifndef CB_TOPOLOGY_H
#define CB_TOPOLOGY_H

#include "mesh.h"

typedef struct cb_topology {
  int ne;          /* unique edges */
  int *edge;       /* 2*ne vertex pairs, edge[2e] < edge[2e+1], sorted */
  int nb;          /* boundary edges (one triangle) */
  int *boundary;   /* nb edge indices */
  int np;          /* neighbouring-triangle pairs (interior edges with two triangles) */
  int *pair_tri;   /* 2*np triangle indices, in sorted-triple order */
  int *pair_edge;  /* np: the shared edge */
  int *pair_opp;   /* 2*np: the vertex of each triangle opposite the shared edge */
  int nonmanifold; /* edges shared by more than two triangles */
} cb_topology;

int cb_topology_build(const cb_mesh *m, cb_topology *out);
void cb_topology_free(cb_topology *t);

/* Number of connected components and boundary loops, for Euler's formula on a
 * disk (1 component, 1 loop): #edges = 3 #vertices - 3 - #boundary_edges. */
int cb_topology_components(const cb_mesh *m, const cb_topology *t);
int cb_topology_boundary_loops(const cb_mesh *m, const cb_topology *t);

#endif
