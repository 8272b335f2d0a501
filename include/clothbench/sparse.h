/* A symmetric sparse matrix of 3x3 blocks with a pattern fixed at set-up.
 *
 * Storage is compressed sparse column (CSC) holding BOTH triangles, with
 * sorted row indices. Because the matrix is symmetric, the same arrays read as
 * CSR, so the matrix-vector product is a gather (no scatter), and CHOLMOD can
 * use the arrays directly with stype = +1 (it reads the upper triangle only).
 *
 * Energy terms declare which block pairs (bi, bj) they touch; finalising builds
 * the pattern once. A term then asks for the slot of each of its blocks:
 * entry (r, c) of block (bi, bj) lives at val[slot + c*stride + r], because the
 * three columns of block column bj share one pattern. Assembly writes numbers
 * into those slots and never allocates (CHOLMOD's analyse/factorise split
 * applied to our own matrix).
 *
 * A scalar matrix (no block structure: nblk = 0, bcolp = brow = NULL, n any)
 * is the same CSC with one entry per (i, j); CHOLMOD, cb_sparse_matvec and
 * cb_relative_residual read it, the block functions and the iterative solvers
 * do not. Projective dynamics' n x n matrix P is one (pd_matrix.h). */
#ifndef CB_SPARSE_H
#define CB_SPARSE_H

#include <stddef.h>

typedef struct cb_sparse {
  int n;       /* rows = columns = 3 * nblk (any n for a scalar matrix, nblk = 0) */
  int nnz;     /* stored entries (both triangles) */
  int *colp;   /* n+1 column pointers */
  int *rowi;   /* nnz row indices, sorted within each column */
  double *val; /* nnz values */
  int nblk;    /* block rows = block columns */
  int *bcolp;  /* nblk+1: block column pointers into brow */
  int *brow;   /* block row indices, sorted within each block column */
} cb_sparse;

/* Collects block pairs before the pattern is built. */
typedef struct cb_pattern {
  int nblk;
  int n, cap;
  int *ij; /* 2*n block pairs */
} cb_pattern;

int cb_pattern_init(cb_pattern *p, int nblk);
/* Declares block (bi, bj) and, by symmetry, (bj, bi). Negative indices (pinned,
 * eliminated vertices) are ignored. Diagonal blocks are always present. */
int cb_pattern_add(cb_pattern *p, int bi, int bj);
void cb_pattern_free(cb_pattern *p);

/* Builds the CSC pattern (values zeroed). */
int cb_sparse_from_pattern(const cb_pattern *p, cb_sparse *A);
void cb_sparse_free(cb_sparse *A);

/* Slot and stride of block (bi, bj): entry (r, c) is val[slot + c*stride + r].
 * Returns -1 (and slot = -1) if either index is negative or the block is
 * absent. */
int cb_sparse_block_slot(const cb_sparse *A, int bi, int bj, int *slot, int *stride);

/* Index into val of the diagonal entry (i, i), or -1. */
int cb_sparse_diag_index(const cb_sparse *A, int i);

/* Dense copy of diag(d) A diag(d), or of the principal submatrix that map
 * keeps: entry (i, j) goes to out[map[i] * ld + map[j]] when both map values
 * are >= 0 (map NULL keeps every row, d NULL means no scaling). out must be
 * zeroed by the caller; it is row-major with leading dimension ld. */
void cb_sparse_to_dense(const cb_sparse *A, const double *d, const int *map, double *out, size_t ld);

/* y = A x */
void cb_sparse_matvec(const cb_sparse *A, const double *x, double *y);

/* Bytes one matrix-vector product must move (values, block-row indices,
 * block pointers, x once, y once): the numerator of its achieved bandwidth. */
size_t cb_sparse_matvec_bytes(const cb_sparse *A);

/* The upper blocks of a cb_sparse, for the matrix-vector product of the
 * iterative solvers: each block A(bi, bj) with bi <= bj stored once, 9
 * contiguous values row-major, so a product reads about half the bytes of
 * the full matrix. y = A x walks block column bj: y(bj) gathers
 * A(bi,bj)^T x(bi) over the column and is assigned when the column ends, and
 * each off-diagonal block also scatters A(bi,bj) x(bj) into y(bi), bi < bj,
 * a row assigned earlier (columns > bj later add their scatter to y(bj)).
 * The pattern is set by alloc; fill copies the values after each assembly. */
typedef struct cb_sparse_sym {
  int n, nblk, nub; /* nub: stored blocks (upper ones, diagonal included) */
  int *bcolp;       /* nblk+1 pointers into brow */
  int *brow;        /* nub block rows, ascending within a column (the diagonal last) */
  double *val;      /* 9 nub: block k holds val[9k + 3r + c] = A(3 bi + r, 3 bj + c) */
} cb_sparse_sym;

int cb_sparse_sym_alloc(cb_sparse_sym *S, const cb_sparse *A);
void cb_sparse_sym_free(cb_sparse_sym *S);
/* Copies the upper blocks' values from A (whose pattern S was built from). */
void cb_sparse_sym_fill(cb_sparse_sym *S, const cb_sparse *A);
/* y = A x */
void cb_sparse_sym_matvec(const cb_sparse_sym *S, const double *x, double *y);
/* r = b - A x; returns |r|_2. */
double cb_sparse_sym_residual(const cb_sparse_sym *S, const double *b, const double *x, double *r);
/* Bytes one product must move (the same convention as cb_sparse_matvec_bytes):
 * 72 nub (values) + 4 nub (block rows) + 4 (nblk+1) + 16 n (x once, y once). */
size_t cb_sparse_sym_matvec_bytes(const cb_sparse_sym *S);

/* r = b - A x in one pass; returns |r|_2. */
double cb_sparse_residual(const cb_sparse *A, const double *b, const double *x, double *r);

/* Adds the 3x3 row-major block s*H to block (bi, bj) given by (slot, stride). */
static inline void cb_sparse_add_block(double *val, int slot, int stride, const double H[9], double s) {
  if (slot < 0) return;
  for (int c = 0; c < 3; c++)
    for (int r = 0; r < 3; r++) val[slot + c * stride + r] += s * H[3 * r + c];
}

#endif
