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

#if defined(__SSE2__) && !defined(CB_BROADPHASE_SCALAR)
#include <emmintrin.h>
#endif

enum { PARAMS_COOKIE = 0x42505048, MAX_DEPTH = 64 };

/* A box in single precision, each coordinate the double one rounded to
 * nearest (lane 3: lo 0, hi 1, so it never decides a test). Rounding to
 * nearest is monotone: fl(a) < fl(b) implies a < b and fl(a) > fl(b) implies
 * a > b, so a comparison of two float coordinates is the comparison of the
 * doubles unless they are equal (a tie), and then the doubles decide. The
 * float tests therefore give exactly the double tests' answers. */
typedef struct fbox {
  float lo[4], hi[4];
} __attribute__((aligned(16))) fbox;

/* A tree node as the traversal reads it: its box in float (fbox; for the
 * pruning, where a tie counts as an overlap, which only visits more), 48
 * bytes. The double box, for the refit, is in dbox. */
typedef struct node {
  fbox fb;
  double area; /* half surface area of the box: the descent rule and the SAH cost */
  int first;   /* leaf: first slot; internal: index of the left child (the right one is first + 1) */
  int count;   /* leaf: triangles; internal: 0 */
} node;

static void to_fbox(const double *d, fbox *f) {
  for (int k = 0; k < 3; k++) {
    f->lo[k] = (float)d[k];
    f->hi[k] = (float)d[3 + k];
  }
  f->lo[3] = 0.0f;
  f->hi[3] = 1.0f;
}

/* What the candidate code needs of the triangle in one leaf slot, stored in
 * slot order so that a leaf's triangles are read from consecutive memory. */
typedef struct slot_rec {
  int v[3];  /* its vertices */
  int ov[3]; /* the vertices it owns (nov of them) */
  int oe[3]; /* the edges it owns (noe of them) */
  int t;     /* triangle id */
  unsigned char nov, noe;
  unsigned char ek[3]; /* local index k of owned edge oe[m]: it joins v[k] and v[(k + 1) % 3] */
} slot_rec;

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
  double *box;        /* 6*nt: each triangle's box, by triangle id (build scratch) */
  double *sbox;       /* 6*nt: the box of the triangle in each leaf slot (slot order) */
  fbox *fsbox;        /* nt: sbox in float (fbox), slot order */
  float *soa;         /* 6 * stride: sbox in float, structure of arrays (lo x, y, z, hi x, y, z), slot order */
  int stride;         /* nt rounded up, plus 16 lanes of padding the 4-wide loads may read */
  fbox *fvbox;        /* nv: vbox in float */
  fbox *febox;        /* ne: ebox in float */
  slot_rec *rec;      /* nt: the triangle in each leaf slot */
  int *slot;          /* nt: the slot of each triangle */
  double *vbox;       /* 6*nv: each vertex's swept box, grown by d/2 */
  double *ebox;       /* 6*ne: each edge's */
  int boxed;          /* the boxes are set (cb_broadphase_boxes) */
  double *cen;        /* nt: centroid along the split axis during a build */
  int *idx;           /* nt: triangle of each leaf slot (identity before the first build) */
  node *nodes;        /* 2*nt */
  double *dbox;       /* 6 * 2*nt: each node's box in double (fit) */
  int *sv;            /* 3 * stride: the vertices of each slot's triangle, structure of arrays (ring_mask) */
  /* The ring: the primitive pairs of the triangle pairs that share a vertex
   * (their boxes always overlap: both hold the shared vertex's box), listed
   * once at set-up by the ownership rule; a self query tests their boxes in
   * one pass and its traversal leaves these triangle pairs out. */
  int *rvf; /* 2*nrvf: (vertex, triangle) */
  int *ree; /* 2*nree: (edge, edge) */
  long nrvf, nree;
  int nnodes;
  pair *stack; /* traversal and build stack */
  int stack_cap;
  int built, force_rebuild;
  cb_broadphase_stats stats;
};

cb_broadphase_params cb_broadphase_params_default(void) {
  cb_broadphase_params p = {0};
  p.thickness = 0.0;
  p.leaf_size = 8;
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

static const int next3[3] = {1, 2, 0};

typedef struct ilist {
  int *p;
  long n, cap; /* pairs */
} ilist;

static int ilist_add(ilist *l, int u, int v) {
  if (l->n == l->cap) {
    long cap = l->cap ? 2 * l->cap : 1024;
    int *q = cb_realloc(l->p, (size_t)cap, 2 * sizeof(int));
    if (!q) return CB_ENOMEM;
    l->p = q;
    l->cap = cap;
  }
  l->p[2 * l->n] = u;
  l->p[2 * l->n + 1] = v;
  l->n++;
  return CB_OK;
}

static int ring_cmp(const void *a, const void *b) {
  const int *x = a, *y = b;
  if (x[0] != y[0]) return x[0] < y[0] ? -1 : 1;
  return (x[1] > y[1]) - (x[1] < y[1]);
}

/* The ring lists (struct cb_broadphase): for each pair of triangles A < B
 * sharing a vertex, found through each vertex's triangles, the non-adjacent
 * (vertex owned by A, face B), (vertex owned by B, face A) and (edge owned by
 * A, edge owned by B): what the candidate code makes of the pair, less the box
 * tests. Sorted, so that a pass reads the boxes in index order. */
static int build_ring(cb_broadphase *b) {
  int nv = b->nv, nt = b->nt, rc = CB_OK;
  int *start = cb_calloc((size_t)nv + 1, sizeof(int)), *inc = cb_malloc((size_t)3 * nt, sizeof(int));
  int *mark = cb_malloc((size_t)nt, sizeof(int));
  ilist vf = {0}, ee = {0};
  if (!start || !inc || !mark) {
    rc = CB_ENOMEM;
    goto out;
  }
  for (int i = 0; i < 3 * nt; i++) start[b->tri[i] + 1]++;
  for (int v = 0; v < nv; v++) start[v + 1] += start[v];
  for (int t = 0; t < nt; t++) {
    mark[t] = -1;
    for (int k = 0; k < 3; k++) inc[start[b->tri[3 * t + k]]++] = t;
  }
  for (int v = nv; v > 0; v--) start[v] = start[v - 1];
  start[0] = 0;
  for (int A = 0; A < nt && !rc; A++) {
    const int *ta = b->tri + 3 * A;
    unsigned oa = b->own[A];
    for (int k = 0; k < 3 && !rc; k++)
      for (int i = start[ta[k]]; i < start[ta[k] + 1] && !rc; i++) {
        int B = inc[i];
        if (B <= A || mark[B] == A) continue;
        mark[B] = A;
        const int *tb = b->tri + 3 * B;
        unsigned ob = b->own[B];
        for (int m = 0; m < 3 && !rc; m++) {
          int va = ta[m], vb = tb[m];
          if ((oa & (1u << m)) && va != tb[0] && va != tb[1] && va != tb[2]) rc = ilist_add(&vf, va, B);
          if (!rc && (ob & (1u << m)) && vb != ta[0] && vb != ta[1] && vb != ta[2]) rc = ilist_add(&vf, vb, A);
        }
        for (int m = 0; m < 3 && !rc; m++) {
          if (!(oa & (8u << m))) continue;
          int a0 = ta[m], a1 = ta[next3[m]];
          for (int l = 0; l < 3 && !rc; l++) {
            if (!(ob & (8u << l))) continue;
            int b0 = tb[l], b1 = tb[next3[l]];
            if (a0 == b0 || a0 == b1 || a1 == b0 || a1 == b1) continue;
            rc = ilist_add(&ee, b->tri_edge[3 * A + m], b->tri_edge[3 * B + l]);
          }
        }
      }
  }
  if (!rc) {
    if (vf.n) qsort(vf.p, (size_t)vf.n, 2 * sizeof(int), ring_cmp);
    if (ee.n) qsort(ee.p, (size_t)ee.n, 2 * sizeof(int), ring_cmp);
    b->rvf = vf.p;
    b->nrvf = vf.n;
    b->ree = ee.p;
    b->nree = ee.n;
    vf.p = ee.p = NULL;
  }
out:
  free(start);
  free(inc);
  free(mark);
  free(vf.p);
  free(ee.p);
  return rc;
}

/* slot[] and rec[] for the current idx[] */
static void set_slots(cb_broadphase *b) {
  for (int s = 0; s < b->nt; s++) {
    int t = b->idx[s];
    slot_rec *r = b->rec + s;
    unsigned own = b->own[t];
    b->slot[t] = s;
    r->t = t;
    r->nov = r->noe = 0;
    for (int k = 0; k < 3; k++) {
      r->v[k] = b->tri[3 * t + k];
      if (own & (1u << k)) r->ov[r->nov++] = r->v[k];
      if (own & (8u << k)) {
        r->ek[r->noe] = (unsigned char)k;
        r->oe[r->noe++] = b->tri_edge[3 * t + k];
      }
    }
    for (int k = 0; k < 3; k++) b->sv[k * b->stride + s] = r->v[k];
  }
}


/* The float copies of the slot boxes, in slot order (after the boxes, and
 * after a build reorders the slots). */
static void fill_float(cb_broadphase *b) {
  int st = b->stride;
  float *f = b->soa;
  for (int s = 0; s < b->nt; s++) {
    const double *bx = b->sbox + 6 * s;
    fbox *fb = b->fsbox + s;
    to_fbox(bx, fb);
    for (int k = 0; k < 3; k++) {
      f[k * st + s] = fb->lo[k];
      f[(3 + k) * st + s] = fb->hi[k];
    }
  }
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
  b->slot = cb_malloc((size_t)nt, sizeof(int));
  b->sbox = cb_malloc((size_t)nt, 6 * sizeof(double));
  b->rec = cb_calloc((size_t)nt, sizeof(slot_rec));
  b->stride = (nt + 3) / 4 * 4 + 16;
  b->fsbox = cb_calloc_aligned((size_t)nt, sizeof(fbox));
  b->soa = cb_calloc_aligned((size_t)6 * b->stride, sizeof(float));
  b->nodes = cb_calloc_aligned((size_t)2 * nt, sizeof(node));
  b->dbox = cb_malloc((size_t)2 * nt, 6 * sizeof(double));
  b->sv = cb_calloc_aligned((size_t)3 * b->stride, sizeof(int));
  b->stack = cb_malloc((size_t)b->stack_cap, sizeof(pair));
  if (!b->tri || !b->tri_edge || !b->own || !b->box || !b->vbox || !b->cen || !b->idx || !b->nodes || !b->stack ||
      !b->slot || !b->sbox || !b->rec || !b->fsbox || !b->soa || !b->dbox || !b->sv) {
    cb_broadphase_free(b);
    return CB_ENOMEM;
  }
  memcpy(b->tri, tri, (size_t)nt * 3 * sizeof(int));
  int rc = build_topology(b);
  if (rc) {
    cb_broadphase_free(b);
    return rc;
  }
  b->fvbox = cb_calloc_aligned(nv > 0 ? (size_t)nv : 1, sizeof(fbox));
  b->febox = cb_calloc_aligned(b->ne > 0 ? (size_t)b->ne : 1, sizeof(fbox));
  if (!b->fvbox || !b->febox) rc = CB_ENOMEM;
  if (rc || (rc = build_ring(b)) != CB_OK) {
    cb_broadphase_free(b);
    return rc;
  }
  for (int t = 0; t < nt; t++) b->idx[t] = t;
  set_slots(b);
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
  free(b->slot);
  free(b->sbox);
  free(b->fsbox);
  free(b->soa);
  free(b->fvbox);
  free(b->febox);
  free(b->rec);
  free(b->nodes);
  free(b->dbox);
  free(b->sv);
  free(b->rvf);
  free(b->ree);
  free(b->stack);
  free(b);
}

const int *cb_broadphase_edges(const cb_broadphase *b, int *ne) {
  *ne = b->ne;
  return b->edge;
}

void cb_broadphase_invalidate(cb_broadphase *b) { b->force_rebuild = 1; }

int cb_broadphase_set_thickness(cb_broadphase *b, double thickness) {
  if (!(thickness >= 0.0) || !isfinite(thickness))
    return cb_fail("broadphase: thickness %g must be finite and >= 0", thickness);
  b->p.thickness = thickness;
  return CB_OK;
}

const cb_broadphase_stats *cb_broadphase_stats_get(const cb_broadphase *b) { return &b->stats; }

/* ---- the tree ------------------------------------------------------------- */

static double half_area(const double *lo, const double *hi) {
  double dx = hi[0] - lo[0], dy = hi[1] - lo[1], dz = hi[2] - lo[2];
  return dx * dy + dy * dz + dz * dx;
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

/* Every node's box and area from the slot boxes, bottom up (children come
 * after their parent), and the SAH cost (header) of the result. */
static double fit(cb_broadphase *b) {
  double c = 0.0;
  for (int i = b->nnodes - 1; i >= 0; i--) {
    node *nd = b->nodes + i;
    double lo[3], hi[3];
    if (nd->count) {
      const double *bx = b->sbox + 6 * nd->first;
      for (int k = 0; k < 3; k++) {
        lo[k] = bx[k];
        hi[k] = bx[3 + k];
      }
      for (int s = 1; s < nd->count; s++) {
        bx += 6;
        for (int k = 0; k < 3; k++) {
          lo[k] = bx[k] < lo[k] ? bx[k] : lo[k];
          hi[k] = bx[3 + k] > hi[k] ? bx[3 + k] : hi[k];
        }
      }
    } else {
      const double *l = b->dbox + 6 * nd->first, *r = l + 6;
      for (int k = 0; k < 3; k++) {
        lo[k] = l[k] < r[k] ? l[k] : r[k];
        hi[k] = l[3 + k] > r[3 + k] ? l[3 + k] : r[3 + k];
      }
    }
    double *db = b->dbox + 6 * i;
    for (int k = 0; k < 3; k++) {
      db[k] = lo[k];
      db[3 + k] = hi[k];
    }
    to_fbox(db, &nd->fb);
    nd->area = half_area(lo, hi);
    c += nd->area * (nd->count ? nd->count : 1);
  }
  double root = b->nodes[0].area;
  return root > 0.0 ? c / root : (double)b->nnodes;
}

static int build(cb_broadphase *b) {
  /* the boxes by triangle id, then a fresh order */
  for (int s = 0; s < b->nt; s++) memcpy(b->box + 6 * b->idx[s], b->sbox + 6 * s, 6 * sizeof(double));
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
  /* the slot order of the new tree: boxes and records follow */
  for (int s = 0; s < b->nt; s++) memcpy(b->sbox + 6 * s, b->box + 6 * b->idx[s], 6 * sizeof(double));
  set_slots(b);
  fill_float(b);
  b->stats.depth = depth;
  b->stats.nodes = b->nnodes;
  b->stats.rebuilds++;
  b->stats.rebuilt = 1;
  b->stats.sah_built = b->stats.sah_cost = fit(b);
  b->built = 1;
  b->force_rebuild = 0;
  return CB_OK;
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
    to_fbox(bx, b->fvbox + v);
  }
  for (int e = 0; e < b->ne; e++) {
    union_box(b->vbox + 6 * b->edge[2 * e], b->vbox + 6 * b->edge[2 * e + 1], b->ebox + 6 * e);
    to_fbox(b->ebox + 6 * e, b->febox + e);
  }
  for (int s = 0; s < b->nt; s++) {
    const int *v = b->rec[s].v;
    double *bx = b->sbox + 6 * s;
    union_box(b->vbox + 6 * v[0], b->vbox + 6 * v[1], bx);
    union_box(bx, b->vbox + 6 * v[2], bx);
    memcpy(b->box + 6 * b->rec[s].t, bx, 6 * sizeof(double)); /* by triangle id: the ring's VF tests */
  }
  fill_float(b);
  b->boxed = 1;
  return CB_OK;
}

int cb_broadphase_update(cb_broadphase *b, const double *x0, const double *x1) {
  int rc = cb_broadphase_boxes(b, x0, x1);
  if (rc) return rc;
  if (!b->built || b->force_rebuild) return build(b);
  b->stats.rebuilt = 0;
  b->stats.sah_cost = fit(b);
  if (b->stats.sah_cost > b->p.rebuild_ratio * b->stats.sah_built) return build(b);
  return CB_OK;
}

/* ---- candidates of one triangle pair -------------------------------------- */

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

static inline int box_overlap(const double *a, const double *b) {
  return a[0] <= b[3] && b[0] <= a[3] && a[1] <= b[4] && b[1] <= a[4] && a[2] <= b[5] && b[2] <= a[5];
}

/* Whether two nodes' float boxes overlap, a tie counting as an overlap: so a
 * pair of nodes whose double boxes overlap is never pruned (fbox); the answer
 * is data (0 or 1), for a push without a branch. */
static inline int node_overlap(const node *a, const node *b) {
#if defined(__SSE2__) && !defined(CB_BROADPHASE_SCALAR)
  __m128 alo = _mm_load_ps(a->fb.lo), ahi = _mm_load_ps(a->fb.hi), blo = _mm_load_ps(b->fb.lo),
         bhi = _mm_load_ps(b->fb.hi);
  return _mm_movemask_ps(_mm_or_ps(_mm_cmpgt_ps(alo, bhi), _mm_cmpgt_ps(blo, ahi))) == 0;
#else
  int gt = 0;
  for (int k = 0; k < 3; k++) gt |= (a->fb.lo[k] > b->fb.hi[k]) | (b->fb.lo[k] > a->fb.hi[k]);
  return !gt;
#endif
}

/* Box overlap from the float boxes fa, fb, with the double boxes da, db
 * deciding a tie (fbox): the answer of box_overlap(da, db). */
static inline int fbox_overlap(const fbox *fa, const fbox *fb, const double *da, const double *db) {
#if defined(__SSE2__) && !defined(CB_BROADPHASE_SCALAR)
  __m128 alo = _mm_load_ps(fa->lo), ahi = _mm_load_ps(fa->hi), blo = _mm_load_ps(fb->lo), bhi = _mm_load_ps(fb->hi);
  int gt = _mm_movemask_ps(_mm_or_ps(_mm_cmpgt_ps(alo, bhi), _mm_cmpgt_ps(blo, ahi)));
  int eq = _mm_movemask_ps(_mm_or_ps(_mm_cmpeq_ps(alo, bhi), _mm_cmpeq_ps(blo, ahi)));
  /* no branch on the answer (it is data: about a third of the tests pass); a tie is rare */
  if (__builtin_expect(eq != 0, 0)) return !gt && box_overlap(da, db);
  return !gt;
#else
  int gt = 0, eq = 0;
  for (int k = 0; k < 3; k++) {
    gt |= (fa->lo[k] > fb->hi[k]) | (fb->lo[k] > fa->hi[k]);
    eq |= (fa->lo[k] == fb->hi[k]) | (fb->lo[k] == fa->hi[k]);
  }
  if (gt) return 0;
  return !eq || box_overlap(da, db);
#endif
}

/* push(u, v) if ok (0 or 1), without a branch on ok: the pair is written at
 * the end of the list either way and counted only if ok */
static inline void push_if(int *arr, long *n, long cap, int u, int v, int ok) {
  long m = *n;
  if (__builtin_expect(m < cap, 1)) {
    arr[2 * m] = u;
    arr[2 * m + 1] = v;
  }
  *n = m + ok;
}

/* The VF and EE candidates of triangles ra (mesh A, box ba) and rb (mesh B,
 * box bb): the vertices each owns against the other's face, the edges each
 * owns against the other's (header). self: A and B are one mesh, so adjacent
 * pairs are left out and both VF lists are c->vf. */
static inline void pair_cands(const cb_broadphase *A, int s, const cb_broadphase *B, int u, int self,
                              cb_candidates *c) {
  const slot_rec *ra = A->rec + s, *rb = B->rec + u;
  const double *ba = A->sbox + 6 * s, *bb = B->sbox + 6 * u;
  const fbox *fa = A->fsbox + s, *fb = B->fsbox + u;
  /* adjacency and overlap are data, not branches (push_if) */
  for (int k = 0; k < ra->nov; k++) {
    int v = ra->ov[k];
    int adj = self & ((v == rb->v[0]) | (v == rb->v[1]) | (v == rb->v[2]));
    push_if(c->vf, &c->nvf, c->cap_vf, v, rb->t, (!adj) & fbox_overlap(A->fvbox + v, fb, A->vbox + 6 * v, bb));
  }
  for (int k = 0; k < rb->nov; k++) {
    int v = rb->ov[k];
    int adj = self & ((v == ra->v[0]) | (v == ra->v[1]) | (v == ra->v[2]));
    int ok = (!adj) & fbox_overlap(B->fvbox + v, fa, B->vbox + 6 * v, ba);
    if (self) push_if(c->vf, &c->nvf, c->cap_vf, v, ra->t, ok);
    else push_if(c->fv, &c->nfv, c->cap_fv, v, ra->t, ok);
  }
  for (int k = 0; k < ra->noe; k++) {
    int ea = ra->oe[k], a0 = ra->v[ra->ek[k]], a1 = ra->v[next3[ra->ek[k]]];
    const fbox *fea = A->febox + ea;
    for (int l = 0; l < rb->noe; l++) {
      int b0 = rb->v[rb->ek[l]], b1 = rb->v[next3[rb->ek[l]]];
      int adj = self & ((a0 == b0) | (a0 == b1) | (a1 == b0) | (a1 == b1));
      int ok = (!adj) & fbox_overlap(fea, B->febox + rb->oe[l], A->ebox + 6 * ea, B->ebox + 6 * rb->oe[l]);
      push_if(c->ee, &c->nee, c->cap_ee, ea, rb->oe[l], ok);
    }
  }
}

void cb_broadphase_pair_candidates(const cb_broadphase *b, int i, int j, cb_candidates *c) {
  pair_cands(b, b->slot[i], b, b->slot[j], 1, c);
}

/* ---- traversal ------------------------------------------------------------ */

static int share_vertex(const int *a, const int *b) {
  for (int i = 0; i < 3; i++)
    for (int j = 0; j < 3; j++)
      if (a[i] == b[j]) return 1;
  return 0;
}

/* Bit i set: the box of slot s of A overlaps that of slot first + i of B,
 * i < n <= 16 (a leaf). Four slots at a time from B's float SoA boxes; a
 * lane whose floats tie is decided by the doubles (fbox), so the mask is
 * box_overlap's answer exactly. */
static inline unsigned leaf_mask(const cb_broadphase *A, int s, const cb_broadphase *B, int first, int n) {
  unsigned m = 0;
#if defined(__SSE2__) && !defined(CB_BROADPHASE_SCALAR)
  const fbox *f = A->fsbox + s;
  const float *so = B->soa;
  int st = B->stride;
  __m128 lo0 = _mm_set1_ps(f->lo[0]), lo1 = _mm_set1_ps(f->lo[1]), lo2 = _mm_set1_ps(f->lo[2]);
  __m128 hi0 = _mm_set1_ps(f->hi[0]), hi1 = _mm_set1_ps(f->hi[1]), hi2 = _mm_set1_ps(f->hi[2]);
  for (int c = 0; c < n; c += 4) {
    const float *q = so + first + c;
    __m128 blo0 = _mm_loadu_ps(q), blo1 = _mm_loadu_ps(q + st), blo2 = _mm_loadu_ps(q + 2 * st);
    __m128 bhi0 = _mm_loadu_ps(q + 3 * st), bhi1 = _mm_loadu_ps(q + 4 * st), bhi2 = _mm_loadu_ps(q + 5 * st);
    __m128 gt = _mm_or_ps(_mm_or_ps(_mm_or_ps(_mm_cmpgt_ps(lo0, bhi0), _mm_cmpgt_ps(blo0, hi0)),
                                    _mm_or_ps(_mm_cmpgt_ps(lo1, bhi1), _mm_cmpgt_ps(blo1, hi1))),
                          _mm_or_ps(_mm_cmpgt_ps(lo2, bhi2), _mm_cmpgt_ps(blo2, hi2)));
    __m128 eq = _mm_or_ps(_mm_or_ps(_mm_or_ps(_mm_cmpeq_ps(lo0, bhi0), _mm_cmpeq_ps(blo0, hi0)),
                                    _mm_or_ps(_mm_cmpeq_ps(lo1, bhi1), _mm_cmpeq_ps(blo1, hi1))),
                          _mm_or_ps(_mm_cmpeq_ps(lo2, bhi2), _mm_cmpeq_ps(blo2, hi2)));
    unsigned lanes = n - c >= 4 ? 15u : (1u << (n - c)) - 1u;
    unsigned yes = ~(unsigned)_mm_movemask_ps(gt) & lanes, tie = (unsigned)_mm_movemask_ps(eq) & yes;
    while (__builtin_expect(tie != 0, 0)) {
      int i = __builtin_ctz(tie);
      tie &= tie - 1;
      if (!box_overlap(A->sbox + 6 * s, B->sbox + 6 * (first + c + i))) yes &= ~(1u << i);
    }
    m |= yes << c;
  }
#else
  for (int i = 0; i < n; i++) m |= (unsigned)box_overlap(A->sbox + 6 * s, B->sbox + 6 * (first + i)) << i;
#endif
  return m;
}

/* Bit i set: the triangle of slot first + i of A shares a vertex with that
 * of slot s, i < n <= 16. */
static inline unsigned ring_mask(const cb_broadphase *A, int s, int first, int n) {
  unsigned m = 0;
  const int *v = A->rec[s].v;
#if defined(__SSE2__) && !defined(CB_BROADPHASE_SCALAR)
  const int *sv = A->sv + first;
  int st = A->stride;
  __m128i a0 = _mm_set1_epi32(v[0]), a1 = _mm_set1_epi32(v[1]), a2 = _mm_set1_epi32(v[2]);
  for (int c = 0; c < n; c += 4) {
    __m128i eq = _mm_setzero_si128();
    for (int k = 0; k < 3; k++) {
      __m128i u = _mm_loadu_si128((const __m128i *)(sv + k * st + c));
      eq = _mm_or_si128(
          eq, _mm_or_si128(_mm_or_si128(_mm_cmpeq_epi32(u, a0), _mm_cmpeq_epi32(u, a1)), _mm_cmpeq_epi32(u, a2)));
    }
    m |= (unsigned)_mm_movemask_ps(_mm_castsi128_ps(eq)) << c;
  }
  m &= n >= 32 ? ~0u : (1u << n) - 1u;
#else
  for (int i = 0; i < n; i++) {
    const int *u = A->rec[first + i].v;
    int sh = 0;
    for (int k = 0; k < 3; k++) sh |= (u[k] == v[0]) | (u[k] == v[1]) | (u[k] == v[2]);
    m |= (unsigned)sh << i;
  }
#endif
  return m;
}

/* One overlapping triangle pair (slot s of A, slot u of B): its candidates
 * (c != NULL) or a call of visit. */
static inline int emit(const cb_broadphase *A, int s, const cb_broadphase *B, int u, int self, int skip_adjacent,
                       cb_broadphase_visit visit, void *ctx, cb_candidates *c) {
  const slot_rec *ra = A->rec + s, *rb = B->rec + u;
  if (c) {
    pair_cands(A, s, B, u, self, c);
    return 0;
  }
  if (!self) return visit(ctx, ra->t, rb->t);
  if (skip_adjacent && share_vertex(ra->v, rb->v)) return 0;
  return ra->t < rb->t ? visit(ctx, ra->t, rb->t) : visit(ctx, rb->t, ra->t);
}

/* Pairs of nodes (a, b), a == b meaning "pairs within a" (self), on an
 * explicit stack; a pair is pushed only if its boxes overlap. Each pop pushes
 * at most three; descending one side at a time keeps the stack under
 * 3 (depth_a + depth_b) entries. At a pair of leaves, each triangle of one is
 * first tested against the other leaf's box. Inlined into each query with
 * constant self and c == NULL or not, so the candidate code is not a call. */
static inline __attribute__((always_inline)) int traverse(const cb_broadphase *A, const cb_broadphase *B, int self,
                                                          int skip_adjacent, cb_broadphase_visit visit, void *ctx,
                                                          cb_candidates *c) {
  if (!A->built || !B->built) return cb_fail("broadphase: query before the first update");
  pair *st = A->stack;
  int cap = A->stack_cap, sp = 0, rc;
  if (self) st[sp++] = (pair){0, 0};
  else if (node_overlap(A->nodes, B->nodes)) st[sp++] = (pair){0, 0};
  while (sp) {
    pair q = st[--sp];
    const node *na = A->nodes + q.a, *nb = B->nodes + q.b;
    if (self && q.a == q.b) {
      if (na->count) {
        int f = na->first, n = na->count;
        for (int s = f; s < f + n - 1; s++) {
          unsigned m = leaf_mask(A, s, A, f, n) & ~((2u << (s - f)) - 1u); /* the slots after s */
          if (c) m &= ~ring_mask(A, s, f, n); /* the ring pass lists these pairs' candidates */
          while (m) {
            int u = f + __builtin_ctz(m);
            m &= m - 1;
            if ((rc = emit(A, s, A, u, 1, skip_adjacent, visit, ctx, c))) return rc;
          }
        }
        continue;
      }
      if (sp + 3 > cap) return cb_fail_status(CB_ENOMEM, "broadphase: traversal stack exhausted");
      int l = na->first;
      st[sp++] = (pair){l, l};
      st[sp++] = (pair){l + 1, l + 1};
      st[sp] = (pair){l, l + 1}; /* pushed without a branch: kept if the boxes overlap */
      sp += node_overlap(A->nodes + l, A->nodes + l + 1);
      continue;
    }
    /* na and nb overlap */
    if (na->count && nb->count) {
      int ea = na->first + na->count, f = nb->first, n = nb->count;
      for (int s = na->first; s < ea; s++) {
        unsigned m = leaf_mask(A, s, B, f, n);
        if (self && c) m &= ~ring_mask(A, s, f, n);
        while (m) {
          int u = f + __builtin_ctz(m);
          m &= m - 1;
          if ((rc = emit(A, s, B, u, self, skip_adjacent, visit, ctx, c))) return rc;
        }
      }
      continue;
    }
    if (sp + 2 > cap) return cb_fail_status(CB_ENOMEM, "broadphase: traversal stack exhausted");
    /* descend the larger box (or the only internal one) */
    if (nb->count || (!na->count && na->area >= nb->area)) {
      int l = na->first;
      st[sp] = (pair){l, q.b};
      sp += node_overlap(A->nodes + l, nb);
      st[sp] = (pair){l + 1, q.b};
      sp += node_overlap(A->nodes + l + 1, nb);
    } else {
      int l = nb->first;
      st[sp] = (pair){q.a, l};
      sp += node_overlap(na, B->nodes + l);
      st[sp] = (pair){q.a, l + 1};
      sp += node_overlap(na, B->nodes + l + 1);
    }
  }
  return CB_OK;
}

int cb_broadphase_self_pairs(const cb_broadphase *b, int skip_adjacent, cb_broadphase_visit visit, void *ctx) {
  return traverse(b, b, 1, skip_adjacent, visit, ctx, NULL);
}

int cb_broadphase_cross_pairs(const cb_broadphase *a, const cb_broadphase *b, cb_broadphase_visit visit, void *ctx) {
  if (a == b) return cb_fail("broadphase: a cross query needs two trees (use cb_broadphase_self_pairs)");
  return traverse(a, b, 0, 0, visit, ctx, NULL);
}

static int finish(const cb_candidates *c, int rc) {
  if (rc) return rc;
  if (c->nvf > c->cap_vf || c->nfv > c->cap_fv || c->nee > c->cap_ee)
    return cb_fail_status(CB_ENOMEM, "broadphase: candidates exceed the capacity (vf %ld/%ld, fv %ld/%ld, ee %ld/%ld)",
                          c->nvf, c->cap_vf, c->nfv, c->cap_fv, c->nee, c->cap_ee);
  return CB_OK;
}

static inline int dbox_overlap(const double *a, const double *b) {
  return (a[0] <= b[3]) & (b[0] <= a[3]) & (a[1] <= b[4]) & (b[1] <= a[4]) & (a[2] <= b[5]) & (b[2] <= a[5]);
}

/* The candidates of the triangle pairs that share a vertex: the ring lists'
 * pairs whose boxes overlap (double boxes by id; no branch on the answer). */
static void ring_pass(const cb_broadphase *b, cb_candidates *c) {
  const int *p = b->rvf;
  for (long k = 0; k < b->nrvf; k++, p += 2)
    push_if(c->vf, &c->nvf, c->cap_vf, p[0], p[1], dbox_overlap(b->vbox + 6 * p[0], b->box + 6 * p[1]));
  p = b->ree;
  for (long k = 0; k < b->nree; k++, p += 2)
    push_if(c->ee, &c->nee, c->cap_ee, p[0], p[1], dbox_overlap(b->ebox + 6 * p[0], b->ebox + 6 * p[1]));
}

int cb_broadphase_self_candidates(const cb_broadphase *b, cb_candidates *c) {
  c->nvf = c->nfv = c->nee = 0;
  /* triangle pairs sharing a vertex have candidates too (their primitives need
   * not be adjacent): the ring pass lists them, the traversal the others */
  int rc = traverse(b, b, 1, 0, NULL, NULL, c);
  if (!rc) ring_pass(b, c);
  return finish(c, rc);
}

int cb_broadphase_cross_candidates(const cb_broadphase *a, const cb_broadphase *b, cb_candidates *c) {
  c->nvf = c->nfv = c->nee = 0;
  if (a == b) return cb_fail("broadphase: a cross query needs two trees (use cb_broadphase_self_candidates)");
  return finish(c, traverse(a, b, 0, 0, NULL, NULL, c));
}
