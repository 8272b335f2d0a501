/* Opening an input file for reading without blocking on it: a FIFO (or a
 * device) given as a config, a mesh or a CSV is refused, never waited on, as
 * fopen would wait for a writer for ever. */
#ifndef CB_READFILE_H
#define CB_READFILE_H

#include <stdio.h>
#include <sys/stat.h>

/* Opens path for reading if it is a regular file: open(O_NONBLOCK), fstat,
 * then an ordinary blocking FILE. Returns NULL with errno set when it cannot
 * be opened, and NULL with errno = 0 when it is not a regular file (sb, if
 * not NULL, then says what it is); on success sb holds its fstat. */
FILE *cb_fopen_regular(const char *path, struct stat *sb);

#endif
