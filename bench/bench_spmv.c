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
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <clothbench/clothbench.h>
#include "experiment.h"
#include "provenance.h"
#include <clothbench/timer.h>

static void *read_n(FILE *f, size_t n, size_t size, const char *path) {
  void *p = malloc(n * size + 1);
  if (!p || fread(p, size, n, f) != n) {
    fprintf(stderr, "bench_spmv: %s: short or unreadable file\n", path);
    exit(1);
  }
  return p;
}

int main(int argc, char **argv) {
  if (argc != 2 || !strcmp(argv[1], "--help")) {
    fprintf(argc == 2 ? stdout : stderr, "usage: bench_spmv FILE (see bench/spmv_scipy.py)\n");
    return argc == 2 ? 0 : 1;
  }
  if (cb_runtime_init()) { fprintf(stderr, "bench_spmv: %s\n", cb_error_message()); return 1; }
  FILE *f = fopen(argv[1], "rb");
  if (!f) { perror(argv[1]); return 1; }
  int32_t hdr[2];
  if (fread(hdr, sizeof hdr, 1, f) != 1 || hdr[0] <= 0 || hdr[0] % 3 || hdr[1] <= 0) {
    fprintf(stderr, "bench_spmv: %s: not a bench_core matrix (bad header)\n", argv[1]);
    return 1;
  }
  int n = hdr[0], nnz = hdr[1];
  int32_t *ip = read_n(f, (size_t)n + 1, sizeof(int32_t), argv[1]), *ix = read_n(f, (size_t)nnz, sizeof(int32_t), argv[1]);
  double *vx = read_n(f, (size_t)nnz, sizeof(double), argv[1]);
  fclose(f);
  cb_pattern p;
  cb_sparse A;
  if (cb_pattern_init(&p, n / 3)) return 1;
  for (int j = 0; j < n; j++)
    for (int q = ip[j]; q < ip[j + 1]; q++)
      if (ix[q] < 0 || ix[q] >= n || cb_pattern_add(&p, ix[q] / 3, j / 3)) {
        fprintf(stderr, "bench_spmv: %s: bad index at entry %d\n", argv[1], q);
        return 1;
      }
  if (cb_sparse_from_pattern(&p, &A)) { fprintf(stderr, "bench_spmv: %s\n", cb_error_message()); return 1; }
  cb_pattern_free(&p);
  if (A.nnz != nnz) { fprintf(stderr, "bench_spmv: %s: not a full 3x3-block pattern (%d entries, blocks hold %d)\n", argv[1], nnz, A.nnz); return 1; }
  if (memcmp(A.colp, ip, ((size_t)n + 1) * sizeof(int)) || memcmp(A.rowi, ix, (size_t)nnz * sizeof(int))) {
    fprintf(stderr, "bench_spmv: %s: entries not in cb_sparse's sorted block layout\n", argv[1]);
    return 1;
  }
  memcpy(A.val, vx, (size_t)nnz * sizeof(double));
  cb_sparse_sym S;
  if (cb_sparse_sym_alloc(&S, &A)) { fprintf(stderr, "bench_spmv: %s\n", cb_error_message()); return 1; }
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
    for (int q = 0; q < k; q++) cb_sparse_sym_matvec(&S, q & 1 ? y : x, q & 1 ? z : y); /* y = A x, z = A y: no growth */
    double sym = (cb_now_ms() - t0) / k;
    t0 = cb_now_ms();
    for (int q = 0; q < k; q++) cb_sparse_matvec(&A, q & 1 ? y : x, q & 1 ? z : y);
    double full = (cb_now_ms() - t0) / k;
    printf("%.6f %.6f\n", sym, full);
    fflush(stdout);
  }
  free(ip); free(ix); free(vx); free(x); free(y); free(z);
  cb_sparse_sym_free(&S);
  cb_sparse_free(&A);
  return 0;
}
