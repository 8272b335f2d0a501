/* Stencil slots (stencil.h): the k x k blocks of each element looked up once
 * in the fixed pattern, so that assembly never searches. */
#include <clothbench/stencil.h>

#include <stdlib.h>
#include <string.h>

#include <clothbench/status.h>

int cb_stencil_init(cb_stencil *s, int k, int ne, const int *vert, const int *free_index) {
  memset(s, 0, sizeof *s);
  if (k < 1 || ne < 0) return cb_fail("stencil: need k >= 1 vertices and ne >= 0 elements (k = %d, ne = %d)", k, ne);
  s->k = k;
  s->ne = ne;
  s->vert = vert;
  s->free_index = free_index;
  size_t n = 2 * (size_t)k * k * (size_t)(ne > 0 ? ne : 1);
  s->slot = cb_malloc(n, sizeof(int));
  if (!s->slot) return CB_ENOMEM;
  for (size_t i = 0; i < n; i++) s->slot[i] = -1;
  return CB_OK;
}

void cb_stencil_free(cb_stencil *s) {
  if (!s) return;
  free(s->slot);
  s->slot = NULL;
}

int cb_stencil_pattern(const cb_stencil *s, cb_pattern *p) {
  for (int e = 0; e < s->ne; e++) {
    const int *v = s->vert + (size_t)e * s->k;
    for (int a = 0; a < s->k; a++)
      for (int b = a + 1; b < s->k; b++) { /* (b, a) by symmetry; diagonal blocks are always there */
        int st = cb_pattern_add(p, s->free_index[v[a]], s->free_index[v[b]]);
        if (st) return st;
      }
  }
  return CB_OK;
}

int cb_stencil_bind(cb_stencil *s, const cb_sparse *A, const char *label) {
  int k = s->k;
  for (int e = 0; e < s->ne; e++) {
    const int *v = s->vert + (size_t)e * k;
    int *q = s->slot + 2 * (size_t)e * k * k;
    for (int a = 0; a < k; a++)
      for (int b = 0; b < k; b++, q += 2) {
        int ba = s->free_index[v[a]], bb = s->free_index[v[b]];
        cb_sparse_block_slot(A, ba, bb, q, q + 1);
        if (ba >= 0 && bb >= 0 && q[0] < 0)
          return cb_fail("%s element %d: block (vertex %d, vertex %d) missing from the sparsity pattern", label, e,
                         v[a], v[b]);
      }
  }
  return CB_OK;
}
