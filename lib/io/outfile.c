#define _XOPEN_SOURCE 700 /* realpath, lstat */
#include "outfile.h"

#include <errno.h>
#include <limits.h>
#include <signal.h>
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

/* ---- temporary files removed on SIGINT, SIGTERM, SIGHUP ------------------------
 * The handler only calls unlink (async-signal-safe) on the paths registered
 * here, then restores the default action and re-raises the signal. */

#define MAX_OPEN 64
static char tracked[MAX_OPEN][4160];
static volatile sig_atomic_t tracked_used[MAX_OPEN];
static int handlers_installed;

static void on_signal(int sig) {
  for (int i = 0; i < MAX_OPEN; i++)
    if (tracked_used[i]) unlink(tracked[i]);
  signal(sig, SIG_DFL);
  raise(sig);
}

/* Registers o's temporary file (a copy of its name, so the struct may move). */
static void track(cb_outfile *o) {
  if (!handlers_installed) {
    static const int sigs[] = {SIGINT, SIGTERM, SIGHUP};
    for (int k = 0; k < 3; k++) {
      struct sigaction sa, old;
      memset(&sa, 0, sizeof sa);
      sa.sa_handler = on_signal;
      sigemptyset(&sa.sa_mask);
      /* leave a signal the program's caller chose to ignore (nohup) ignored */
      if (sigaction(sigs[k], NULL, &old) == 0 && old.sa_handler == SIG_IGN) continue;
      sigaction(sigs[k], &sa, NULL);
    }
    handlers_installed = 1;
  }
  for (int i = 0; i < MAX_OPEN; i++)
    if (!tracked_used[i]) {
      memcpy(tracked[i], o->tmp, sizeof tracked[i]);
      tracked_used[i] = 1;
      o->slot = i + 1;
      return;
    }
}

static void untrack(cb_outfile *o) {
  if (o->slot > 0) tracked_used[o->slot - 1] = 0;
  o->slot = 0;
}

static const char *file_kind(mode_t m) {
  return S_ISDIR(m)    ? "a directory"
         : S_ISLNK(m)  ? "a symbolic link"
         : S_ISSOCK(m) ? "a socket"
         : S_ISBLK(m)  ? "a block device"
                       : "not a regular file";
}

/* The canonical form of path, which need not exist: realpath of its longest
 * existing leading folder, then the remaining names, "." ones dropped. */
static void canonical(const char *path, char *out, size_t n) {
  char dir[PATH_MAX], real[PATH_MAX];
  const char *slash = strrchr(path, '/');
  const char *name = slash ? slash + 1 : path;
  snprintf(dir, sizeof dir, "%.*s", slash ? (int)(slash - path) + (slash == path) : 1, slash ? path : ".");
  if (realpath(dir, real)) snprintf(out, n, "%s", real);
  else if (strcmp(dir, path) != 0 && strlen(dir) < strlen(path)) canonical(dir, out, n); /* a folder still to be made */
  else snprintf(out, n, "%s", dir);
  size_t used = strlen(out);
  if (*name && strcmp(name, ".") != 0 && used + 1 < n)
    snprintf(out + used, n - used, "%s%s", used && out[used - 1] == '/' ? "" : "/", name);
}

int cb_same_file(const char *a, const char *b) {
  struct stat sa, sb;
  if (stat(a, &sa) == 0 && stat(b, &sb) == 0) return sa.st_dev == sb.st_dev && sa.st_ino == sb.st_ino;
  char ca[PATH_MAX * 2], cb[PATH_MAX * 2];
  canonical(a, ca, sizeof ca);
  canonical(b, cb, sizeof cb);
  return strcmp(ca, cb) == 0;
}

int cb_outfile_open(cb_outfile *o, const char *path) {
  memset(o, 0, sizeof *o);
  if (!path[0]) return cb_fail_status(CB_EIO, "output path is empty");
  if (strlen(path) >= sizeof o->path) return cb_fail_status(CB_EIO, "%s: path too long", path);
  strcpy(o->path, path);
  if (strcmp(path, "-") == 0) { /* standard output, streamed */
    o->f = stdout;
    o->stream = 1;
    return CB_OK;
  }
  struct stat ls;
  if (lstat(path, &ls) == 0 && !S_ISREG(ls.st_mode)) {
    struct stat ts;
    int target = stat(path, &ts) == 0;
    if (S_ISLNK(ls.st_mode) && target && S_ISREG(ts.st_mode))
      return cb_fail_status(
          CB_EIO, "%s: is a symbolic link; give the file it points to (an atomic write would replace the link)", path);
    mode_t m = target ? ts.st_mode : ls.st_mode;
    if (S_ISCHR(m) || S_ISFIFO(m)) { /* a device or pipe: stream into it, never replace it */
      o->f = fopen(path, "w");
      if (!o->f) return cb_fail_status(CB_EIO, "%s: cannot open for writing: %s", path, strerror(errno));
      o->stream = 1;
      return CB_OK;
    }
    return cb_fail_status(CB_EIO, "%s: exists and is %s; outputs replace only regular files", path, file_kind(m));
  }
  int st = cb_make_parent_dirs(path);
  if (st) return st;
  snprintf(o->tmp, sizeof o->tmp, "%s.tmp.XXXXXX", path);
  /* no signal between creating the temporary file and registering it, or a SIGTERM there leaves it behind
   * (seen: an interrupted simulate --frames whose staging folder could then not be removed) */
  sigset_t block, old;
  sigemptyset(&block);
  sigaddset(&block, SIGINT);
  sigaddset(&block, SIGTERM);
  sigaddset(&block, SIGHUP);
  sigprocmask(SIG_BLOCK, &block, &old);
  int fd = mkstemp(o->tmp);
  if (fd >= 0) track(o);
  sigprocmask(SIG_SETMASK, &old, NULL);
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
    untrack(o);
    return cb_fail_status(CB_EIO, "%s: fdopen failed: %s", path, strerror(errno));
  }
  return CB_OK;
}

/* The cause of a write error that stdio reported without keeping errno (a
 * buffer whose write failed earlier, then a fflush with nothing left to
 * write): one byte written past the data at fd's end (and truncated away)
 * meets the same full disk, quota or file-size limit. 0 if it does not. */
static int write_error_cause(int fd) {
  struct stat st;
  if (fd < 0 || fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) return 0;
  if (pwrite(fd, "\n", 1, st.st_size) == 1) {
    if (ftruncate(fd, st.st_size) != 0) return errno;
    return 0;
  }
  return errno;
}

/* Flushes and closes o->f; returns 0, or the errno of the first failure
 * (-1 when stdio reported an error whose cause is lost). */
static int flush_close(cb_outfile *o, int sync) {
  int err = 0;
  errno = 0;
  if (fflush(o->f) != 0) err = errno ? errno : EIO;
  if (!err && ferror(o->f) && !(err = write_error_cause(fileno(o->f)))) err = -1; /* the cause is lost */
  if (!err && sync && fsync(fileno(o->f)) != 0 && errno != EINVAL) err = errno;
  if (o->f != stdout) {
    errno = 0;
    if (fclose(o->f) != 0 && !err) err = errno ? errno : EIO;
  }
  o->f = NULL;
  return err;
}

int cb_outfile_finish(cb_outfile *o) {
  if (!o->f) return o->tmp[0] ? CB_OK : cb_fail_status(CB_EIO, "%s: file not open", o->path);
  int err = flush_close(o, !o->stream);
  if (err) {
    if (o->tmp[0]) unlink(o->tmp);
    o->tmp[0] = '\0';
    untrack(o);
    return cb_fail_status(CB_EIO, "%s: write failed: %s", o->path,
                          err > 0 ? strerror(err) : "an earlier write failed (the C library did not keep its cause)");
  }
  return CB_OK;
}

int cb_outfile_publish(cb_outfile *o) {
  if (o->stream) return CB_OK;
  if (!o->tmp[0] || o->f) return cb_fail_status(CB_EIO, "%s: nothing finished to publish", o->path);
  if (rename(o->tmp, o->path) != 0) {
    int err = errno;
    unlink(o->tmp);
    o->tmp[0] = '\0';
    untrack(o);
    return cb_fail_status(CB_EIO, "%s: rename failed: %s", o->path, strerror(err));
  }
  o->tmp[0] = '\0';
  untrack(o);
  return CB_OK;
}

int cb_outfile_commit(cb_outfile *o) {
  if (!o->f) return cb_fail_status(CB_EIO, "%s: file not open", o->path);
  int st = cb_outfile_finish(o);
  return st ? st : cb_outfile_publish(o);
}

void cb_outfile_abort(cb_outfile *o) {
  if (o->f && o->f != stdout) fclose(o->f);
  else if (o->f) fflush(o->f);
  o->f = NULL;
  if (o->tmp[0]) unlink(o->tmp);
  o->tmp[0] = '\0';
  untrack(o);
}

int cb_mesh_write_obj(const cb_mesh *m, const double *x, const char *path) {
  cb_outfile o;
  int st = cb_outfile_open(&o, path);
  if (st) return st;
  cb_mesh_print_obj(m, x, o.f);
  return cb_outfile_commit(&o);
}
