/* The broad phase: a BVH over the swept, inflated boxes of a mesh's triangles,
 * and the VF/EE candidates it yields. The method, its conservativeness and the
 * ownership rule that lists each primitive pair once are in
 * include/clothbench/broadphase.h; docs/geometry-broadphase.md has the
 * benchmark against Embree. */
#include <clothbench/broadphase.h>

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include <clothbench/status.h>

enum { PARAMS_COOKIE = 0x42505048, MAX_DEPTH = 64 };

typedef struct node {
  double lo[3], hi[3];
  int first; /* leaf: first slot in idx[]; internal: index of the left child (the right one is first + 1) */
  int count; /* leaf: triangles; internal: 0 */
} node;

typedef struct pair {
  int a, b;
} pair;

struct cb_broadphase {
  cb_broadphase_params p;
  int nv, nt, ne;
  int *tri;           /* 3*nt */
  int *edge;          /* 2*ne, i < j */
  int *tri_edge;      /* 3*nt: edge k of triangle t joins tri[3t+k] and tri[3t+(k+1)%3] */
  unsigned char *own; /* per triangle: bits 0-2 the vertices it owns, bits 3-5 the edges */
  double *box;        /* 6*nt: lo[3], hi[3] of each triangle */
  double *vbox;       /* 6*nv: each vertex's swept box, grown by d/2 */
  double *ebox;       /* 6*ne: each edge's */
  int boxed;          /* the boxes are set (cb_broadphase_boxes) */
  double *cen;        /* nt: centroid along the split axis during a build */
  int *idx;           /* nt: triangle of each leaf slot */
  node *nodes;        /* 2*nt */
  int nnodes;
  pair *stack; /* traversal and build stack */
  int stack_cap;
  int built, force_rebuild;
  cb_broadphase_stats stats;
};

cb_broadphase_params cb_broadphase_params_default(void) {
  cb_broadphase_params p = {0};
  p.thickness = 0.0;
  p.leaf_size = 4;
  p.rebuild_ratio = 1.5;
  p.cookie = PARAMS_COOKIE;
  return p;
}

/* ---- set-up ------------------------------------------------------------- */

static int cmp_edge(const void *a, const void *b) {
  const int *x = a, *y = b;
  if (x[0] != y[0]) return x[0] < y[0] ? -1 : 1;
  if (x[1] != y[1]) return x[1] < y[1] ? -1 : 1;
  return x[2] < y[2] ? -1 : x[2] > y[2];
}

/* The unique edges, each triangle's three edge ids, and the owner bits:
 * vertex v and edge e belong to the lowest-numbered triangle containing them. */
static int build_topology(cb_broadphase *b) {
  int nt = b->nt;
  int *trip = cb_malloc((size_t)3 * nt > 0 ? (size_t)3 * nt : 1, 3 * sizeof(int));
  int *vowner = cb_malloc(b->nv > 0 ? (size_t)b->nv : 1, sizeof(int));
  if (!trip || !vowner) {
    free(trip);
    free(vowner);
    return CB_ENOMEM;
  }
  for (int t = 0; t < nt; t++)
    for (int k = 0; k < 3; k++) {
      int i = b->tri[3 * t + k], j = b->tri[3 * t + (k + 1) % 3];
      int *r = trip + 3 * (3 * t + k);
      r[0] = i < j ? i : j;
      r[1] = i < j ? j : i;
      r[2] = 3 * t + k; /* triangle and local edge */
    }
  qsort(trip, (size_t)3 * nt, 3 * sizeof(int), cmp_edge);
  int ne = 0;
  for (int r = 0; r < 3 * nt; r++)
    if (r == 0 || trip[3 * r] != trip[3 * r - 3] || trip[3 * r + 1] != trip[3 * r - 2]) ne++;
  b->edge = cb_malloc(ne > 0 ? (size_t)ne : 1, 2 * sizeof(int));
  if (!b->edge) {
    free(trip);
    free(vowner);
    return CB_ENOMEM;
  }
  int e = -1;
  for (int r = 0; r < 3 * nt; r++) {
    const int *q = trip + 3 * r;
    int fresh = r == 0 || q[0] != q[-3] || q[1] != q[-2];
    if (fresh) { /* sorted by (i, j, slot): the first of a run is the lowest triangle */
      e++;
      b->edge[2 * e] = q[0];
      b->edge[2 * e + 1] = q[1];
      b->own[q[2] / 3] |= (unsigned char)(8u << (q[2] % 3));
    }
    b->tri_edge[q[2]] = e;
  }
  b->ne = ne;
  b->ebox = cb_malloc(ne > 0 ? (size_t)ne : 1, 6 * sizeof(double));
  if (!b->ebox) {
    free(trip);
    free(vowner);
    return CB_ENOMEM;
  }
  for (int v = 0; v < b->nv; v++) vowner[v] = -1;
  for (int t = 0; t < nt; t++)
    for (int k = 0; k < 3; k++) {
      int v = b->tri[3 * t + k];
      if (vowner[v] < 0) {
        vowner[v] = t;
        b->own[t] |= (unsigned char)(1u << k);
      }
    }
  free(trip);
  free(vowner);
  return CB_OK;
}

int cb_broadphase_alloc(int nv, int nt, const int *tri, const cb_broadphase_params *p, cb_broadphase **out) {
  *out = NULL;
  if (!p || p->cookie != PARAMS_COOKIE)
    return cb_fail("broadphase: parameters not from cb_broadphase_params_default()");
  if (!(p->thickness >= 0.0) || !isfinite(p->thickness))
    return cb_fail("broadphase: thickness %g must be finite and >= 0", p->thickness);
  if (p->leaf_size < 1 || p->leaf_size > 16) return cb_fail("broadphase: leaf_size %d not in 1..16", p->leaf_size);
  if (!(p->rebuild_ratio > 1.0)) return cb_fail("broadphase: rebuild_ratio %g must be > 1", p->rebuild_ratio);
  if (nv < 0 || nt < 1 || !tri || nt > INT32_MAX / 6)
    return cb_fail("broadphase: need at least one triangle (nv %d, nt %d)", nv, nt);
  for (int t = 0; t < nt; t++) {
    const int *v = tri + 3 * t;
    for (int k = 0; k < 3; k++)
      if (v[k] < 0 || v[k] >= nv) return cb_fail("broadphase: triangle %d: vertex %d out of range", t, v[k]);
    if (v[0] == v[1] || v[1] == v[2] || v[0] == v[2])
      return cb_fail("broadphase: triangle %d repeats a vertex (%d %d %d)", t, v[0], v[1], v[2]);
  }
  cb_broadphase *b = cb_calloc(1, sizeof *b);
  if (!b) return CB_ENOMEM;
  b->p = *p;
  b->nv = nv;
  b->nt = nt;
  b->stack_cap = 8 * (MAX_DEPTH + 2);
  b->tri = cb_malloc((size_t)nt, 3 * sizeof(int));
  b->tri_edge = cb_malloc((size_t)nt, 3 * sizeof(int));
  b->own = cb_calloc((size_t)nt, 1);
  b->box = cb_malloc((size_t)nt, 6 * sizeof(double));
  b->vbox = cb_malloc(nv > 0 ? (size_t)nv : 1, 6 * sizeof(double));
  b->cen = cb_malloc((size_t)nt, sizeof(double));
  b->idx = cb_malloc((size_t)nt, sizeof(int));
  b->nodes = cb_malloc((size_t)2 * nt, sizeof(node));
  b->stack = cb_malloc((size_t)b->stack_cap, sizeof(pair));
  if (!b->tri || !b->tri_edge || !b->own || !b->box || !b->vbox || !b->cen || !b->idx || !b->nodes || !b->stack) {
    cb_broadphase_free(b);
    return CB_ENOMEM;
  }
  memcpy(b->tri, tri, (size_t)nt * 3 * sizeof(int));
  int rc = build_topology(b);
  if (rc) {
    cb_broadphase_free(b);
    return rc;
  }
  *out = b;
  return CB_OK;
}

void cb_broadphase_free(cb_broadphase *b) {
  if (!b) return;
  free(b->tri);
  free(b->edge);
  free(b->tri_edge);
  free(b->own);
  free(b->box);
  free(b->vbox);
  free(b->ebox);
  free(b->cen);
  free(b->idx);
  free(b->nodes);
  free(b->stack);
  free(b);
}

const int *cb_broadphase_edges(const cb_broadphase *b, int *ne) {
  *ne = b->ne;
  return b->edge;
}

void cb_broadphase_invalidate(cb_broadphase *b) { b->force_rebuild = 1; }

const cb_broadphase_stats *cb_broadphase_stats_get(const cb_broadphase *b) { return &b->stats; }

/* ---- the tree ------------------------------------------------------------- */

static double half_area(const double *lo, const double *hi) {
  double dx = hi[0] - lo[0], dy = hi[1] - lo[1], dz = hi[2] - lo[2];
  return dx * dy + dy * dz + dz * dx;
}

static void leaf_bounds(const cb_broadphase *b, node *nd) {
  for (int k = 0; k < 3; k++) {
    nd->lo[k] = INFINITY;
    nd->hi[k] = -INFINITY;
  }
  for (int s = nd->first; s < nd->first + nd->count; s++) {
    const double *bx = b->box + 6 * b->idx[s];
    for (int k = 0; k < 3; k++) {
      if (bx[k] < nd->lo[k]) nd->lo[k] = bx[k];
      if (bx[3 + k] > nd->hi[k]) nd->hi[k] = bx[3 + k];
    }
  }
}

/* Reorders idx[lo, hi) so that idx[mid] has the key of rank mid - lo, keys
 * before it <= and after it >= (Hoare's selection, median-of-three pivot). */
static void select_median(int *idx, const double *key, int lo, int hi, int mid) {
  hi--;
  while (hi > lo) {
    int m = lo + (hi - lo) / 2;
    double a = key[idx[lo]], c = key[idx[m]], d = key[idx[hi]];
    double piv = a < c ? (c < d ? c : (a < d ? d : a)) : (a < d ? a : (c < d ? d : c));
    int i = lo, j = hi;
    while (i <= j) {
      while (key[idx[i]] < piv) i++;
      while (key[idx[j]] > piv) j--;
      if (i <= j) {
        int t = idx[i];
        idx[i] = idx[j];
        idx[j] = t;
        i++;
        j--;
      }
    }
    if (mid <= j) hi = j;
    else if (mid >= i) lo = i;
    else return;
  }
}

/* The SAH cost (header) of the current boxes, nodes visited in any order. */
static double sah_cost(const cb_broadphase *b) {
  double root = half_area(b->nodes[0].lo, b->nodes[0].hi), c = 0.0;
  for (int i = 0; i < b->nnodes; i++) {
    const node *nd = b->nodes + i;
    c += half_area(nd->lo, nd->hi) * (nd->count ? nd->count : 1);
  }
  return root > 0.0 ? c / root : (double)b->nnodes;
}

static int build(cb_broadphase *b) {
  for (int i = 0; i < b->nt; i++) b->idx[i] = i;
  b->nnodes = 1;
  b->nodes[0].first = 0;
  b->nodes[0].count = b->nt;
  /* stack of (node, depth); a node's slots are [first, first + count) */
  int sp = 0, depth = 1;
  b->stack[sp++] = (pair){0, 1};
  while (sp) {
    pair top = b->stack[--sp];
    node *nd = b->nodes + top.a;
    if (top.b > depth) depth = top.b;
    leaf_bounds(b, nd);
    if (nd->count <= b->p.leaf_size) continue;
    /* split at the median centroid along the longest axis of the centroids' bounds */
    double clo[3] = {INFINITY, INFINITY, INFINITY}, chi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (int s = nd->first; s < nd->first + nd->count; s++) {
      const double *bx = b->box + 6 * b->idx[s];
      for (int k = 0; k < 3; k++) {
        double c = 0.5 * (bx[k] + bx[3 + k]);
        if (c < clo[k]) clo[k] = c;
        if (c > chi[k]) chi[k] = c;
      }
    }
    int ax = 0;
    for (int k = 1; k < 3; k++)
      if (chi[k] - clo[k] > chi[ax] - clo[ax]) ax = k;
    for (int s = nd->first; s < nd->first + nd->count; s++) {
      const double *bx = b->box + 6 * b->idx[s];
      b->cen[b->idx[s]] = 0.5 * (bx[ax] + bx[3 + ax]);
    }
    int first = nd->first, count = nd->count, mid = first + count / 2;
    select_median(b->idx, b->cen, first, first + count, mid);
    int c = b->nnodes;
    b->nnodes += 2;
    nd->first = c;
    nd->count = 0;
    b->nodes[c] = (node){.first = first, .count = mid - first};
    b->nodes[c + 1] = (node){.first = mid, .count = first + count - mid};
    if (sp + 2 > b->stack_cap || top.b + 1 > MAX_DEPTH)
      return cb_fail_status(CB_ENOMEM, "broadphase: build stack exhausted (depth %d)", top.b + 1);
    b->stack[sp++] = (pair){c, top.b + 1};
    b->stack[sp++] = (pair){c + 1, top.b + 1};
  }
  /* internal bounds: children come after their parent */
  for (int i = b->nnodes - 1; i >= 0; i--) {
    node *nd = b->nodes + i;
    if (nd->count) continue;
    const node *l = b->nodes + nd->first, *r = l + 1;
    for (int k = 0; k < 3; k++) {
      nd->lo[k] = l->lo[k] < r->lo[k] ? l->lo[k] : r->lo[k];
      nd->hi[k] = l->hi[k] > r->hi[k] ? l->hi[k] : r->hi[k];
    }
  }
  b->stats.depth = depth;
  b->stats.nodes = b->nnodes;
  b->stats.rebuilds++;
  b->stats.rebuilt = 1;
  b->stats.sah_built = b->stats.sah_cost = sah_cost(b);
  b->built = 1;
  b->force_rebuild = 0;
  return CB_OK;
}

static void refit(cb_broadphase *b) {
  for (int i = b->nnodes - 1; i >= 0; i--) {
    node *nd = b->nodes + i;
    if (nd->count) {
      leaf_bounds(b, nd);
      continue;
    }
    const node *l = b->nodes + nd->first, *r = l + 1;
    for (int k = 0; k < 3; k++) {
      nd->lo[k] = l->lo[k] < r->lo[k] ? l->lo[k] : r->lo[k];
      nd->hi[k] = l->hi[k] > r->hi[k] ? l->hi[k] : r->hi[k];
    }
  }
  b->stats.rebuilt = 0;
  b->stats.sah_cost = sah_cost(b);
}

static void union_box(const double *a, const double *b, double *out) {
  for (int k = 0; k < 3; k++) {
    out[k] = a[k] < b[k] ? a[k] : b[k];
    out[3 + k] = a[3 + k] > b[3 + k] ? a[3 + k] : b[3 + k];
  }
}

int cb_broadphase_boxes(cb_broadphase *b, const double *x0, const double *x1) {
  for (int i = 0; i < 3 * b->nv; i++)
    if (!isfinite(x0[i]) || (x1 && !isfinite(x1[i])))
      return cb_fail("broadphase: vertex %d: coordinate %d is not finite (%g%s%g)", i / 3, i % 3, x0[i],
                     x1 ? " -> " : "", x1 ? x1[i] : 0.0);
  double d = 0.5 * b->p.thickness; /* half on each box: boxes of pairs within d overlap */
  for (int v = 0; v < b->nv; v++) {
    double *bx = b->vbox + 6 * v;
    for (int k = 0; k < 3; k++) {
      double a = x0[3 * v + k], c = x1 ? x1[3 * v + k] : a;
      bx[k] = (a < c ? a : c) - d;
      bx[3 + k] = (a > c ? a : c) + d;
    }
  }
  for (int e = 0; e < b->ne; e++)
    union_box(b->vbox + 6 * b->edge[2 * e], b->vbox + 6 * b->edge[2 * e + 1], b->ebox + 6 * e);
  for (int t = 0; t < b->nt; t++) {
    const int *v = b->tri + 3 * t;
    double *bx = b->box + 6 * t;
    union_box(b->vbox + 6 * v[0], b->vbox + 6 * v[1], bx);
    union_box(bx, b->vbox + 6 * v[2], bx);
  }
  b->boxed = 1;
  return CB_OK;
}

int cb_broadphase_update(cb_broadphase *b, const double *x0, const double *x1) {
  int rc = cb_broadphase_boxes(b, x0, x1);
  if (rc) return rc;
  if (!b->built || b->force_rebuild) return build(b);
  refit(b);
  if (b->stats.sah_cost > b->p.rebuild_ratio * b->stats.sah_built) return build(b);
  return CB_OK;
}

/* ---- traversal ------------------------------------------------------------ */

static inline int overlap(const double *alo, const double *ahi, const double *blo, const double *bhi) {
  return alo[0] <= bhi[0] && blo[0] <= ahi[0] && alo[1] <= bhi[1] && blo[1] <= ahi[1] && alo[2] <= bhi[2] &&
         blo[2] <= ahi[2];
}

static inline int box_overlap(const double *a, const double *b) { return overlap(a, a + 3, b, b + 3); }

static int share_vertex(const int *a, const int *b) {
  for (int i = 0; i < 3; i++)
    for (int j = 0; j < 3; j++)
      if (a[i] == b[j]) return 1;
  return 0;
}

/* Pairs of nodes (a, b), a == b meaning "pairs within a", on an explicit
 * stack. Each pop pushes at most three; descending one side at a time keeps
 * the stack under 3 (depth_a + depth_b) entries. */
static int traverse(const cb_broadphase *A, const cb_broadphase *B, int skip_adjacent, cb_broadphase_visit visit,
                    void *ctx) {
  if (!A->built || !B->built) return cb_fail("broadphase: query before the first update");
  int self = A == B;
  pair *st = A->stack;
  int cap = A->stack_cap, sp = 0;
  st[sp++] = (pair){0, 0};
  while (sp) {
    pair q = st[--sp];
    const node *na = A->nodes + q.a, *nb = B->nodes + q.b;
    if (self && q.a == q.b) {
      if (na->count) {
        for (int s = na->first; s < na->first + na->count; s++)
          for (int u = s + 1; u < na->first + na->count; u++) {
            int i = A->idx[s], j = A->idx[u];
            if (!box_overlap(A->box + 6 * i, A->box + 6 * j)) continue;
            if (skip_adjacent && share_vertex(A->tri + 3 * i, A->tri + 3 * j)) continue;
            int rc = i < j ? visit(ctx, i, j) : visit(ctx, j, i);
            if (rc) return rc;
          }
        continue;
      }
      if (sp + 3 > cap) return cb_fail_status(CB_ENOMEM, "broadphase: traversal stack exhausted");
      st[sp++] = (pair){na->first, na->first};
      st[sp++] = (pair){na->first + 1, na->first + 1};
      st[sp++] = (pair){na->first, na->first + 1};
      continue;
    }
    if (!overlap(na->lo, na->hi, nb->lo, nb->hi)) continue;
    if (na->count && nb->count) {
      for (int s = na->first; s < na->first + na->count; s++)
        for (int u = nb->first; u < nb->first + nb->count; u++) {
          int i = A->idx[s], j = B->idx[u];
          if (!box_overlap(A->box + 6 * i, B->box + 6 * j)) continue;
          if (self) {
            if (skip_adjacent && share_vertex(A->tri + 3 * i, A->tri + 3 * j)) continue;
            int rc = i < j ? visit(ctx, i, j) : visit(ctx, j, i);
            if (rc) return rc;
          } else {
            int rc = visit(ctx, i, j);
            if (rc) return rc;
          }
        }
      continue;
    }
    if (sp + 2 > cap) return cb_fail_status(CB_ENOMEM, "broadphase: traversal stack exhausted");
    /* descend the larger box (or the only internal one) */
    if (nb->count || (!na->count && half_area(na->lo, na->hi) >= half_area(nb->lo, nb->hi))) {
      st[sp++] = (pair){na->first, q.b};
      st[sp++] = (pair){na->first + 1, q.b};
    } else {
      st[sp++] = (pair){q.a, nb->first};
      st[sp++] = (pair){q.a, nb->first + 1};
    }
  }
  return CB_OK;
}

int cb_broadphase_self_pairs(const cb_broadphase *b, int skip_adjacent, cb_broadphase_visit visit, void *ctx) {
  return traverse(b, b, skip_adjacent, visit, ctx);
}

int cb_broadphase_cross_pairs(const cb_broadphase *a, const cb_broadphase *b, cb_broadphase_visit visit, void *ctx) {
  if (a == b) return cb_fail("broadphase: a cross query needs two trees (use cb_broadphase_self_pairs)");
  return traverse(a, b, 0, visit, ctx);
}

/* ---- primitive candidates ------------------------------------------------- */

int cb_candidates_alloc(long cap_vf, long cap_fv, long cap_ee, cb_candidates *c) {
  memset(c, 0, sizeof *c);
  if (cap_vf < 0 || cap_fv < 0 || cap_ee < 0) return cb_fail("candidates: negative capacity");
  c->vf = cb_malloc((size_t)(cap_vf > 0 ? cap_vf : 1), 2 * sizeof(int));
  c->fv = cb_malloc((size_t)(cap_fv > 0 ? cap_fv : 1), 2 * sizeof(int));
  c->ee = cb_malloc((size_t)(cap_ee > 0 ? cap_ee : 1), 2 * sizeof(int));
  if (!c->vf || !c->fv || !c->ee) {
    cb_candidates_free(c);
    return CB_ENOMEM;
  }
  c->cap_vf = cap_vf;
  c->cap_fv = cap_fv;
  c->cap_ee = cap_ee;
  return CB_OK;
}

void cb_candidates_free(cb_candidates *c) {
  if (!c) return;
  free(c->vf);
  free(c->fv);
  free(c->ee);
  memset(c, 0, sizeof *c);
}

typedef struct cand_ctx {
  const cb_broadphase *a, *b;
  cb_candidates *c;
} cand_ctx;

static inline void push(int *arr, long *n, long cap, int u, int v) {
  if (*n < cap) {
    arr[2 * *n] = u;
    arr[2 * *n + 1] = v;
  }
  (*n)++;
}

/* VF pairs (vertices owned by triangle i of mesh P, face j of mesh Q). */
static void vf_pairs(const cb_broadphase *P, int i, const cb_broadphase *Q, int j, int same_mesh, int *arr, long *n,
                     long cap) {
  unsigned own = P->own[i] & 7u;
  if (!own) return;
  const int *f = Q->tri + 3 * j;
  const double *fb = Q->box + 6 * j;
  for (int k = 0; k < 3; k++) {
    if (!(own & (1u << k))) continue;
    int v = P->tri[3 * i + k];
    if (same_mesh && (v == f[0] || v == f[1] || v == f[2])) continue;
    if (box_overlap(P->vbox + 6 * v, fb)) push(arr, n, cap, v, j);
  }
}

static int cand_visit(void *vctx, int i, int j) {
  cand_ctx *x = vctx;
  const cb_broadphase *A = x->a, *B = x->b;
  int self = A == B;
  cb_candidates *c = x->c;
  vf_pairs(A, i, B, j, self, c->vf, &c->nvf, c->cap_vf);
  if (self) vf_pairs(A, j, A, i, 1, c->vf, &c->nvf, c->cap_vf);
  else vf_pairs(B, j, A, i, 0, c->fv, &c->nfv, c->cap_fv);
  unsigned oa = A->own[i] >> 3, ob = B->own[j] >> 3;
  if (!oa || !ob) return 0;
  for (int k = 0; k < 3; k++) {
    if (!(oa & (1u << k))) continue;
    int ea = A->tri_edge[3 * i + k];
    const int *va = A->edge + 2 * ea;
    const double *ba = A->ebox + 6 * ea;
    for (int l = 0; l < 3; l++) {
      if (!(ob & (1u << l))) continue;
      int eb = B->tri_edge[3 * j + l];
      const int *vb = B->edge + 2 * eb;
      if (self && (va[0] == vb[0] || va[0] == vb[1] || va[1] == vb[0] || va[1] == vb[1])) continue;
      if (box_overlap(ba, B->ebox + 6 * eb)) push(c->ee, &c->nee, c->cap_ee, ea, eb);
    }
  }
  return 0;
}

static int finish(const cb_candidates *c, int rc) {
  if (rc) return rc;
  if (c->nvf > c->cap_vf || c->nfv > c->cap_fv || c->nee > c->cap_ee)
    return cb_fail_status(CB_ENOMEM, "broadphase: candidates exceed the capacity (vf %ld/%ld, fv %ld/%ld, ee %ld/%ld)",
                          c->nvf, c->cap_vf, c->nfv, c->cap_fv, c->nee, c->cap_ee);
  return CB_OK;
}

void cb_broadphase_pair_candidates(const cb_broadphase *b, int i, int j, cb_candidates *c) {
  cand_ctx x = {b, b, c};
  cand_visit(&x, i, j);
}

int cb_broadphase_self_candidates(const cb_broadphase *b, cb_candidates *c) {
  c->nvf = c->nfv = c->nee = 0;
  cand_ctx x = {b, b, c};
  /* adjacent triangle pairs are visited: their primitives need not be adjacent */
  return finish(c, traverse(b, b, 0, cand_visit, &x));
}

int cb_broadphase_cross_candidates(const cb_broadphase *a, const cb_broadphase *b, cb_candidates *c) {
  c->nvf = c->nfv = c->nee = 0;
  if (a == b) return cb_fail("broadphase: a cross query needs two trees (use cb_broadphase_self_candidates)");
  cand_ctx x = {a, b, c};
  return finish(c, traverse(a, b, 0, cand_visit, &x));
}
