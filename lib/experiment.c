#include "experiment.h"

#include <dirent.h>

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "provenance.h"
#include "status.h"

int cb_experiment_begin(cb_experiment *e, const char *name, const char *about, int argc, char **argv) {
  memset(e, 0, sizeof *e);
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
  snprintf(e->out, sizeof e->out, "results/%s.csv", name);
  for (int i = 1; i < argc; i++) {
    if (!strcmp(argv[i], "--help") || !strcmp(argv[i], "-h")) {
      printf("usage: %s [--quick] [--out PATH] [--configs DIR]\n\n%s\n\n"
             "  --quick        reduced sweep for CI (also QUICK=1 in the environment)\n"
             "  --out PATH     CSV output (default results/%s.csv); written atomically\n"
             "  --configs DIR  folder with the scene configs (default configs)\n"
             "Progress goes to stderr (CB_QUIET=1 silences it); data goes to the CSV only.\n",
             name, about, name);
      return 1;
    }
    if (!strcmp(argv[i], "--quick")) e->quick = 1;
    else if (!strcmp(argv[i], "--out") && i + 1 < argc) snprintf(e->out, sizeof e->out, "%s", argv[++i]);
    else if (!strcmp(argv[i], "--configs") && i + 1 < argc) e->configs = argv[++i];
    else {
      fprintf(stderr, "%s: unknown or incomplete option '%s' (see --help)\n", name, argv[i]);
      return -1;
    }
  }
  return 0;
}

static int cmp_str(const void *a, const void *b) { return strcmp(*(const char *const *)a, *(const char *const *)b); }

/* "# config <file>: <every effective key>" for each INI file in the configs
 * folder: the scenes an experiment builds are these plus the overrides in its
 * source, which the git revision pins. */
static void write_configs(const cb_experiment *e, FILE *f) {
  DIR *d = opendir(e->configs);
  if (!d) {
    fprintf(f, "# configs: %s (cannot open)\n", e->configs);
    return;
  }
  char *names[256];
  int n = 0;
  for (struct dirent *de; (de = readdir(d)) && n < 256;) {
    size_t len = strlen(de->d_name);
    if (len > 4 && strcmp(de->d_name + len - 4, ".ini") == 0) names[n++] = strdup(de->d_name);
  }
  closedir(d);
  qsort(names, (size_t)n, sizeof *names, cmp_str);
  for (int i = 0; i < n; i++) {
    char path[CB_PATH_LEN];
    cb_config c;
    snprintf(path, sizeof path, "%s/%s", e->configs, names[i]);
    if (cb_config_load(path, &c) == CB_OK) {
      fprintf(f, "# config %s: ", path);
      cb_config_write(&c, f, " ");
      fputc('\n', f);
    } else {
      fprintf(f, "# config %s: %s\n", path, cb_error_message());
    }
    free(names[i]);
  }
}

int cb_experiment_csv(cb_experiment *e, cb_outfile *o, const char *path, const char *extra, const char *header) {
  int st = cb_outfile_open(o, path ? path : e->out);
  if (st) return st;
  cb_provenance_write(o->f, e->name, e->argc, e->argv, NULL);
  write_configs(e, o->f);
  fprintf(o->f, "# experiment: %s\n# quick: %d\n", e->name, e->quick);
  if (extra && *extra) fputs(extra, o->f);
  fprintf(o->f, "%s\n", header);
  return CB_OK;
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
