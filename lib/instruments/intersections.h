/* The exact intersection check, an instrument: it observes a frame and never
 * steers a run (DESIGN.md, "Contact").
 *
 * It counts the pairs of non-adjacent triangles (no shared vertex) of a mesh
 * that intersect: closed triangles, no tolerance, touching counts, decided by
 * cb_tri_tri_intersect's exact predicates (include/clothbench/intersect.h).
 * The pairs tested are the broad phase's (include/clothbench/broadphase.h)
 * over the static boxes of the frame with thickness 0: closed boxes, so
 * triangles that touch have touching boxes and none is missed. Triangles
 * sharing a vertex always meet there and are not counted; a pair that shares
 * a vertex and also crosses elsewhere is not seen by this count. */
#ifndef CB_INTERSECTIONS_H
#define CB_INTERSECTIONS_H

#include <clothbench/broadphase.h>
#include <clothbench/mesh.h>

typedef struct cb_intersections {
  cb_broadphase *bp;
  int nt;
  const int *tri;   /* the mesh's triangles (not owned) */
  long pairs;       /* candidate pairs tested by the last count */
  long exact_calls; /* orientation predicates that needed exact arithmetic in the last count */
  double wall_ms;   /* wall time of the last count (broad and narrow phase) */
} cb_intersections;

/* Set-up for mesh m (its triangles are referenced, not copied). */
int cb_intersections_init(cb_intersections *c, const cb_mesh *m);
void cb_intersections_free(cb_intersections *c);
/* *count = intersecting non-adjacent pairs at positions x (3*nv). -> CB_EINVAL
 * (and *count = -1) if a coordinate is NaN or infinite. */
int cb_intersections_count(cb_intersections *c, const double *x, long *count);

#endif
