#include "outfile.h"

#include <errno.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include <clothbench/status.h>

int cb_make_parent_dirs(const char *path) {
  char buf[4096];
  size_t n = strlen(path);
  if (n >= sizeof buf) return cb_fail_status(CB_EIO, "%s: path too long", path);
  memcpy(buf, path, n + 1);
  char *slash = strrchr(buf, '/');
  if (!slash || slash == buf) return CB_OK;
  *slash = '\0';
  for (char *p = buf + 1; *p; p++) {
    if (*p != '/') continue;
    *p = '\0';
    if (mkdir(buf, 0777) != 0 && errno != EEXIST)
      return cb_fail_status(CB_EIO, "%s: cannot create directory: %s", buf, strerror(errno));
    *p = '/';
  }
  if (mkdir(buf, 0777) != 0 && errno != EEXIST)
    return cb_fail_status(CB_EIO, "%s: cannot create directory: %s", buf, strerror(errno));
  return CB_OK;
}

int cb_outfile_open(cb_outfile *o, const char *path) {
  memset(o, 0, sizeof *o);
  if (strlen(path) >= sizeof o->path) return cb_fail_status(CB_EIO, "%s: path too long", path);
  int st = cb_make_parent_dirs(path);
  if (st) return st;
  strcpy(o->path, path);
  snprintf(o->tmp, sizeof o->tmp, "%s.tmp.XXXXXX", path);
  int fd = mkstemp(o->tmp);
  if (fd < 0) {
    o->tmp[0] = '\0';
    return cb_fail_status(CB_EIO, "%s: cannot create temporary file: %s", path, strerror(errno));
  }
  fchmod(fd, 0644);
  o->f = fdopen(fd, "w");
  if (!o->f) {
    close(fd);
    unlink(o->tmp);
    o->tmp[0] = '\0';
    return cb_fail_status(CB_EIO, "%s: fdopen failed: %s", path, strerror(errno));
  }
  return CB_OK;
}

int cb_outfile_commit(cb_outfile *o) {
  if (!o->f) return cb_fail_status(CB_EIO, "%s: file not open", o->path);
  int bad = fflush(o->f) != 0 || ferror(o->f);
  if (!bad) bad = fsync(fileno(o->f)) != 0 && errno != EINVAL;
  int err = errno;
  if (fclose(o->f) != 0) bad = 1;
  o->f = NULL;
  if (bad) {
    unlink(o->tmp);
    o->tmp[0] = '\0';
    return cb_fail_status(CB_EIO, "%s: write failed: %s", o->path, strerror(err));
  }
  if (rename(o->tmp, o->path) != 0) {
    err = errno;
    unlink(o->tmp);
    o->tmp[0] = '\0';
    return cb_fail_status(CB_EIO, "%s: rename failed: %s", o->path, strerror(err));
  }
  o->tmp[0] = '\0';
  return CB_OK;
}

void cb_outfile_abort(cb_outfile *o) {
  if (o->f) fclose(o->f);
  o->f = NULL;
  if (o->tmp[0]) unlink(o->tmp);
  o->tmp[0] = '\0';
}

int cb_mesh_write_obj(const cb_mesh *m, const double *x, const char *path) {
  cb_outfile o;
  int st = cb_outfile_open(&o, path);
  if (st) return st;
  cb_mesh_print_obj(m, x, o.f);
  return cb_outfile_commit(&o);
}
