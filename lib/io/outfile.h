/* Atomic output files: data is written to a temporary file beside the target
 * and renamed over it on commit, so a reader never sees a truncated file and a
 * failed run leaves the previous file (or none) in place. */
#ifndef CB_OUTFILE_H
#define CB_OUTFILE_H

#include <stdio.h>

#include <clothbench/mesh.h>

typedef struct cb_outfile {
  FILE *f;        /* write here between open and commit */
  char path[4096];
  char tmp[4160];
} cb_outfile;

/* Creates missing parent directories, then a temporary file beside path. */
int cb_outfile_open(cb_outfile *o, const char *path);
/* Flushes, checks for write errors, fsyncs and renames. On failure the
 * temporary file is removed and CB_EIO returned. */
int cb_outfile_commit(cb_outfile *o);
/* Drops the temporary file; safe to call on a committed or unopened file. */
void cb_outfile_abort(cb_outfile *o);

/* mkdir -p for the directory part of path. */
int cb_make_parent_dirs(const char *path);

/* Writes positions x (3*nv, or the mesh's own if NULL) and the triangles as
 * OBJ, atomically (cb_mesh_print_obj into a cb_outfile). */
int cb_mesh_write_obj(const cb_mesh *m, const double *x, const char *path);

#endif
