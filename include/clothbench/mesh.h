/* Triangle meshes: a vertex list and index triples (the lecture's
 * "Triangle Mesh Representation"), a grid generator, and OBJ input/output. */
#ifndef CB_MESH_H
#define CB_MESH_H

#include "params.h"

#include <stdio.h>

typedef struct cb_mesh {
  int nv;    /* number of vertices */
  int nt;    /* number of triangles */
  double *x; /* 3*nv positions, m, flat: x[3i+0..2] */
  int *tri;  /* 3*nt vertex indices (0-based), counter-clockwise */
  /* Grid meshes only (grid_n > 0): vertex (i, j) has index j*grid_n + i.
   * A chain is a grid with grid_m = 1. */
  int grid_n, grid_m;
  /* Line elements (OBJ `l`, or a chain): nl segments, 2*nl vertex indices.
   * They carry springs like triangle edges but no area. */
  int nl;
  int *lines;
  /* OBJ meshes only (else NULL): the file line of each vertex's `v`
   * statement, for messages about one vertex. */
  int *vline;
} cb_mesh;

/* The largest OBJ file cb_mesh_read_obj reads, bytes (256 MiB: about five
 * million vertices with their faces). */
#define CB_OBJ_MAX_BYTES (256L << 20)

typedef enum { CB_PLANE_XY = 0, CB_PLANE_XZ = 1, CB_PLANE_YZ = 2 } cb_plane;
typedef enum { CB_DIAG_REGULAR = 0, CB_DIAG_ALTERNATING = 1 } cb_diagonal;

typedef struct cb_grid_params {
  int cookie;           /* CB_PARAMS_COOKIE, set by cb_grid_params_default() and checked by cb_mesh_grid (params.h) */
  int n;                /* vertices along the first axis; >= 2. Default 21 */
  int m;                /* vertices along the second axis; >= 2. Default 21 */
  double size[2];       /* side lengths along the two axes, m. Default 10 x 10 */
  cb_plane plane;       /* plane the grid lies in. Default xz (horizontal, y up) */
  cb_diagonal diagonal; /* how each quad is split. Default regular */
} cb_grid_params;

cb_grid_params cb_grid_params_default(void);

/* Grid of n*m vertices centred on the origin. The first axis of the plane
 * carries i, the second carries j; vertex (i, j) is j*n + i, and the row j = m-1
 * is the "top" edge. Regular diagonals split every quad (i,j)-(i+1,j+1);
 * alternating flips the diagonal in a checkerboard. */
int cb_mesh_grid(const cb_grid_params *p, cb_mesh *out);

/* A chain of n >= 2 vertices (n-1 segments, no triangles) of the given
 * length along the first axis of the plane, centred on the origin; vertex n-1
 * is the top end (largest coordinate). The lab-free way to get a single
 * spring (n = 2) or a hanging chain. */
int cb_mesh_chain(int n, double length, cb_plane plane, cb_mesh *out);

/* Reads `v` and `f` statements. Faces may use v, v/vt, v//vn, v/vt/vn, 1-based
 * or negative (relative) indices; polygons are fan-triangulated. Other
 * `l` polylines become line segments. Other statements (vt, vn, o, g, s,
 * usemtl, mtllib, ...) are ignored. Errors name
 * file:line. Rejects non-finite coordinates, out-of-range indices, faces with
 * fewer than 3 vertices, zero-area triangles (area <= 1e-12 x the longest
 * edge squared, a test independent of the mesh's scale), zero-length line
 * segments, and input that is not a text file: a path that is not a regular
 * file (a directory, /dev/zero, a FIFO), a file over CB_OBJ_MAX_BYTES, a NUL
 * byte, or a read error. */
int cb_mesh_read_obj(const char *path, cb_mesh *out);

/* Length of the diagonal of the axis-aligned bounding box of the rest
 * positions m->x, m (0 for an empty or one-point mesh). */
double cb_mesh_bbox_diagonal(const cb_mesh *m);

/* Prints positions x (3*nv, or the mesh's own if NULL), the triangles and the
 * line elements as OBJ to f. Writing a file atomically is the I/O layer's
 * cb_mesh_write_obj (lib/io/outfile.h). */
void cb_mesh_print_obj(const cb_mesh *m, const double *x, FILE *f);

/* Area of triangle t at positions x (3*nv). */
double cb_mesh_triangle_area(const cb_mesh *m, const double *x, int t);

void cb_mesh_free(cb_mesh *m);

#endif
