/* The Newton matrices bench_core exports (CB_BENCH_MATRIX_DIR) for the
 * programs that compare against other codes on the same matrix
 * (bench_spmv, bench_peers): reading them back into a cb_sparse. */
#ifndef CB_BENCH_MATRIX_H
#define CB_BENCH_MATRIX_H

#include <clothbench/sparse.h>

/* Reads path (int32 n, int32 nnz, int32 indptr[n+1], int32 indices[nnz],
 * float64 data[nnz]: the CSC = CSR of a symmetric matrix of 3x3 blocks) and
 * rebuilds the cb_sparse with the same entries in the same order (the block
 * pattern from the entries). Returns 0, or -1 after a message on stderr
 * prefixed by prog (unreadable, short, bad header or index, not cb_sparse's
 * full sorted 3x3-block layout). */
int cb_bench_matrix_read(const char *prog, const char *path, cb_sparse *A);

/* "<dir>/bench_matrix_<n>.bin" into buf. */
void cb_bench_matrix_path(const char *dir, int n, char *buf, size_t cap);

#endif
