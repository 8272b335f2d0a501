/* The broad phase before this branch's changes (bp_old.c), for
 * bench_broadphase's interleaved old-against-new rows. The same semantics as
 * include/clothbench/broadphase.h; parameters from cb_broadphase_params_default. */
#ifndef CB_BENCH_BP_OLD_H
#define CB_BENCH_BP_OLD_H

#include <clothbench/broadphase.h>

typedef struct cb_oldbp cb_oldbp;
int cb_oldbp_alloc(int nv, int nt, const int *tri, const cb_broadphase_params *p, cb_oldbp **out);
void cb_oldbp_free(cb_oldbp *b);
const int *cb_oldbp_edges(const cb_oldbp *b, int *ne);
void cb_oldbp_invalidate(cb_oldbp *b);
const cb_broadphase_stats *cb_oldbp_stats_get(const cb_oldbp *b);
int cb_oldbp_boxes(cb_oldbp *b, const double *x0, const double *x1);
int cb_oldbp_update(cb_oldbp *b, const double *x0, const double *x1);
int cb_oldbp_self_pairs(const cb_oldbp *b, int skip_adjacent, cb_broadphase_visit visit, void *ctx);
int cb_oldbp_cross_pairs(const cb_oldbp *a, const cb_oldbp *b, cb_broadphase_visit visit, void *ctx);
void cb_oldbp_pair_candidates(const cb_oldbp *b, int i, int j, cb_candidates *c);
int cb_oldbp_self_candidates(const cb_oldbp *b, cb_candidates *c);
int cb_oldbp_cross_candidates(const cb_oldbp *a, const cb_oldbp *b, cb_candidates *c);

#endif
