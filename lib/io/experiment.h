/* What every experiment program shares: its command line, its CSV (opened
 * atomically with the provenance lines), progress, and config loading.
 *
 * Common options:
 *   --quick        reduced sweep (QUICK=1 in the environment does the same)
 *   --out PATH     main CSV (default results/<name>.csv)
 *   --configs DIR  folder holding hanging.ini etc. (default configs)
 *   --help         usage and what the experiment decides */
#ifndef CB_EXPERIMENT_H
#define CB_EXPERIMENT_H

#include "config.h"
#include "outfile.h"
#include "progress.h"

typedef struct cb_experiment {
  const char *name;
  int quick;
  char out[2048];
  const char *configs;
  int argc;
  char **argv;
  cb_outfile csv;
  cb_progress progress;
} cb_experiment;

/* Returns 0 to go on, 1 when --help was printed (exit 0), negative on a bad
 * option (message printed; exit 1). about: a paragraph for --help. */
int cb_experiment_begin(cb_experiment *e, const char *name, const char *about, int argc, char **argv);

/* Opens a CSV at path (NULL = the main --out path): provenance lines,
 * "# experiment:", "# quick:", the caller's extra "# ..." lines (may be
 * NULL), then the header row. */
int cb_experiment_csv(cb_experiment *e, cb_outfile *o, const char *path, const char *extra, const char *header);

/* <configs>/<file>, then the NULL-terminated "section.key=value" overrides. */
int cb_experiment_config(const cb_experiment *e, const char *file, const char *const *sets, cb_config *out);

/* Path of a side output next to the main CSV: results/<name>_<suffix>. */
void cb_experiment_side_path(const cb_experiment *e, const char *suffix, char *buf, size_t n);

#endif
