/* bench_broadphase: the broad and narrow phase of one step of self-contact on
 * a folded sheet, with our BVH (lib/core/geometry/broadphase.c) and with
 * Embree's rtcCollide over user geometry, and the exact intersection check
 * (make bench; docs/geometry-broadphase.md).
 *
 * The scene. An n x n grid of unit side (spacing h = 1/(n-1)) folded onto
 * itself: the first half flat at z = 0, a half-circle fold of radius h/4, and
 * the second half back over the first at height 2r = h/2, pressed down by a
 * bump A(x, t) = 0.45 h sin^2(pi x) sin^2(pi t) (t in [0, 1] along the top
 * half) so that the gap runs from h/2 down to 0.05 h. The step moves the top
 * half down by 0.02 h (x0 -> x1). Contact distance d = 0.2 h. At n = 256:
 * 130 050 triangles.
 *
 * Broad phase: the swept boxes of x0 -> x1 grown by d/2, triangle pairs whose
 * boxes overlap, and from them the VF and EE pairs (each once, adjacent ones
 * left out, each kept only if its primitives' boxes overlap:
 * cb_broadphase_pair_candidates, shared by both traversals). Variants, in
 * interleaved rounds on one core:
 *   bvh_refit     our tree refitted (the steady state of a run)
 *   bvh_build     our tree rebuilt every step
 *   bvh_old_refit the code before the float boxes and the ring lists
 *                 (bench/support/bp_old.c), refitted: old against new in
 *                 one run, interleaved
 *   embree_build  an Embree scene of user primitives (the same boxes, rounded
 *                 outwards to float) built every step, build quality low
 *   embree_refit  the same scene committed with build quality refit
 * Narrow phase: the distance at x1 of every VF pair (point-triangle) and EE
 * pair (segment-segment); a contact is a pair closer than d. The candidates
 * per contact say how much the broad phase over-reports.
 *
 * The intersection check (cb_intersections_count: static boxes, exact
 * triangle-triangle test) on the folded sheet, and on the same sheet pressed
 * through itself (bump 0.7 h: the top half crosses z = 0), at n = 101 (20 000
 * triangles) and at n = 256.
 *
 * Times: wall clock (broad_ms, narrow_ms) and this thread's CPU time
 * (broad_cpu_ms, narrow_cpu_ms: leaves out the time the process waits for a
 * shared core). same_as_old: 1 if the method's VF and EE sets (EE pairs
 * unordered) equal bvh_old_refit's, compared sorted after the last round.
 *
 * Output: results/bench_broadphase.csv, one row per (mesh, method). */
#include <embree3/rtcore.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "support/bp_old.h"

#include "csv.h"
#include "experiment.h"
#include "intersections.h"
#include "provenance.h"
#include "stats.h"
#include <clothbench/broadphase.h>
#include <clothbench/mesh.h>
#include <clothbench/status.h>
#include <clothbench/timer.h>
#include <clothbench/timer.h>

#define PI 3.14159265358979323846

/* ---- the folded sheet ---- */

static int folded_sheet(int n, double bump, cb_mesh *m, double **x1) {
  cb_grid_params gp = cb_grid_params_default();
  gp.n = gp.m = n;
  gp.plane = CB_PLANE_XY;
  gp.size[0] = gp.size[1] = 1.0;
  if (cb_mesh_grid(&gp, m)) return -1;
  double h = 1.0 / (n - 1), r = h / 4, L1 = 0.5 - PI * r / 2, L2 = L1 + PI * r;
  *x1 = malloc(sizeof(double) * 3 * (size_t)m->nv);
  if (!*x1) return -1;
  for (int j = 0; j < n; j++)
    for (int i = 0; i < n; i++) {
      double x = i * h, s = j * h, *p = m->x + 3 * (j * n + i), *q = *x1 + 3 * (j * n + i);
      if (s <= L1) {
        p[0] = x, p[1] = s, p[2] = 0;
      } else if (s <= L2) {
        double phi = (s - L1) / r;
        p[0] = x, p[1] = L1 + r * sin(phi), p[2] = r - r * cos(phi);
      } else {
        double t = (s - L2) / (1.0 - L2), w = sin(PI * x) * sin(PI * x) * sin(PI * t) * sin(PI * t);
        p[0] = x, p[1] = L1 - (s - L2), p[2] = 2 * r - bump * h * w;
      }
      q[0] = p[0], q[1] = p[1], q[2] = p[2] - (s > L2 ? 0.02 * h : 0.0);
    }
  return 0;
}

/* ---- the narrow phase: distances at x1 ---- */

static double dot(const double *a, const double *b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
static void sub(const double *a, const double *b, double *c) {
  c[0] = a[0] - b[0], c[1] = a[1] - b[1], c[2] = a[2] - b[2];
}
static double clamp01(double t) { return t < 0 ? 0 : t > 1 ? 1 : t; }

/* squared distance from p to triangle abc: the closest point by Voronoi
 * region of the triangle (vertex, edge or face), from the dot products of the
 * edges with p - vertex */
static double point_tri2(const double *p, const double *a, const double *b, const double *c) {
  double ab[3], ac[3], ap[3], bp[3], cp[3], q[3];
  sub(b, a, ab), sub(c, a, ac), sub(p, a, ap);
  double d1 = dot(ab, ap), d2 = dot(ac, ap);
  if (d1 <= 0 && d2 <= 0) return dot(ap, ap); /* vertex a */
  sub(p, b, bp);
  double d3 = dot(ab, bp), d4 = dot(ac, bp);
  if (d3 >= 0 && d4 <= d3) return dot(bp, bp); /* vertex b */
  double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) { /* edge ab */
    double v = d1 / (d1 - d3);
    for (int k = 0; k < 3; k++) q[k] = ap[k] - v * ab[k];
    return dot(q, q);
  }
  sub(p, c, cp);
  double d5 = dot(ab, cp), d6 = dot(ac, cp);
  if (d6 >= 0 && d5 <= d6) return dot(cp, cp); /* vertex c */
  double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) { /* edge ac */
    double w = d2 / (d2 - d6);
    for (int k = 0; k < 3; k++) q[k] = ap[k] - w * ac[k];
    return dot(q, q);
  }
  double va = d3 * d6 - d5 * d4;
  if (va <= 0 && d4 - d3 >= 0 && d5 - d6 >= 0) { /* edge bc */
    double w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
    for (int k = 0; k < 3; k++) q[k] = bp[k] - w * (c[k] - b[k]);
    return dot(q, q);
  }
  double den = 1.0 / (va + vb + vc), v = vb * den, w = vc * den; /* face */
  for (int k = 0; k < 3; k++) q[k] = ap[k] - v * ab[k] - w * ac[k];
  return dot(q, q);
}

/* squared distance between segments p1q1 and p2q2: minimise over (s, t) in
 * [0, 1]^2, the unconstrained optimum clamped, then t's optimum for that s and
 * s re-clamped */
static double seg_seg2(const double *p1, const double *q1, const double *p2, const double *q2) {
  double d1[3], d2[3], r[3];
  sub(q1, p1, d1), sub(q2, p2, d2), sub(p1, p2, r);
  double a = dot(d1, d1), e = dot(d2, d2), f = dot(d2, r), s, t;
  const double tiny = 1e-300;
  if (a <= tiny && e <= tiny) return dot(r, r);
  if (a <= tiny) {
    s = 0, t = clamp01(f / e);
  } else {
    double c = dot(d1, r);
    if (e <= tiny) {
      t = 0, s = clamp01(-c / a);
    } else {
      double b = dot(d1, d2), den = a * e - b * b;
      s = den > 0 ? clamp01((b * f - c * e) / den) : 0;
      t = (b * s + f) / e;
      if (t < 0) t = 0, s = clamp01(-c / a);
      else if (t > 1) t = 1, s = clamp01((b - c) / a);
    }
  }
  double w[3];
  for (int k = 0; k < 3; k++) w[k] = r[k] + s * d1[k] - t * d2[k];
  return dot(w, w);
}

static void narrow(const cb_mesh *m, const int *E, const cb_candidates *c, const double *x, double d, long *cvf,
                   long *cee) {
  double d2 = d * d;
  long a = 0, b = 0;
  for (long k = 0; k < c->nvf; k++) {
    const int *t = m->tri + 3 * c->vf[2 * k + 1];
    a += point_tri2(x + 3 * c->vf[2 * k], x + 3 * t[0], x + 3 * t[1], x + 3 * t[2]) < d2;
  }
  for (long k = 0; k < c->nee; k++) {
    const int *e = E + 2 * c->ee[2 * k], *f = E + 2 * c->ee[2 * k + 1];
    b += seg_seg2(x + 3 * e[0], x + 3 * e[1], x + 3 * f[0], x + 3 * f[1]) < d2;
  }
  *cvf = a, *cee = b;
}

/* ---- Embree ---- */

typedef struct emb {
  RTCDevice dev;
  RTCScene scene;
  RTCGeometry geom;
  const cb_mesh *m;
  const double *x0, *x1;
  double half; /* d/2 */
  const cb_broadphase *bp;
  cb_candidates *c;
  long pairs, both_orders;
} emb;

static float down(double v) {
  float f = (float)v;
  return (double)f > v ? nextafterf(f, -INFINITY) : f;
}
static float up(double v) {
  float f = (float)v;
  return (double)f < v ? nextafterf(f, INFINITY) : f;
}

static void emb_bounds(const struct RTCBoundsFunctionArguments *args) {
  const emb *e = args->geometryUserPtr;
  const int *t = e->m->tri + 3 * args->primID;
  double lo[3], hi[3];
  for (int k = 0; k < 3; k++) {
    lo[k] = INFINITY, hi[k] = -INFINITY;
    for (int c = 0; c < 3; c++) {
      double a = e->x0[3 * t[c] + k], b = e->x1[3 * t[c] + k];
      lo[k] = fmin(lo[k], fmin(a, b)), hi[k] = fmax(hi[k], fmax(a, b));
    }
  }
  struct RTCBounds *o = args->bounds_o;
  o->lower_x = down(lo[0] - e->half), o->lower_y = down(lo[1] - e->half), o->lower_z = down(lo[2] - e->half);
  o->upper_x = up(hi[0] + e->half), o->upper_y = up(hi[1] + e->half), o->upper_z = up(hi[2] + e->half);
}

/* rtcCollide of a scene with itself reports each overlapping pair in both
 * orders (i, j) and (j, i), and (i, i): the pairs i < j are kept */
static void emb_collide(void *user, struct RTCCollision *col, unsigned int n) {
  emb *e = user;
  for (unsigned int k = 0; k < n; k++) {
    int i = (int)col[k].primID0, j = (int)col[k].primID1;
    if (i >= j) {
      e->both_orders += i > j;
      continue;
    }
    e->pairs++;
    cb_broadphase_pair_candidates(e->bp, i, j, e->c);
  }
}

static int emb_init(emb *e, const cb_mesh *m, const cb_broadphase *bp, double d) {
  memset(e, 0, sizeof *e);
  e->dev = rtcNewDevice("threads=1,set_affinity=0,verbose=0");
  if (!e->dev) return -1;
  e->m = m, e->bp = bp, e->half = 0.5 * d;
  return 0;
}

/* builds (refit = 0: a new scene, quality low) or refits the scene */
static int emb_commit(emb *e, int refit) {
  if (!refit || !e->scene) {
    if (e->scene) rtcReleaseScene(e->scene);
    e->scene = rtcNewScene(e->dev);
    rtcSetSceneBuildQuality(e->scene, RTC_BUILD_QUALITY_LOW);
    e->geom = rtcNewGeometry(e->dev, RTC_GEOMETRY_TYPE_USER);
    rtcSetGeometryUserPrimitiveCount(e->geom, (unsigned)e->m->nt);
    rtcSetGeometryUserData(e->geom, e);
    rtcSetGeometryBoundsFunction(e->geom, emb_bounds, NULL);
    rtcSetGeometryBuildQuality(e->geom, refit ? RTC_BUILD_QUALITY_REFIT : RTC_BUILD_QUALITY_LOW);
    rtcCommitGeometry(e->geom);
    rtcAttachGeometry(e->scene, e->geom);
    rtcReleaseGeometry(e->geom);
  } else {
    rtcCommitGeometry(e->geom);
  }
  rtcCommitScene(e->scene);
  return rtcGetDeviceError(e->dev) == RTC_ERROR_NONE ? 0 : -1;
}

static void emb_free(emb *e) {
  if (e->scene) rtcReleaseScene(e->scene);
  if (e->dev) rtcReleaseDevice(e->dev);
}

/* ---- one variant's step ---- */

enum { BVH_REFIT, BVH_BUILD, EMB_BUILD, EMB_REFIT, BVH_OLD, NMETHOD };
static const char *method_name[NMETHOD] = {"bvh_refit", "bvh_build", "embree_build", "embree_refit", "bvh_old_refit"};

typedef struct result {
  double broad[32], narrow[32], broad_cpu[32], narrow_cpu[32];
  long vf, ee, cvf, cee, tri_pairs, rebuilds;
  int status, same; /* same: the candidate sets equal bvh_old_refit's (-1: not compared) */
} result;

static double cpu_ms(void) {
  struct timespec t;
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return 1e3 * (double)t.tv_sec + 1e-6 * (double)t.tv_nsec;
}

static int run_variant(int method, int round, const cb_mesh *m, const double *x0, const double *x1, double d,
                       cb_broadphase *bp, cb_oldbp *ob, emb *e, cb_candidates *c, result *r) {
  double t0 = cb_now_ms(), u0 = cpu_ms();
  int rc = 0;
  c->nvf = c->nfv = c->nee = 0;
  long pairs = -1;
  if (method == BVH_OLD) {
    rc = cb_oldbp_update(ob, x0, x1);
    if (!rc) rc = cb_oldbp_self_candidates(ob, c);
    r->rebuilds = cb_oldbp_stats_get(ob)->rebuilds;
  } else if (method == BVH_REFIT || method == BVH_BUILD) {
    if (method == BVH_BUILD) cb_broadphase_invalidate(bp);
    rc = cb_broadphase_update(bp, x0, x1);
    if (!rc) rc = cb_broadphase_self_candidates(bp, c);
    r->rebuilds = cb_broadphase_stats_get(bp)->rebuilds;
  } else {
    e->x0 = x0, e->x1 = x1, e->c = c, e->pairs = 0;
    rc = cb_broadphase_boxes(bp, x0, x1); /* the primitives' boxes the candidates are filtered with */
    if (!rc) rc = emb_commit(e, method == EMB_REFIT && round > 0);
    if (!rc) rtcCollide(e->scene, e->scene, emb_collide, e);
    if (!rc && (c->nvf > c->cap_vf || c->nee > c->cap_ee)) rc = CB_ENOMEM;
    pairs = e->pairs;
  }
  double t1 = cb_now_ms(), u1 = cpu_ms();
  long cvf = 0, cee = 0;
  int ne;
  const int *E = cb_broadphase_edges(bp, &ne); /* the old code numbers the edges the same way (set-up unchanged) */
  if (!rc) narrow(m, E, c, x1, d, &cvf, &cee);
  double t2 = cb_now_ms(), u2 = cpu_ms();
  r->broad[round] = t1 - t0, r->narrow[round] = t2 - t1;
  r->broad_cpu[round] = u1 - u0, r->narrow_cpu[round] = u2 - u1;
  r->vf = c->nvf, r->ee = c->nee, r->cvf = cvf, r->cee = cee, r->tri_pairs = pairs, r->status = rc;
  return rc;
}

static int cmp_key(const void *a, const void *b) {
  long long x = *(const long long *)a, y = *(const long long *)b;
  return (x > y) - (x < y);
}

/* the pairs as sorted keys u * 2^32 + v (unordered: the smaller first) */
static long long *pair_keys(const int *p, long n, int unordered) {
  long long *k = malloc(sizeof *k * (size_t)(n > 0 ? n : 1));
  if (!k) return NULL;
  for (long i = 0; i < n; i++) {
    long long u = p[2 * i], v = p[2 * i + 1];
    if (unordered && u > v) {
      long long t = u;
      u = v, v = t;
    }
    k[i] = u * 4294967296LL + v;
  }
  qsort(k, (size_t)n, sizeof *k, cmp_key);
  return k;
}

/* 1 if c's VF and EE sets are ref's (keys from pair_keys), 0 if not, -1 if out of memory */
static int same_sets(const cb_candidates *c, const long long *ref_vf, long nvf, const long long *ref_ee, long nee) {
  if (c->nvf != nvf || c->nee != nee) return 0;
  long long *a = pair_keys(c->vf, c->nvf, 0), *b = pair_keys(c->ee, c->nee, 1);
  int same = a && b ? !memcmp(a, ref_vf, sizeof *a * (size_t)nvf) && !memcmp(b, ref_ee, sizeof *b * (size_t)nee) : -1;
  free(a);
  free(b);
  return same;
}

typedef struct tri_count {
  long n;
} tri_count;
static int count_visit(void *ctx, int i, int j) {
  (void)i, (void)j;
  ((tri_count *)ctx)->n++;
  return 0;
}

static void spread(double *v, int n, double *med, double *lo, double *hi) {
  *lo = *hi = v[0];
  for (int i = 1; i < n; i++) *lo = fmin(*lo, v[i]), *hi = fmax(*hi, v[i]);
  *med = cb_median(v, n);
}

int main(int argc, char **argv) {
  cb_experiment ex;
  int r = cb_experiment_begin(&ex, "bench_broadphase",
                              "Broad + narrow phase of one self-contact step on a folded sheet (our BVH against "
                              "Embree's rtcCollide), and the exact intersection check.",
                              argc, argv);
  if (r) return r > 0 ? 0 : 1;
  cb_experiment_timed(&ex);
  cb_runtime_init();
  cb_outfile csv;
  if (cb_experiment_csv(&ex, &csv, NULL,
                        "# scene: n x n sheet of unit side folded onto itself (gap h/2 pressed to 0.05 h by a bump), "
                        "the top half "
                        "moving down 0.02 h in the step; d = 0.2 h; one core (Embree: threads=1)\n"
                        "# broad_ms: swept boxes, tree update or Embree commit, traversal, VF/EE candidates; "
                        "narrow_ms: their "
                        "distances at x1; medians (and min, max) of interleaved rounds\n"
                        "# n_contacts_*: candidates closer than d at x1; candidates_per_contact = (n_vf + n_ee) / "
                        "n_contacts\n"
                        "# broad_cpu_ms, narrow_cpu_ms: the same in this thread's CPU time (medians); same_as_old: "
                        "the VF and EE sets equal bvh_old_refit's (the code before the float boxes and ring lists)\n"
                        "# intersect rows: cb_intersections_count (static boxes, exact triangle-triangle test); the "
                        "crossing mesh "
                        "has its top half pressed through the bottom (bump 0.7 h)\n",
                        "mesh,n,n_triangles,method,n_rounds,broad_ms,broad_min_ms,broad_max_ms,narrow_ms,total_ms,"
                        "total_ns_per_tri,"
                        "n_tri_pairs,n_vf,n_ee,n_contacts_vf,n_contacts_ee,candidates_per_contact,n_rebuilds,"
                        "intersecting_pairs,"
                        "intersect_tested_pairs,n_exact_calls,broad_cpu_ms,narrow_cpu_ms,same_as_old,status"))
    return 1;
  int sizes_full[] = {64, 128, 256}, sizes_quick[] = {32, 64};
  int *sizes = ex.quick ? sizes_quick : sizes_full, nsizes = ex.quick ? 2 : 3;
  int rc_all = 0;
  for (int si = 0; si < nsizes; si++) {
    int n = sizes[si], rounds = ex.quick ? 3 : n >= 256 ? 9 : 15;
    cb_mesh m = {0};
    double *x1 = NULL;
    if (folded_sheet(n, 0.45, &m, &x1)) {
      fprintf(stderr, "bench_broadphase: %s\n", cb_error_message());
      return 1;
    }
    double h = 1.0 / (n - 1), d = 0.2 * h;
    cb_broadphase_params p = cb_broadphase_params_default();
    p.thickness = d;
    cb_broadphase *bp = NULL;
    cb_oldbp *ob = NULL;
    cb_candidates c = {0};
    emb e;
    if (cb_broadphase_alloc(m.nv, m.nt, m.tri, &p, &bp) || cb_oldbp_alloc(m.nv, m.nt, m.tri, &p, &ob) ||
        cb_candidates_alloc(40L * m.nt, 0, 80L * m.nt, &c) || emb_init(&e, &m, bp, d)) {
      fprintf(stderr, "bench_broadphase: n = %d: set-up failed: %s\n", n, cb_error_message());
      return 1;
    }
    /* the old code's candidate sets, for same_as_old */
    if (cb_oldbp_update(ob, m.x, x1) || cb_oldbp_self_candidates(ob, &c)) {
      fprintf(stderr, "bench_broadphase: n = %d: the old broad phase failed: %s\n", n, cb_error_message());
      return 1;
    }
    long nref_vf = c.nvf, nref_ee = c.nee;
    long long *ref_vf = pair_keys(c.vf, c.nvf, 0), *ref_ee = pair_keys(c.ee, c.nee, 1);
    if (!ref_vf || !ref_ee) return 1;
    result res[NMETHOD];
    memset(res, 0, sizeof res);
    for (int q = 0; q < rounds; q++)
      for (int k = 0; k < NMETHOD; k++) {
        int meth = (k + q) % NMETHOD; /* rotate the order between rounds */
        run_variant(meth, q, &m, m.x, x1, d, bp, ob, &e, &c, &res[meth]);
        if (q == rounds - 1) res[meth].same = same_sets(&c, ref_vf, nref_vf, ref_ee, nref_ee);
      }
    free(ref_vf);
    free(ref_ee);
    /* our tree's triangle-pair count, for the Embree rows to compare with */
    tri_count tc = {0};
    cb_broadphase_update(bp, m.x, x1);
    cb_broadphase_self_pairs(bp, 0, count_visit, &tc);
    res[BVH_REFIT].tri_pairs = res[BVH_BUILD].tri_pairs = tc.n;
    tc.n = 0;
    cb_oldbp_self_pairs(ob, 0, count_visit, &tc);
    res[BVH_OLD].tri_pairs = tc.n;
    for (int k = 0; k < NMETHOD; k++) {
      result *R = res + k;
      double bm, blo, bhi, nm, nlo, nhi, bc, nc, lo, hi;
      spread(R->broad, rounds, &bm, &blo, &bhi);
      spread(R->narrow, rounds, &nm, &nlo, &nhi);
      spread(R->broad_cpu, rounds, &bc, &lo, &hi);
      spread(R->narrow_cpu, rounds, &nc, &lo, &hi);
      long contacts = R->cvf + R->cee;
      cb_csv_printf(csv.f,
                    "folded,%d,%d,%s,%d,%.6f,%.6f,%.6f,%.6f,%.6f,%.17g,%ld,%ld,%ld,%ld,%ld,%.17g,%.17g,,,,%.6f,%.6f,%d,"
                    "%s\n",
                    n, m.nt, method_name[k], rounds, bm, blo, bhi, nm, bm + nm, (bm + nm) * 1e6 / m.nt, R->tri_pairs,
                    R->vf, R->ee, R->cvf, R->cee, contacts ? (double)(R->vf + R->ee) / contacts : cb_csv_na(),
                    k <= BVH_BUILD || k == BVH_OLD ? (double)R->rebuilds : cb_csv_na(), bc, nc, R->same,
                    cb_status_name(R->status));
      fprintf(stderr,
              "bench_broadphase: n = %d (%d triangles) %-13s broad %8.2f ms  narrow %7.2f ms  total %8.2f ms "
              "(%.0f ns/tri; CPU %.2f + %.2f ms)  pairs %ld  vf %ld ee %ld  contacts %ld  same as old %d%s\n",
              n, m.nt, method_name[k], bm, nm, bm + nm, (bm + nm) * 1e6 / m.nt, bc, nc, R->tri_pairs, R->vf, R->ee,
              contacts, R->same, R->status ? " FAILED" : "");
      if (R->status || R->same != 1) rc_all = 1;
    }
    if (res[EMB_BUILD].vf != res[BVH_REFIT].vf || res[EMB_BUILD].ee != res[BVH_REFIT].ee)
      fprintf(stderr, "bench_broadphase: n = %d: Embree's candidates (%ld, %ld) differ from the BVH's (%ld, %ld)\n", n,
              res[EMB_BUILD].vf, res[EMB_BUILD].ee, res[BVH_REFIT].vf, res[BVH_REFIT].ee);
    if (e.both_orders == 0)
      fprintf(stderr, "bench_broadphase: rtcCollide reported no pair twice: the i < j filter may drop pairs\n");
    emb_free(&e);
    cb_candidates_free(&c);
    cb_broadphase_free(bp);
    cb_oldbp_free(ob);
    free(x1);
    cb_mesh_free(&m);
    fflush(csv.f);
  }
  /* the exact intersection check */
  int isizes[] = {101, 256};
  for (int si = 0; si < (ex.quick ? 1 : 2); si++)
    for (int crossing = 0; crossing < 2; crossing++) {
      int n = ex.quick ? 41 : isizes[si], rounds = ex.quick ? 2 : 5;
      cb_mesh m = {0};
      double *x1 = NULL;
      if (folded_sheet(n, crossing ? 0.7 : 0.45, &m, &x1)) return 1;
      cb_intersections ix;
      if (cb_intersections_init(&ix, &m)) return 1;
      double t[16];
      long count = -1;
      int st = 0;
      for (int q = 0; q < rounds && !st; q++) {
        st = cb_intersections_count(&ix, m.x, &count);
        t[q] = ix.wall_ms;
      }
      double tm, tlo, thi;
      spread(t, rounds, &tm, &tlo, &thi);
      cb_csv_printf(csv.f, "%s,%d,%d,intersect,%d,,,,,%.6f,%.17g,%ld,,,,,,%.17g,%ld,%ld,%ld,,,,%s\n",
                    crossing ? "folded_crossing" : "folded", n, m.nt, rounds, tm, tm * 1e6 / m.nt, ix.pairs,
                    (double)cb_broadphase_stats_get(ix.bp)->rebuilds, count, ix.pairs, ix.exact_calls,
                    cb_status_name(st));
      fprintf(stderr, "bench_broadphase: intersection check, %s n = %d (%d triangles): %ld pairs of %ld, %.2f ms\n",
              crossing ? "crossing" : "folded", n, m.nt, count, ix.pairs, tm);
      cb_intersections_free(&ix);
      free(x1);
      cb_mesh_free(&m);
    }
  if (cb_outfile_commit(&csv)) {
    fprintf(stderr, "bench_broadphase: %s\n", cb_error_message());
    return 2;
  }
  return rc_all;
}
