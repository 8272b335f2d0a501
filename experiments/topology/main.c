/* topology: the lecture's topological construction and Euler count (T1, T2).
 *
 * T1: the 5-vertex example of the "Topological Construction" slide, through
 *     cb_topology_build (sorting edge triples): its edge list and its
 *     neighbouring-triangle pairs, one row each.
 * T2: for grids (both diagonal patterns) and irregular ring disks, the counts
 *     of vertices, edges and boundary edges against #E = 3#V - 3 - #B, and the
 *     degrees of freedom left if every edge were a hard constraint, measured as
 *     3#V - rank(R) where R is the rigidity matrix (row e = d/dx of |x_i - x_j|
 *     up to scale: x_ij^T at i, -x_ij^T at j), computed by GSL's SVD at a
 *     generic, non-planar embedding (the flat one has extra out-of-plane flexes),
 *     against the lecture's 3 + #B. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <clothbench/mesh.h>
#include <clothbench/status.h>
#include <clothbench/topology.h>
#include "csv.h"
#include "experiment.h"
#include "provenance.h"
#include "rigidity.h"
#include "rng.h"
#include "sweep.h"

static void count_row(FILE *f, const char *name, cb_mesh *m, unsigned seed) {
  cb_topology tp;
  if (cb_topology_build(m, &tp)) {
    fprintf(f, "count,%s,,,%d,%d,,,,,,,,%s\n", name, m->nv, m->nt, "bad_input");
    return;
  }
  double *x = malloc((size_t)3 * m->nv * sizeof *x);
  cb_rng rng = cb_rng_seed(seed);
  double h = 0.3 * sqrt(cb_mesh_triangle_area(m, m->x, 0)); /* about a third of an edge */
  for (int i = 0; i < 3 * m->nv; i++) {                     /* generic embedding: jitter every coordinate */
    x[i] = m->x[i] + h * (cb_rng_uniform(&rng) - 0.5);
  }
  int dofs = cb_rigidity_dofs(m->nv, x, tp.ne, tp.edge); /* lib/instruments/rigidity.c */
  cb_csv_printf(f, "count,%s,,,%d,%d,%d,%d,%d,%d,%d,%.17g,%d,%s\n", name, m->nv, m->nt, tp.ne, tp.nb,
                3 * m->nv - 3 - tp.nb, cb_topology_boundary_loops(m, &tp), cb_topology_components(m, &tp),
                dofs < 0 ? cb_csv_na() : dofs, 3 + tp.nb,
                dofs < 0 ? "svd_failed" : "ok"); /* free_dofs empty when the SVD failed */
  free(x);
  cb_topology_free(&tp);
}

/* Cells: 0 the lecture's example (T1 and its count), then the grids of both
 * diagonal patterns (T2), then the ring disks. */
typedef struct {
  int quick, ngrids, nrings;
} plan;
static const int sizes[][2] = {{2, 2}, {3, 3}, {4, 3}, {5, 5}, {8, 6}, {10, 10}};

static int cell(long i, void *ctx, FILE *const *out) {
  const plan *p = ctx;
  FILE *f = out[0];
  if (i == 0) { /* T1: the lecture's example, triangle list {1,2,3, 0,1,3, 0,3,4} */
    double x5[15] = {0, 0, 0, 1, 0, 0, 2, 1, 0, 1, 1, 0, 0, 1, 0};
    int t5[9] = {1, 2, 3, 0, 1, 3, 0, 3, 4};
    cb_mesh m5 = {.nv = 5, .nt = 3, .x = x5, .tri = t5};
    cb_topology tp;
    int st = cb_topology_build(&m5, &tp);
    if (st) return st;
    for (int k = 0; k < tp.ne; k++) fprintf(f, "edge,lecture,%d,%d,,,,,,,,,,ok\n", tp.edge[2 * k], tp.edge[2 * k + 1]);
    for (int k = 0; k < tp.np; k++)
      fprintf(f, "pair,lecture,%d,%d,,,,,,,,,,ok\n", tp.pair_tri[2 * k], tp.pair_tri[2 * k + 1]);
    count_row(f, "lecture", &m5, 1);
    cb_topology_free(&tp);
    return CB_OK;
  }
  cb_mesh m;
  char name[64];
  if (--i < 2L * p->ngrids) { /* T2: grids */
    int k = (int)i / 2, d = (int)i % 2;
    cb_grid_params g = cb_grid_params_default();
    g.n = sizes[k][0];
    g.m = sizes[k][1];
    g.diagonal = d ? CB_DIAG_ALTERNATING : CB_DIAG_REGULAR;
    snprintf(name, sizeof name, "grid_%dx%d_%s", g.n, g.m, d ? "alternating" : "regular");
    if (cb_mesh_grid(&g, &m) == CB_OK) count_row(f, name, &m, 7 + (unsigned)k);
  } else { /* irregular disks */
    int rings = (int)(i - 2L * p->ngrids) + 1;
    snprintf(name, sizeof name, "ring_disk_%d", rings);
    if (cb_ring_disk(rings, &m) == CB_OK) count_row(f, name, &m, 100 + (unsigned)rings);
  }
  cb_mesh_free(&m);
  return CB_OK;
}

int main(int argc, char **argv) {
  cb_experiment e;
  int r = cb_experiment_begin(&e, "topology",
                              "T1 and T2: edge lists by sorting triples, Euler's count and the DoFs "
                              "left when every edge is a hard constraint.",
                              argc, argv);
  if (r) return r > 0 ? 0 : 1;
  /* smoke: the lecture's example, the 2x2 grid of each diagonal pattern, one ring */
  plan p = {e.quick, e.smoke ? 1 : e.quick ? 4 : 6, e.smoke ? 1 : e.quick ? 3 : 5};
  int st = cb_experiment_table(&e, NULL,
                               "# free_dofs = 3 #vertices - rank(rigidity matrix) at a jittered non-planar embedding "
                               "(GSL SVD, relative threshold 1e-9)\n",
                               "kind,mesh,i,j,vertices,triangles,edges,boundary_edges,predicted_edges,boundary_loops,"
                               "components,free_dofs,predicted_dofs,status");
  if (st < 0) return cb_experiment_end(&e, st), 2;
  cb_sweep sw = {"meshes", 1 + 2L * p.ngrids + p.nrings, cell, NULL, &p, NULL};
  st = cb_sweep_run(&e, &sw, 1);
  st = cb_experiment_end(&e, st);
  return st == CB_OK ? 0 : st == CB_EIO ? 2 : 1;
}
