/* bench_spmv: times clothbench's matrix-vector products on a matrix written
 * by bench_core (CB_BENCH_MATRIX_DIR), driven by bench/spmv_scipy.py so that
 * its samples interleave with SciPy's on the same matrix.
 *
 *   bench_spmv FILE     reads the CSR file (int32 n, int32 nnz, int32
 *                       indptr[n+1], int32 indices[nnz], float64 data[nnz];
 *                       a symmetric matrix of 3x3 blocks), rebuilds the
 *                       cb_sparse (block pattern from the entries) and its
 *                       upper-block copy, prints "ready <n> <nnz> <bytes>"
 *                       (the symmetric kernel's counted bytes), then for each
 *                       line "K" on stdin runs K products and prints the
 *                       milliseconds per product of the symmetric kernel
 *                       and of the full-storage kernel. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <clothbench/sparse.h>
#include <clothbench/status.h>
#include <clothbench/timer.h>
#include "experiment.h"
#include "provenance.h"
#include <clothbench/timer.h>
#include "support/bench_matrix.h"

int main(int argc, char **argv) {
  if (argc != 2 || !strcmp(argv[1], "--help")) {
    fprintf(argc == 2 ? stdout : stderr, "usage: bench_spmv FILE (see bench/spmv_scipy.py)\n");
    return argc == 2 ? 0 : 1;
  }
  if (cb_runtime_init()) {
    fprintf(stderr, "bench_spmv: %s\n", cb_error_message());
    return 1;
  }
  cb_sparse A;
  if (cb_bench_matrix_read("bench_spmv", argv[1], &A)) return 1;
  int n = A.n, nnz = A.nnz;
  cb_sparse_sym S;
  if (cb_sparse_sym_alloc(&S, &A)) {
    fprintf(stderr, "bench_spmv: %s\n", cb_error_message());
    return 1;
  }
  cb_sparse_sym_fill(&S, &A);
  double *x = malloc((size_t)n * sizeof *x), *y = malloc((size_t)n * sizeof *y), *z = malloc((size_t)n * sizeof *z);
  for (int i = 0; i < n; i++) x[i] = 1.0;
  printf("ready %d %d %zu\n", n, nnz, cb_sparse_sym_matvec_bytes(&S));
  fflush(stdout);
  char line[64];
  while (fgets(line, sizeof line, stdin)) {
    int k = atoi(line);
    if (k <= 0) break;
    double t0 = cb_now_ms();
    for (int q = 0; q < k; q++)
      cb_sparse_sym_matvec(&S, q & 1 ? y : x, q & 1 ? z : y); /* y = A x, z = A y: no growth */
    double sym = (cb_now_ms() - t0) / k;
    t0 = cb_now_ms();
    for (int q = 0; q < k; q++) cb_sparse_matvec(&A, q & 1 ? y : x, q & 1 ? z : y);
    double full = (cb_now_ms() - t0) / k;
    printf("%.6f %.6f\n", sym, full);
    fflush(stdout);
  }
  free(x);
  free(y);
  free(z);
  cb_sparse_sym_free(&S);
  cb_sparse_free(&A);
  return 0;
}
