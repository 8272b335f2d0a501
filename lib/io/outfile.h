/* Output files, written atomically: data goes to a temporary file beside the
 * target and is renamed over it on commit, so a reader never sees a truncated
 * file and a failed or interrupted run leaves the previous file (or none) in
 * place.
 *
 * What a destination means:
 *   - a path that does not exist, or names a regular file: written atomically;
 *   - "-": standard output, streamed (not atomic: a failed run leaves what it
 *     wrote so far);
 *   - an existing character device or FIFO (/dev/null, /dev/stdout, a pipe):
 *     opened and streamed into, never replaced (root could otherwise replace
 *     /dev/null with a regular file);
 *   - anything else (a directory, a socket, a symbolic link to anything but a
 *     regular file): refused with a message.
 * SIGINT, SIGTERM and SIGHUP remove the temporary files of every output still
 * open, then end the program as the signal would have. */
#ifndef CB_OUTFILE_H
#define CB_OUTFILE_H

#include <stdio.h>

#include <clothbench/mesh.h>

typedef struct cb_outfile {
  FILE *f; /* write here between open and commit */
  char path[4096];
  char tmp[4160]; /* temporary file ("" when streaming, or after commit/abort) */
  int stream;     /* 1: written straight into path (stdout, a device or FIFO) */
  int slot;       /* 1 + index in the table of temporary files removed on a signal; 0 = none */
} cb_outfile;

/* Creates missing parent directories, then a temporary file beside path. */
int cb_outfile_open(cb_outfile *o, const char *path);
/* Flushes, checks for write errors, fsyncs and renames. On failure the
 * temporary file is removed and CB_EIO returned; the message names the first
 * error's cause (a full disk is "No space left on device", never "Success").
 * cb_outfile_finish then cb_outfile_publish. */
int cb_outfile_commit(cb_outfile *o);
/* The two halves of commit, for a set of files committed together (all or
 * none: finish each, and publish them only if every one finished):
 * finish flushes, checks, fsyncs and closes, keeping the temporary file (on
 * failure it is removed: CB_EIO); publish renames it over the path. A
 * finished file not published is dropped by cb_outfile_abort. */
int cb_outfile_finish(cb_outfile *o);
int cb_outfile_publish(cb_outfile *o);
/* Drops the temporary file; safe to call on a committed or unopened file. */
void cb_outfile_abort(cb_outfile *o);

/* Whether paths a and b name the same file: the same inode where both exist,
 * otherwise the same canonical path (its folder resolved, the name as is). */
int cb_same_file(const char *a, const char *b);

/* mkdir -p for the directory part of path. */
int cb_make_parent_dirs(const char *path);

/* Writes positions x (3*nv, or the mesh's own if NULL) and the triangles as
 * OBJ, atomically (cb_mesh_print_obj into a cb_outfile). */
int cb_mesh_write_obj(const cb_mesh *m, const double *x, const char *path);

#endif
