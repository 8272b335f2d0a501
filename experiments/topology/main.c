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
#include <gsl/gsl_linalg.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <clothbench/clothbench.h>
#include "experiment.h"
#include "provenance.h"
#include <clothbench/rng.h>
#include "sweep.h"

/* Irregular disk: a centre vertex and rings of round(6.5 r) vertices, each
 * ring zipped to the previous one by angle, so valences vary (5, 6, 7, ...). */
static int ring_disk(int rings, cb_mesh *m) {
  memset(m, 0, sizeof *m);
  int nv = 1, nt = 0, cnt[64], start[64];
  cnt[0] = 1; start[0] = 0;
  for (int r = 1; r <= rings; r++) { cnt[r] = (int)lround(6.5 * r); start[r] = nv; nv += cnt[r]; nt += cnt[r] + cnt[r - 1]; }
  nt -= 1; /* the centre fan has cnt[1] triangles, not cnt[1] + 1 */
  m->nv = nv;
  m->x = calloc((size_t)3 * nv, sizeof(double));
  m->tri = malloc((size_t)3 * nt * sizeof(int));
  if (!m->x || !m->tri) return CB_ENOMEM;
  for (int r = 1; r <= rings; r++)
    for (int k = 0; k < cnt[r]; k++) {
      double a = 2 * M_PI * (k + 0.37 * (r % 2)) / cnt[r];
      m->x[3 * (start[r] + k)] = r * cos(a);
      m->x[3 * (start[r] + k) + 1] = r * sin(a);
    }
  int t = 0;
  for (int r = 1; r <= rings; r++) {
    int na = cnt[r - 1], nb = cnt[r], i = 0, j = 0;
    while (i < na || j < nb) { /* advance on the ring whose next vertex comes first by angle */
      double ai = r == 1 ? 1e9 : (i + 1 + 0.37 * ((r - 1) % 2)) / na, bj = (j + 1 + 0.37 * (r % 2)) / nb;
      int a0 = start[r - 1] + i % na, b0 = start[r] + j % nb;
      if (r == 1 || (j < nb && (i >= na || bj < ai))) {
        if (r == 1 && j >= nb) break;
        m->tri[3 * t] = a0; m->tri[3 * t + 1] = b0; m->tri[3 * t + 2] = start[r] + (j + 1) % nb; j++;
      } else {
        m->tri[3 * t] = a0; m->tri[3 * t + 1] = b0; m->tri[3 * t + 2] = start[r - 1] + (i + 1) % na; i++;
      }
      t++;
    }
  }
  m->nt = t;
  return CB_OK;
}

/* 3#V - rank of the rigidity matrix at positions x. */
static int free_dofs(const cb_mesh *m, const cb_topology *tp, const double *x) {
  size_t rows = (size_t)3 * m->nv, cols = (size_t)tp->ne; /* R^T, so that rows >= cols for GSL's SVD */
  if (rows < cols) return -1;
  gsl_matrix *R = gsl_matrix_calloc(rows, cols), *V = gsl_matrix_alloc(cols, cols);
  gsl_vector *S = gsl_vector_alloc(cols), *w = gsl_vector_alloc(cols);
  for (int e = 0; e < tp->ne; e++) {
    int i = tp->edge[2 * e], j = tp->edge[2 * e + 1];
    for (int a = 0; a < 3; a++) {
      double d = x[3 * i + a] - x[3 * j + a];
      gsl_matrix_set(R, (size_t)(3 * i + a), (size_t)e, d);
      gsl_matrix_set(R, (size_t)(3 * j + a), (size_t)e, -d);
    }
  }
  int rank = -1;
  if (gsl_linalg_SV_decomp(R, V, S, w) == 0) {
    rank = 0;
    for (size_t k = 0; k < cols; k++) rank += gsl_vector_get(S, k) > 1e-9 * gsl_vector_get(S, 0);
  }
  gsl_matrix_free(R); gsl_matrix_free(V); gsl_vector_free(S); gsl_vector_free(w);
  return rank < 0 ? -1 : 3 * m->nv - rank;
}

static void count_row(FILE *f, const char *name, cb_mesh *m, unsigned seed) {
  cb_topology tp;
  if (cb_topology_build(m, &tp)) { fprintf(f, "count,%s,,,%d,%d,,,,,,,,%s\n", name, m->nv, m->nt, "bad_input"); return; }
  double *x = malloc((size_t)3 * m->nv * sizeof *x);
  cb_rng rng = cb_rng_seed(seed);
  double h = 0.3 * sqrt(cb_mesh_triangle_area(m, m->x, 0)); /* about a third of an edge */
  for (int i = 0; i < 3 * m->nv; i++) { /* generic embedding: jitter every coordinate */
    x[i] = m->x[i] + h * (cb_rng_uniform(&rng) - 0.5);
  }
  int dofs = free_dofs(m, &tp, x);
  fprintf(f, "count,%s,,,%d,%d,%d,%d,%d,%d,%d,%d,%d,%s\n", name, m->nv, m->nt, tp.ne, tp.nb, 3 * m->nv - 3 - tp.nb,
          cb_topology_boundary_loops(m, &tp), cb_topology_components(m, &tp), dofs, 3 + tp.nb, dofs < 0 ? "svd_failed" : "ok");
  free(x);
  cb_topology_free(&tp);
}

/* Cells: 0 the lecture's example (T1 and its count), then the grids of both
 * diagonal patterns (T2), then the ring disks. */
typedef struct { int quick, ngrids, nrings; } plan;
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
    for (int k = 0; k < tp.np; k++) fprintf(f, "pair,lecture,%d,%d,,,,,,,,,,ok\n", tp.pair_tri[2 * k], tp.pair_tri[2 * k + 1]);
    count_row(f, "lecture", &m5, 1);
    cb_topology_free(&tp);
    return CB_OK;
  }
  cb_mesh m;
  char name[64];
  if (--i < 2L * p->ngrids) { /* T2: grids */
    int k = (int)i / 2, d = (int)i % 2;
    cb_grid_params g = cb_grid_params_default();
    g.n = sizes[k][0]; g.m = sizes[k][1]; g.diagonal = d ? CB_DIAG_ALTERNATING : CB_DIAG_REGULAR;
    snprintf(name, sizeof name, "grid_%dx%d_%s", g.n, g.m, d ? "alternating" : "regular");
    if (cb_mesh_grid(&g, &m) == CB_OK) count_row(f, name, &m, 7 + (unsigned)k);
  } else { /* irregular disks */
    int rings = (int)(i - 2L * p->ngrids) + 1;
    snprintf(name, sizeof name, "ring_disk_%d", rings);
    if (ring_disk(rings, &m) == CB_OK) count_row(f, name, &m, 100 + (unsigned)rings);
  }
  cb_mesh_free(&m);
  return CB_OK;
}

int main(int argc, char **argv) {
  cb_experiment e;
  int r = cb_experiment_begin(&e, "topology", "T1 and T2: edge lists by sorting triples, Euler's count and the DoFs "
                                              "left when every edge is a hard constraint.", argc, argv);
  if (r) return r > 0 ? 0 : 1;
  plan p = {e.quick, e.quick ? 4 : 6, e.quick ? 3 : 5};
  int st = cb_experiment_table(&e, NULL, "# free_dofs = 3 #vertices - rank(rigidity matrix) at a jittered non-planar embedding (GSL SVD, relative threshold 1e-9)\n",
                               "kind,mesh,i,j,vertices,triangles,edges,boundary_edges,predicted_edges,boundary_loops,components,free_dofs,predicted_dofs,status");
  if (st < 0) return cb_experiment_end(&e, st), 2;
  cb_sweep sw = {"meshes", 1 + 2L * p.ngrids + p.nrings, cell, NULL, &p};
  st = cb_sweep_run(&e, &sw, 1);
  st = cb_experiment_end(&e, st);
  return st == CB_OK ? 0 : st == CB_EIO ? 2 : 1;
}
