#include "provenance.h"

#include <cblas.h>
#include <cholmod.h>
#include <gsl/gsl_errno.h>
#include <gsl/gsl_version.h>
#include <stdlib.h>
#include <time.h>

#include "threads.h"

int cb_runtime_init(void) {
  gsl_set_error_handler_off();
  return cb_threads_init();
}

void cb_provenance_write(FILE *f, const char *program, int argc, char **argv, const cb_config *cfg) {
  int cv[3] = {0, 0, 0};
  cholmod_version(cv);
  time_t now = time(NULL);
  struct tm tmv;
  char date[64];
  gmtime_r(&now, &tmv);
  strftime(date, sizeof date, "%Y-%m-%dT%H:%M:%SZ", &tmv);
  const char *omp = getenv("OMP_NUM_THREADS");
  const cb_threads_info *th = cb_threads_info_get();
  fprintf(f, "# program: %s\n", program);
  fprintf(f, "# git_revision: %s (%s)\n", cb_build_git, cb_build_dirty);
  fprintf(f, "# compiler: gcc %s\n", __VERSION__);
  fprintf(f, "# cflags: %s\n", cb_build_cflags);
  fprintf(f, "# cholmod: %d.%d.%d\n", cv[0], cv[1], cv[2]);
  fprintf(f, "# gsl: %s\n", gsl_version);
  fprintf(f, "# openblas: %s\n", openblas_get_config());
  fprintf(f, "# blas_threads: %d\n", openblas_get_num_threads());
  fprintf(f, "# omp_num_threads: %s\n", omp && *omp ? omp : "unset");
  fprintf(f, "# threads_requested: openblas %d, openmp %d (dynamic on: caps CHOLMOD's num_threads(4) regions)\n",
          th->blas_requested, th->omp_requested);
  fprintf(f, "# threads_observed: cholmod_factorize %d, dgemm %d (threads whose CPU time grew during a probe: "
             "supernodal factorisation of a 96^2-grid Laplacian, 384^3 dgemm)\n",
          th->cholmod_observed, th->dgemm_observed);
  fputs("# command:", f);
  for (int i = 0; i < argc; i++) fprintf(f, " %s", argv[i]);
  fputc('\n', f);
  if (cfg) {
    fprintf(f, "# config: %s\n", cfg->path[0] ? cfg->path : "(defaults)");
    fprintf(f, "# overrides: %s\n", cfg->overrides[0] ? cfg->overrides : "(none)");
    fputs("# config_effective: ", f);
    cb_config_write(cfg, f, " ");
    fputc('\n', f);
  }
  fprintf(f, "# date: %s\n", date);
}
