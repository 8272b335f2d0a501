/* Rigidity-matrix DoF counts and the irregular ring disk (rigidity.h). */
#include "rigidity.h"

#include <gsl/gsl_linalg.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <clothbench/status.h>

int cb_rigidity_dofs(int n, const double *x, int nbars, const int *bar) {
  size_t rows = (size_t)3 * n, cols = (size_t)nbars; /* R^T, so that rows >= cols for GSL's SVD */
  if (rows < cols || cols == 0) return cols == 0 ? 3 * n : -1;
  gsl_matrix *R = gsl_matrix_calloc(rows, cols), *V = gsl_matrix_alloc(cols, cols);
  gsl_vector *S = gsl_vector_alloc(cols), *w = gsl_vector_alloc(cols);
  int rank = -1;
  if (R && V && S && w) {
    for (int e = 0; e < nbars; e++) {
      int i = bar[2 * e], j = bar[2 * e + 1];
      for (int a = 0; a < 3; a++) {
        double d = x[3 * i + a] - x[3 * j + a];
        gsl_matrix_set(R, (size_t)(3 * i + a), (size_t)e, d);
        gsl_matrix_set(R, (size_t)(3 * j + a), (size_t)e, -d);
      }
    }
    if (gsl_linalg_SV_decomp(R, V, S, w) == 0) {
      rank = 0;
      for (size_t k = 0; k < cols; k++) rank += gsl_vector_get(S, k) > 1e-9 * gsl_vector_get(S, 0);
    }
  }
  gsl_matrix_free(R);
  gsl_matrix_free(V);
  gsl_vector_free(S);
  gsl_vector_free(w);
  return rank < 0 ? -1 : 3 * n - rank;
}

int cb_ring_disk(int rings, cb_mesh *m) {
  memset(m, 0, sizeof *m);
  if (rings < 1 || rings > 63) return cb_fail("ring disk: 1..63 rings, got %d", rings);
  int nv = 1, nt = 0, cnt[64], start[64];
  cnt[0] = 1;
  start[0] = 0;
  for (int r = 1; r <= rings; r++) {
    cnt[r] = (int)lround(6.5 * r);
    start[r] = nv;
    nv += cnt[r];
    nt += cnt[r] + cnt[r - 1];
  }
  nt -= 1; /* the centre fan has cnt[1] triangles, not cnt[1] + 1 */
  m->nv = nv;
  m->x = calloc((size_t)3 * nv, sizeof(double));
  m->tri = malloc((size_t)3 * nt * sizeof(int));
  if (!m->x || !m->tri) return CB_ENOMEM;
  for (int r = 1; r <= rings; r++)
    for (int k = 0; k < cnt[r]; k++) {
      double a = 2 * 3.14159265358979323846 * (k + 0.37 * (r % 2)) / cnt[r];
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
        m->tri[3 * t] = a0;
        m->tri[3 * t + 1] = b0;
        m->tri[3 * t + 2] = start[r] + (j + 1) % nb;
        j++;
      } else {
        m->tri[3 * t] = a0;
        m->tri[3 * t + 1] = b0;
        m->tri[3 * t + 2] = start[r - 1] + (i + 1) % na;
        i++;
      }
      t++;
    }
  }
  m->nt = t;
  return CB_OK;
}

static int edge_index(int ne, const int *edge, int i, int j) {
  if (i > j) {
    int s = i;
    i = j;
    j = s;
  }
  int lo = 0, hi = ne - 1; /* edges are sorted by (i, j) */
  while (lo <= hi) {
    int mid = (lo + hi) / 2, a = edge[2 * mid], b = edge[2 * mid + 1];
    if (a == i && b == j) return mid;
    if (a < i || (a == i && b < j)) lo = mid + 1;
    else hi = mid - 1;
  }
  return -1;
}

int cb_nonconforming_bars(const cb_mesh *m, const double *x, int ne, const int *edge, double *mid, int **bar,
                          int *nbars) {
  *bar = NULL;
  *nbars = 0;
  for (int e = 0; e < ne; e++)
    for (int a = 0; a < 3; a++) mid[3 * e + a] = 0.5 * (x[3 * edge[2 * e] + a] + x[3 * edge[2 * e + 1] + a]);
  int *b = cb_malloc((size_t)6 * (m->nt > 0 ? m->nt : 1), sizeof(int));
  if (!b) return CB_ENOMEM;
  for (int t = 0; t < m->nt; t++) {
    const int *v = m->tri + 3 * t;
    int e[3] = {edge_index(ne, edge, v[0], v[1]), edge_index(ne, edge, v[1], v[2]), edge_index(ne, edge, v[2], v[0])};
    if (e[0] < 0 || e[1] < 0 || e[2] < 0) {
      free(b);
      return cb_fail("nonconforming: triangle %d has an edge not in the list", t);
    }
    for (int k = 0; k < 3; k++) {
      b[6 * t + 2 * k] = e[k];
      b[6 * t + 2 * k + 1] = e[(k + 1) % 3];
    }
  }
  *bar = b;
  *nbars = 3 * m->nt;
  return CB_OK;
}
