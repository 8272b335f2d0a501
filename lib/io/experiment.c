#include "experiment.h"

#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <sys/file.h>

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "provenance.h"
#include <clothbench/status.h>

static const char *cpu_lock_path(void) {
  const char *p = getenv("CB_CPU_LOCK");
  return p && *p ? p : "/tmp/clothbench-cpu.lock";
}

/* flock(fd, op), and if it would block, a message (when say) and then a
 * blocking wait. Returns 1 if it had to wait. */
static int flock_waiting(const cb_experiment *e, int fd, int op, const char *why, int say) {
  if (flock(fd, op | LOCK_NB) == 0) return 0;
  if (errno != EWOULDBLOCK) return 0; /* a lock that cannot be taken is not waited for */
  if (say && !getenv("CB_QUIET")) fprintf(stderr, "%s: waiting for %s (lock %s)\n", e->name, why, cpu_lock_path());
  while (flock(fd, op) != 0 && errno == EINTR) {}
  return 1;
}

/* The CPU lock in mode op (LOCK_SH or LOCK_EX), through the turnstile: held
 * while waiting, it keeps later arrivals out, so an exclusive waiter is next
 * once the present holders let go (flock alone may let shared holders pass
 * it for ever). Converting a held lock lets go of it before the turnstile:
 * no process may wait at the turnstile while it holds the lock, or the
 * turnstile's holder, waiting for the lock, and it, waiting for the
 * turnstile, wait for each other for ever (two timed experiments that start
 * together, each converting its shared lock from cb_experiment_begin,
 * deadlocked so; tests/test_cpu_lock.c). Returns 1 if it had to wait. */
static int lock_waiting_say(cb_experiment *e, int op, const char *why, int say) {
  if (e->lock_fd < 0 || e->lock_held == op) return 0;
  struct timespec t0, t1;
  clock_gettime(CLOCK_MONOTONIC, &t0);
  int waited = 0;
  if (e->lock_held) {
    flock(e->lock_fd, LOCK_UN);
    e->lock_held = 0;
  }
  if (e->turn_fd >= 0) waited = flock_waiting(e, e->turn_fd, LOCK_EX, why, say);
  waited |= flock_waiting(e, e->lock_fd, op, why, say && !waited);
  e->lock_held = op;
  if (e->turn_fd >= 0) flock(e->turn_fd, LOCK_UN);
  clock_gettime(CLOCK_MONOTONIC, &t1);
  e->lock_wait_s += (double)(t1.tv_sec - t0.tv_sec) + 1e-9 * (double)(t1.tv_nsec - t0.tv_nsec);
  return waited;
}

static void lock_waiting(cb_experiment *e, int op, const char *why) { lock_waiting_say(e, op, why, 1); }

void cb_experiment_timed(cb_experiment *e) {
  e->timed = 1;
  lock_waiting(e, LOCK_EX, "other experiments to finish: a timed experiment runs alone");
}

void cb_experiment_timed_cells(cb_experiment *e, const char *const *untimed) {
  e->cell_locks = 1;
  e->untimed = untimed;
}

int cb_experiment_sweep_untimed(cb_experiment *e, const char *sweep) {
  for (int k = 0; e->untimed && e->untimed[k] && k < 32; k++)
    if (!strcmp(e->untimed[k], sweep)) {
      e->untimed_seen |= 1u << k;
      return 1;
    }
  return 0;
}

/* Every untimed sweep name matched a sweep that ran (a smoke or sharded run
 * may run no cell of a sweep: its cells were still declared, and the name is
 * checked against the declared sweeps by cb_sweep_run). */
static int check_untimed(const cb_experiment *e) {
  for (int k = 0; e->untimed && e->untimed[k]; k++)
    if (k >= 32 || !(e->untimed_seen & (1u << k)))
      return cb_fail_status(CB_EINVAL, "untimed sweep '%s' (cb_experiment_timed_cells) names no sweep of %s",
                            k < 32 ? e->untimed[k] : "(more than 32)", e->name);
  return CB_OK;
}

void cb_experiment_cells_start(cb_experiment *e) {
  if (!e->cell_locks || e->lock_fd < 0 || !e->lock_held) return;
  flock(e->lock_fd, LOCK_UN);
  e->lock_held = 0;
}

void cb_experiment_cell_lock(cb_experiment *e, int timed) {
  if (!e->cell_locks || e->lock_fd < 0) return;
  /* one message per run: the first cell that waits says so */
  if (lock_waiting_say(e, timed ? LOCK_EX : LOCK_SH,
                       timed ? "other cells and experiments to finish: a timed cell runs alone"
                             : "a timed cell or experiment to finish",
                       !e->waited_msg))
    e->waited_msg = 1;
}

void cb_experiment_cell_unlock(cb_experiment *e) {
  if (!e->cell_locks || e->lock_fd < 0 || !e->lock_held) return;
  flock(e->lock_fd, LOCK_UN);
  e->lock_held = 0;
}

/* Why --out may not be written: it (or its side tables and cell list, which
 * sit beside it) would land in the configs folder, or it is a mesh one of the
 * configs reads; NULL if it may. The configs and meshes are the inputs. */
static const char *input_clash(const cb_experiment *e, char *what, size_t n) {
  char folder[sizeof e->out];
  const char *slash = strrchr(e->out, '/');
  snprintf(folder, sizeof folder, "%.*s", slash ? (int)(slash - e->out) + (slash == e->out) : 1, slash ? e->out : ".");
  if (cb_same_file(folder, e->configs)) {
    snprintf(what, n, "in the configs folder %s (the experiment's inputs)", e->configs);
    return what;
  }
  DIR *d = opendir(e->configs);
  if (!d) return NULL;
  for (struct dirent *de; (de = readdir(d));) {
    size_t len = strlen(de->d_name);
    if (len <= 4 || strcmp(de->d_name + len - 4, ".ini") != 0) continue;
    char path[CB_PATH_LEN], mesh[2 * CB_PATH_LEN];
    cb_config c;
    snprintf(path, sizeof path, "%s/%s", e->configs, de->d_name);
    if (cb_config_load(path, &c) != CB_OK || strcmp(c.mesh_type, "obj") != 0) continue;
    cb_config_resolve_path(&c, c.mesh_file, mesh, sizeof mesh);
    if (cb_same_file(e->out, mesh)) {
      snprintf(what, n, "the mesh %s that %s reads", mesh, path);
      closedir(d);
      return what;
    }
  }
  closedir(d);
  return NULL;
}

/* "I/N" with 1 <= I <= N <= 1e6, digits only (sscanf's %d kept the low 32 bits
 * of 4294967299 and accepted "+2" and " 2"): 0, or -1 */
static int parse_shard(const char *s, int *i, int *n) {
  long v[2];
  for (int k = 0; k < 2; k++) {
    if (*s < '0' || *s > '9') return -1;
    char *end;
    errno = 0;
    v[k] = strtol(s, &end, 10);
    if (errno == ERANGE || v[k] < 1 || v[k] > 1000000) return -1;
    s = end;
    if (k == 0 && *s++ != '/') return -1;
  }
  if (*s || v[0] > v[1]) return -1;
  *i = (int)v[0];
  *n = (int)v[1];
  return 0;
}

int cb_experiment_begin(cb_experiment *e, const char *name, const char *about, int argc, char **argv) {
  memset(e, 0, sizeof *e);
  e->lock_fd = -1;
  e->turn_fd = -1;
  if (cb_runtime_init()) {
    fprintf(stderr, "%s: %s\n", name, cb_error_message());
    return -1;
  }
  e->name = name;
  e->argc = argc;
  e->argv = argv;
  e->configs = "configs";
  const char *q = getenv("QUICK");
  e->quick = q && *q && strcmp(q, "0") != 0;
  const char *sc = getenv("SCALE");
  e->scale = sc && *sc && strcmp(sc, "0") != 0;
  e->shard = 0;
  e->nshards = 1;
  int out_given = 0;
  for (int i = 1; i < argc; i++) {
    if (!strcmp(argv[i], "--help") || !strcmp(argv[i], "-h")) {
      printf("usage: %s [--quick | --smoke | --scale] [--out PATH] [--configs DIR] [--shard I/N [--shard-mode M]] "
             "[--list-cells] "
             "[--version]\n\n%s\n\n"
             "  --quick        reduced sweep for CI (also QUICK=1 in the environment)\n"
             "  --smoke        the smallest run that writes every table and column (make test)\n"
             "  --scale        the full run and the sizes past it, where the experiment has them\n"
             "                 (linear_solvers: J4 at 1024^2, about 1.5 h; also SCALE=1 in the environment)\n"
             "  --out PATH     CSV output (default results/%s.csv); written atomically\n"
             "  --configs DIR  folder with the scene configs (default configs)\n"
             "  --shard I/N    run shard I of N (I = 1..N) only: its share of the cells, balanced by\n"
             "                 their cost hints (largest first, to the least-loaded shard);\n"
             "                 default --out results/shard-<I>of<N>/%s.csv; merge the N shards with\n"
             "                 scripts/merge-shards.sh OUT.csv SHARD1.csv ... SHARDN.csv (a program\n"
             "                 whose CSV is not written cell by cell refuses it: exit 1); <out>.cells\n"
             "                 lists the shard's cells with their hints and measured seconds\n"
             "  --shard-mode M balanced (default) or modulo: the cells with index %% N == I - 1\n"
             "  --list-cells   print every cell: index, sweep group, sweep, index in it, cost hint and\n"
             "                 shard (under --shard I/N, of N), and 1 if it is timed (runs alone under\n"
             "                 the CPU lock), 0 if not; run none, write nothing\n"
             "Progress goes to stderr (CB_QUIET=1 silences it); data goes to the CSV only.\n",
             name, about, name, name);
      return 1;
    }
    if (!strcmp(argv[i], "--version")) {
      printf("%s (clothbench) %s (%s)\n", name, cb_build_git, cb_build_dirty);
      return 1;
    }
    if (!strcmp(argv[i], "--quick")) e->quick = 1;
    else if (!strcmp(argv[i], "--smoke")) e->quick = e->smoke = 1;
    else if (!strcmp(argv[i], "--scale")) e->scale = 1;
    else if (!strcmp(argv[i], "--out") && i + 1 < argc) {
      if (strlen(argv[++i]) >= sizeof e->out - 64) { /* room for the side tables' _<name>.csv and .cells */
        fprintf(stderr, "%s: --out: a path of %zu bytes; at most %zu are allowed\n", name, strlen(argv[i]),
                sizeof e->out - 65);
        return -1;
      }
      snprintf(e->out, sizeof e->out, "%s", argv[i]);
      out_given = 1;
    } else if (!strcmp(argv[i], "--configs") && i + 1 < argc) {
      e->configs = argv[++i];
      if (strlen(e->configs) >= CB_PATH_LEN - 256) { /* room for a config's name */
        fprintf(stderr, "%s: --configs: a path of %zu bytes; at most %d are allowed\n", name, strlen(e->configs),
                CB_PATH_LEN - 257);
        return -1;
      }
    } else if (!strcmp(argv[i], "--shard") && i + 1 < argc) {
      int a = 0, b = 0;
      if (parse_shard(argv[++i], &a, &b) != 0) {
        fprintf(stderr, "%s: --shard '%s': expected I/N with 1 <= I <= N <= 1000000 (e.g. --shard 2/3)\n", name,
                argv[i]);
        return -1;
      }
      e->shard = a;
      e->nshards = b;
    } else if (!strcmp(argv[i], "--list-cells")) {
      e->list_cells = 1;
    } else if (!strcmp(argv[i], "--shard-mode") && i + 1 < argc) {
      i++;
      if (!strcmp(argv[i], "balanced")) e->shard_mode = CB_SHARD_BALANCED;
      else if (!strcmp(argv[i], "modulo")) e->shard_mode = CB_SHARD_MODULO;
      else {
        fprintf(stderr, "%s: --shard-mode '%s': expected balanced or modulo\n", name, argv[i]);
        return -1;
      }
    } else {
      fprintf(stderr, "%s: unknown or incomplete option '%s' (see --help)\n", name, argv[i]);
      return -1;
    }
  }
  if (!out_given && e->shard)
    snprintf(e->out, sizeof e->out, "results/shard-%dof%d/%s.csv", e->shard, e->nshards, name);
  else if (!out_given) snprintf(e->out, sizeof e->out, "results/%s.csv", name);
  char what[CB_PATH_LEN * 4];
  const char *ext = strrchr(e->out, '.');
  if (ext && (!strcmp(ext, ".ini") || !strcmp(ext, ".obj"))) {
    fprintf(stderr, "%s: --out %s: a config or mesh name; the output is a CSV (refusing to write it)\n", name, e->out);
    return -1;
  }
  if (input_clash(e, what, sizeof what)) {
    fprintf(stderr, "%s: --out %s is %s; refusing to overwrite an input\n", name, e->out, what);
    return -1;
  }
  /* the CPU lock, shared: a timed experiment (cb_experiment_timed) waits for us;
   * --list-cells runs no cell, so it neither takes nor waits for the lock */
  if (!e->list_cells) e->lock_fd = open(cpu_lock_path(), O_RDWR | O_CREAT | O_CLOEXEC, 0666);
  if (e->lock_fd >= 0) {
    char turn[4096];
    snprintf(turn, sizeof turn, "%s.turn", cpu_lock_path());
    e->turn_fd = open(turn, O_RDWR | O_CREAT | O_CLOEXEC, 0666); /* without it: flock's own order */
  }
  lock_waiting(e, LOCK_SH, "a timed experiment to finish");
  return 0;
}

static int cmp_str(const void *a, const void *b) { return strcmp(*(const char *const *)a, *(const char *const *)b); }

/* "# config <file>: <every effective key>" for each INI file in the configs
 * folder: the scenes an experiment builds are these plus the overrides in its
 * source, which the git revision pins. */
static void write_configs(const cb_experiment *e, FILE *f) {
  DIR *d = opendir(e->configs);
  if (!d) {
    fputs("# configs: ", f);
    cb_provenance_escaped(f, e->configs);
    fputs(" (cannot open)\n", f);
    return;
  }
  char **names = NULL; /* every .ini, however many: a cap applied in readdir order would drop arbitrary ones */
  int n = 0, cap = 0, oom = 0;
  for (struct dirent *de; (de = readdir(d));) {
    size_t len = strlen(de->d_name);
    if (len <= 4 || strcmp(de->d_name + len - 4, ".ini") != 0) continue;
    if (n == cap) {
      char **nn = realloc(names, (size_t)(cap ? 2 * cap : 64) * sizeof *names);
      if (!nn) {
        oom = 1;
        break;
      }
      names = nn;
      cap = cap ? 2 * cap : 64;
    }
    if (!(names[n] = strdup(de->d_name))) {
      oom = 1;
      break;
    }
    n++;
  }
  closedir(d);
  if (oom) fputs("# configs: (out of memory listing the folder: the list below is incomplete)\n", f);
  qsort(names, (size_t)n, sizeof *names, cmp_str);
  for (int i = 0; i < n; i++) {
    char path[CB_PATH_LEN];
    cb_config c;
    snprintf(path, sizeof path, "%s/%s", e->configs, names[i]);
    fputs("# config ", f);
    cb_provenance_escaped(f, path);
    fputs(": ", f);
    if (cb_config_load(path, &c) == CB_OK) cb_provenance_config(f, &c);
    else cb_provenance_escaped(f, cb_error_message());
    fputc('\n', f);
    free(names[i]);
  }
  free(names);
}

static int open_csv(cb_experiment *e, cb_outfile *o, const char *path, const char *extra, const char *header) {
  int st = cb_outfile_open(o, path ? path : e->out);
  if (st) return st;
  cb_provenance_write(o->f, e->name, e->argc, e->argv, NULL);
  write_configs(e, o->f);
  fprintf(o->f, "# experiment: %s\n# quick: %d\n", e->name, e->quick);
  if (e->smoke) fputs("# smoke: 1\n", o->f);
  fprintf(o->f, "# cpu_lock: %s\n",
          e->lock_fd < 0  ? "none (the lock file could not be opened)"
          : e->timed      ? "exclusive (timed: no other clothbench experiment ran meanwhile)"
          : e->cell_locks ? "per cell (timed cells exclusive: nothing else ran beside them; untimed cells shared)"
                          : "shared (untimed: other untimed experiments may have run meanwhile)");
  if (extra && *extra) fputs(extra, o->f);
  fprintf(o->f, "%s\n", header);
  return CB_OK;
}

int cb_experiment_csv(cb_experiment *e, cb_outfile *o, const char *path, const char *extra, const char *header) {
  memset(o, 0, sizeof *o);
  if (e->shard) { /* a usage error, as a bad --shard value is: exit 1, nothing written */
    fprintf(stderr,
            "%s: --shard %d/%d: this program writes its CSV outside the sweep runner and cannot be sharded; "
            "run it without --shard\n",
            e->name, e->shard, e->nshards);
    exit(1);
  }
  if (e->list_cells) { /* --list-cells: no cells to list; nothing runs, nothing is written (it ran the whole
                        * program before: scripts/lib/all-plan.py lists every experiment's cells) */
    fflush(stdout);
    exit(0);
  }
  return open_csv(e, o, path, extra, header);
}

int cb_experiment_table(cb_experiment *e, const char *name, const char *extra, const char *header) {
  if (e->ntables >= CB_EXPERIMENT_MAX_TABLES)
    return cb_fail("%s: more than %d tables", e->name, CB_EXPERIMENT_MAX_TABLES);
  if (name && (!*name || strlen(name) >= sizeof e->table_name[0] || strpbrk(name, " /\t\n")))
    return cb_fail("%s: bad table name '%s'", e->name, name);
  int t = e->ntables;
  char path[sizeof e->out + 64];
  if (name) {
    char suffix[64];
    snprintf(suffix, sizeof suffix, "%s.csv", name);
    cb_experiment_side_path(e, suffix, path, sizeof path);
  }
  int st = open_csv(e, &e->table[t], name ? path : NULL, extra, header);
  if (st) return st < 0 ? st : -st;
  snprintf(e->table_name[t], sizeof e->table_name[t], "%s", name ? name : "");
  e->ntables++;
  return t;
}

/* <out>.cells: "shard I N C MODE", "tables - side1 side2 ...", then one line
 * per cell this shard ran (sweep.c): its index, the rows it wrote to each
 * table, its sweep group, sweep name and index there, cost hint and seconds. */
static int write_cells(cb_experiment *e, cb_outfile *o) {
  char path[sizeof e->out + 8];
  snprintf(path, sizeof path, "%s.cells", e->out);
  int st = cb_outfile_open(o, path);
  if (st) return st;
  fprintf(o->f, "shard %d %d %ld %s\ntables", e->shard, e->nshards, e->ncells,
          e->shard_mode == CB_SHARD_MODULO ? "modulo" : "balanced");
  for (int t = 0; t < e->ntables; t++) fprintf(o->f, " %s", e->table_name[t][0] ? e->table_name[t] : "-");
  fputc('\n', o->f);
  if (e->cells) fflush(e->cells);
  if (e->cells_len) fwrite(e->cells_log, 1, e->cells_len, o->f);
  return cb_outfile_finish(o);
}

static void drop_cells(cb_experiment *e) {
  if (e->cells) fclose(e->cells);
  if (e->times) fclose(e->times);
  free(e->times_log);
  e->times = NULL;
  e->times_log = NULL;
  e->times_len = 0;
  free(e->cells_log);
  free(e->shard_load);
  e->shard_load = NULL;
  e->cells = NULL;
  e->cells_log = NULL;
  e->cells_len = 0;
}

/* <out>.split: the wall seconds this process spent in timed and in untimed
 * cells, the seconds it waited for the CPU lock, then one line per cell it ran, "cell <global index> <1 timed, 0
 * not> <seconds> <sweep>" (make experiments adds them to
 * results/<name>.runtime; scripts/timed-split.py tabulates them and
 * scripts/lib/all-plan.py --times balances a cluster's groups by them). */
static int write_split(const cb_experiment *e) {
  char path[sizeof e->out + 8];
  snprintf(path, sizeof path, "%s.split", e->out);
  cb_outfile o;
  if (cb_outfile_open(&o, path)) return CB_EIO;
  double timed = e->cell_s[1], untimed = e->cell_s[0];
  if (!e->cell_locks) { /* the process held one lock throughout: all its cells are of its kind */
    timed = e->timed ? e->cell_s[0] + e->cell_s[1] : 0;
    untimed = e->timed ? 0 : e->cell_s[0] + e->cell_s[1];
  }
  fprintf(o.f, "timed_cells_s: %.3f\nuntimed_cells_s: %.3f\ncell_locks: %d\nlock_wait_s: %.3f\n", timed, untimed,
          e->cell_locks, e->lock_wait_s);
  if (e->times && fflush(e->times) == 0 && e->times_len) fwrite(e->times_log, 1, e->times_len, o.f);
  return cb_outfile_commit(&o) ? CB_EIO : CB_OK;
}

int cb_experiment_end(cb_experiment *e, int st) {
  if (e->list_cells) { /* the cells were listed; nothing is written */
    for (int t = 0; t < e->ntables; t++) cb_outfile_abort(&e->table[t]);
    drop_cells(e);
    if (st) fprintf(stderr, "%s: %s\n", e->name, cb_error_message());
    return st;
  }
  /* all of the run's tables (and its cell list) or none: each is finished
   * (flushed, checked, synced) before any replaces the previous run's, so a
   * full disk or a quota on one table leaves the previous run whole */
  cb_outfile cells = {0};
  if (st == CB_OK) st = check_untimed(e);
  for (int t = 0; t < e->ntables; t++)
    if (st == CB_OK && cb_outfile_finish(&e->table[t])) st = CB_EIO;
  if (st == CB_OK && e->shard && write_cells(e, &cells)) st = CB_EIO;
  if (st == CB_OK) {
    for (int t = 0; t < e->ntables; t++)
      if (st == CB_OK && cb_outfile_publish(&e->table[t])) st = CB_EIO;
    if (st == CB_OK && e->shard && cb_outfile_publish(&cells)) st = CB_EIO;
    if (st == CB_OK && write_split(e)) st = CB_EIO; /* the cells' seconds, beside the published run */
  }
  for (int t = 0; t < e->ntables; t++) cb_outfile_abort(&e->table[t]);
  cb_outfile_abort(&cells);
  drop_cells(e);
  if (st) fprintf(stderr, "%s: %s\n", e->name, cb_error_message());
  return st;
}

int cb_experiment_config(const cb_experiment *e, const char *file, const char *const *sets, cb_config *out) {
  char path[CB_PATH_LEN];
  snprintf(path, sizeof path, "%s/%s", e->configs, file);
  int st = cb_config_load(path, out);
  for (int i = 0; st == CB_OK && sets && sets[i]; i++) st = cb_config_set(out, sets[i]);
  return st;
}

void cb_experiment_side_path(const cb_experiment *e, const char *suffix, char *buf, size_t n) {
  const char *dot = strrchr(e->out, '.');
  int len = dot ? (int)(dot - e->out) : (int)strlen(e->out);
  snprintf(buf, n, "%.*s_%s", len, e->out, suffix);
}
