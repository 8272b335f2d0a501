/* The broad phase of collision detection: which primitive pairs of a triangle
 * mesh (self-contact) or of two meshes (cloth against an obstacle) may come
 * within a distance d of each other during one step x0 -> x1.
 *
 * A bounding volume hierarchy (BVH) over one axis-aligned box a triangle: the
 * box of the triangle's three vertices at x0 and at x1 (the swept box of the
 * linear motion: every point of the moving triangle stays in the convex hull
 * of its six end positions, which the box contains), grown by d/2 on every
 * side (d = "thickness"). Two primitives whose boxes do not overlap cannot
 * come within d of each other during the step (at a common time or not), so
 * the candidates are conservative.
 *
 * Build: median split of the box centroids along the longest axis of their
 * bounds (balanced, depth <= log2(n / leaf) + 2), children of a node stored as
 * a pair after it, so a reverse sweep over the nodes refits the tree bottom up.
 * Each step refits the boxes; when the tree's SAH cost (surface area heuristic:
 * sum over internal nodes of area(node) plus sum over leaves of area(leaf) *
 * primitives, over area(root)) has grown past rebuild_ratio times its value at
 * the last build, the tree is rebuilt. Everything is allocated by
 * cb_broadphase_alloc; an update or query does not call malloc.
 *
 * Candidates. A triangle pair whose boxes overlap yields vertex-face (VF) and
 * edge-edge (EE) pairs. Each vertex and each edge is "owned" by one triangle
 * that contains it (the lowest-numbered one), and a triangle pair (A, B)
 * yields only the VF pairs (vertex owned by A, face B), (vertex owned by B,
 * face A) and the EE pairs (edge owned by A, edge owned by B): every primitive
 * pair comes from exactly one triangle pair, so none is listed twice. A
 * primitive's own swept box lies in the box of each triangle that contains it,
 * so no pair is lost. Adjacent pairs (a vertex of the face, edges sharing a
 * vertex) are left out, and each remaining pair is kept only if the boxes of
 * its two primitives overlap.
 *
 * The tests are exact in double precision; they run on float copies of the
 * boxes (rounded to nearest, so a comparison of two floats is that of the
 * doubles unless the floats are equal, and then the doubles decide), four
 * leaf triangles at a time with SSE2. The triangle pairs that share a vertex
 * (about 70% on a cloth sheet) always overlap; their primitive pairs are
 * listed once at cb_broadphase_alloc, and a self query tests their boxes in
 * one pass instead of visiting them in the tree. */
#ifndef CB_BROADPHASE_H
#define CB_BROADPHASE_H

typedef struct cb_broadphase_params {
  double
      thickness; /* d: pairs closer than d are candidates; boxes grow by d/2 a side, m. Default 0 (touching counts) */
  int leaf_size; /* triangles a leaf holds at most, 1..16. Default 8 */
  double rebuild_ratio; /* rebuild when SAH cost / SAH cost at the last build exceeds it, > 1. Default 1.5 */
  int cookie;           /* set by cb_broadphase_params_default; checked by cb_broadphase_alloc */
} cb_broadphase_params;

cb_broadphase_params cb_broadphase_params_default(void);

typedef struct cb_broadphase cb_broadphase;

/* What one update did. */
typedef struct cb_broadphase_stats {
  int rebuilt;      /* 1 if this update rebuilt the tree, 0 if it refitted */
  long rebuilds;    /* rebuilds since alloc (the first build counts) */
  double sah_cost;  /* SAH cost of the tree now (see above), dimensionless */
  double sah_built; /* SAH cost right after the last build */
  int depth;        /* tree depth (root = 1) */
  int nodes;        /* nodes in use */
} cb_broadphase_stats;

/* A tree over the nt triangles tri (3*nt indices into nv vertices). tri is
 * copied; the mesh's edges are found here (edges are numbered in the order of
 * cb_broadphase_edges). -> CB_EINVAL on an index out of range or a triangle
 * with a repeated vertex, CB_ENOMEM. */
int cb_broadphase_alloc(int nv, int nt, const int *tri, const cb_broadphase_params *p, cb_broadphase **out);
void cb_broadphase_free(cb_broadphase *b);

/* The edges the EE pairs refer to: *ne edges, 2*ne vertex indices (i < j). */
const int *cb_broadphase_edges(const cb_broadphase *b, int *ne);

/* Swept boxes of x0 -> x1 (3*nv each; x1 = NULL: the static boxes of x0),
 * then a refit, or a rebuild (the first update, or when the SAH cost has grown
 * past rebuild_ratio). -> CB_EINVAL (and nothing changed) if a coordinate is
 * NaN or infinite. */
int cb_broadphase_update(cb_broadphase *b, const double *x0, const double *x1);
/* Only the boxes of x0 -> x1 (triangles, vertices, edges), no tree work: for
 * cb_broadphase_pair_candidates under another traversal. -> CB_EINVAL on a
 * coordinate that is not finite. */
int cb_broadphase_boxes(cb_broadphase *b, const double *x0, const double *x1);
/* Forces a rebuild at the next update. */
void cb_broadphase_invalidate(cb_broadphase *b);
/* The thickness d of the next updates (the tree is kept: the next update refits it to the new boxes, or rebuilds
 * it by the SAH rule). -> CB_EINVAL if d < 0 or not finite. */
int cb_broadphase_set_thickness(cb_broadphase *b, double thickness);
const cb_broadphase_stats *cb_broadphase_stats_get(const cb_broadphase *b);

/* Triangle pairs (i < j for a self query) whose boxes overlap, reported to
 * visit(ctx, i, j) in no particular order; a non-zero return stops the query
 * and is returned. skip_adjacent: leave out pairs that share a vertex. */
typedef int (*cb_broadphase_visit)(void *ctx, int i, int j);
int cb_broadphase_self_pairs(const cb_broadphase *b, int skip_adjacent, cb_broadphase_visit visit, void *ctx);
/* Pairs (triangle i of a, triangle j of b) whose boxes overlap. */
int cb_broadphase_cross_pairs(const cb_broadphase *a, const cb_broadphase *b, cb_broadphase_visit visit, void *ctx);

/* Primitive candidates, in arrays the caller allocates at set-up with
 * cb_candidates_alloc. Counts go on past the capacity (so a caller learns how
 * much it needs), but only the first cap_* pairs are stored; a query that
 * overflows returns CB_ENOMEM with a message, and the caller grows the arrays
 * outside the step. */
typedef struct cb_candidates {
  long nvf, nfv, nee;          /* pairs found (may exceed the capacity) */
  long cap_vf, cap_fv, cap_ee; /* capacities, pairs */
  int *vf;                     /* 2*cap_vf: (vertex of a, face of a) for self; (vertex of a, face of b) for cross */
  int *fv;                     /* 2*cap_fv: (vertex of b, face of a); cross queries only */
  int *ee;                     /* 2*cap_ee: (edge of a, edge of a) for self; (edge of a, edge of b) for cross */
} cb_candidates;

int cb_candidates_alloc(long cap_vf, long cap_fv, long cap_ee, cb_candidates *c);
void cb_candidates_free(cb_candidates *c);

/* VF and EE self-contact candidates of the last update's boxes (the update
 * also keeps every vertex's and edge's box). */
int cb_broadphase_self_candidates(const cb_broadphase *b, cb_candidates *c);
/* The candidates of one triangle pair (i, j), i != j, of b's mesh, added to c
 * (its counts are not reset; the caller checks them against the capacity):
 * for a traversal other than this tree's (bench/bench_broadphase.c runs
 * Embree's). Needs the boxes (cb_broadphase_boxes or an update). */
void cb_broadphase_pair_candidates(const cb_broadphase *b, int i, int j, cb_candidates *c);

/* Candidates between mesh a and mesh b (each updated with its own x0 -> x1),
 * e.g. cloth and an obstacle; the pairs within
 * (d_a + d_b) / 2 (the two trees' thicknesses: give both the same d). */
int cb_broadphase_cross_candidates(const cb_broadphase *a, const cb_broadphase *b, cb_candidates *c);

#endif
