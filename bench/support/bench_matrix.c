#include "bench_matrix.h"

#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <clothbench/status.h>

void cb_bench_matrix_path(const char *dir, int n, char *buf, size_t cap) {
  snprintf(buf, cap, "%s/bench_matrix_%d.bin", dir, n);
}

static void *read_n(FILE *f, size_t n, size_t size) {
  void *p = malloc(n * size + 1);
  if (p && fread(p, size, n, f) != n) {
    free(p);
    return NULL;
  }
  return p;
}

int cb_bench_matrix_read(const char *prog, const char *path, cb_sparse *A) {
  memset(A, 0, sizeof *A);
  FILE *f = fopen(path, "rb");
  if (!f) {
    fprintf(stderr, "%s: cannot open %s (bench_core writes it when CB_BENCH_MATRIX_DIR is set)\n", prog, path);
    return -1;
  }
  int32_t hdr[2];
  if (fread(hdr, sizeof hdr, 1, f) != 1 || hdr[0] <= 0 || hdr[0] % 3 || hdr[1] <= 0) {
    fprintf(stderr, "%s: %s: not a bench_core matrix (bad header)\n", prog, path);
    fclose(f);
    return -1;
  }
  int n = hdr[0], nnz = hdr[1], rc = -1;
  int32_t *ip = read_n(f, (size_t)n + 1, sizeof(int32_t)), *ix = ip ? read_n(f, (size_t)nnz, sizeof(int32_t)) : NULL;
  double *vx = ix ? read_n(f, (size_t)nnz, sizeof(double)) : NULL;
  fclose(f);
  cb_pattern p;
  int have_p = 0;
  if (!vx) {
    fprintf(stderr, "%s: %s: short or unreadable file\n", prog, path);
    goto out;
  }
  if (ip[0] != 0 || ip[n] != nnz) {
    fprintf(stderr, "%s: %s: column pointers do not span the %d entries\n", prog, path, nnz);
    goto out;
  }
  if (cb_pattern_init(&p, n / 3)) {
    fprintf(stderr, "%s: %s\n", prog, cb_error_message());
    goto out;
  }
  have_p = 1;
  for (int j = 0; j < n; j++) {
    if (ip[j + 1] < ip[j]) {
      fprintf(stderr, "%s: %s: column pointers decrease at column %d\n", prog, path, j);
      goto out;
    }
    for (int q = ip[j]; q < ip[j + 1]; q++)
      if (ix[q] < 0 || ix[q] >= n || cb_pattern_add(&p, ix[q] / 3, j / 3)) {
        fprintf(stderr, "%s: %s: bad index at entry %d\n", prog, path, q);
        goto out;
      }
  }
  if (cb_sparse_from_pattern(&p, A)) {
    fprintf(stderr, "%s: %s\n", prog, cb_error_message());
    goto out;
  }
  if (A->nnz != nnz) {
    fprintf(stderr, "%s: %s: not a full 3x3-block pattern (%d entries, blocks hold %d)\n", prog, path, nnz, A->nnz);
    goto out;
  }
  if (memcmp(A->colp, ip, ((size_t)n + 1) * sizeof(int)) || memcmp(A->rowi, ix, (size_t)nnz * sizeof(int))) {
    fprintf(stderr, "%s: %s: entries not in cb_sparse's sorted block layout\n", prog, path);
    goto out;
  }
  memcpy(A->val, vx, (size_t)nnz * sizeof(double));
  rc = 0;
out:
  if (have_p) cb_pattern_free(&p);
  if (rc) cb_sparse_free(A);
  free(ip);
  free(ix);
  free(vx);
  return rc;
}
