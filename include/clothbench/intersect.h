/* Exact geometric predicates and the exact triangle-triangle intersection
 * test (closed triangles: touching at a point counts; no tolerance).
 *
 * Orientation. orient3d(a, b, c, d) is the sign of det[a-d; b-d; c-d]
 * (positive when d lies below the plane through a, b, c seen with a, b, c
 * counter-clockwise, as in Shewchuk 1997); orient2d(a, b, c) the sign of
 * det[a-c; b-c] (positive when a, b, c turn counter-clockwise). Both are
 * evaluated in double precision first, with Shewchuk's forward error bound
 * ("Adaptive precision floating-point arithmetic and fast robust geometric
 * predicates", 1997, errboundA): when |det| exceeds the bound the sign is
 * certain. Otherwise the determinant is recomputed exactly in GMP rationals
 * (every double is a rational; sums and products of rationals are exact), so
 * the sign is always the sign of the exact determinant of the given doubles.
 * The exact path allocates (GMP); it runs only when the filter fails (nearly
 * degenerate input), and these predicates are for instruments and tests, not
 * for a time step's inner loop.
 *
 * Triangle-triangle test. Two closed triangles meet iff an edge of one meets
 * the other (their intersection is a compact convex set; its extreme points
 * lie on the relative boundary of one of them, i.e. on an edge, and a
 * degenerate triangle is the union of its edges). An edge (closed segment)
 * and a closed triangle are decided by orientations only:
 *   - non-degenerate triangle, segment not in its plane: the segment's end
 *     points may not lie strictly on one side (orient3d), and the line of the
 *     segment must pass through the closed triangle: the three orient3d(a, b,
 *     p, q) over the triangle's edges pq are not of mixed strict signs;
 *   - segment in the triangle's plane: the test in the axis plane onto which
 *     the triangle projects with non-zero area (chosen by an exact orient2d):
 *     an end point inside the closed triangle, or the segment meets an edge;
 *   - degenerate triangle (collinear or repeated points): segment against each
 *     of its edges; two segments meet iff they are coplanar (orient3d = 0) and
 *     their projections meet in all three axis planes (one of them is one to
 *     one on their common plane or line).
 * Inputs must be finite (the callers check; a NaN gives an arbitrary sign). */
#ifndef CB_INTERSECT_H
#define CB_INTERSECT_H

/* Sign (-1, 0, 1) of det[a-d; b-d; c-d], exactly. */
int cb_orient3d(const double *a, const double *b, const double *c, const double *d);
/* Sign of det[a-c; b-c] for 2-vectors, exactly. */
int cb_orient2d(const double *a, const double *b, const double *c);
/* How many orientation calls fell back to exact arithmetic, this thread, since
 * the last reset (for tests and the bench). */
long cb_orient_exact_calls(void);
void cb_orient_exact_reset(void);

/* 1 if the closed triangles (p0, p1, p2) and (q0, q1, q2) share a point. */
int cb_tri_tri_intersect(const double *p0, const double *p1, const double *p2, const double *q0, const double *q1,
                         const double *q2);
/* 1 if the closed segment (a, b) and the closed triangle (p0, p1, p2) share a point. */
int cb_seg_tri_intersect(const double *a, const double *b, const double *p0, const double *p1, const double *p2);

#endif
