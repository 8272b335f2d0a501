/* bench_scale: time per step and peak memory from 64^2 to 1024^2 vertices
 * (make bench SCALE=1; not part of make test).
 *
 * Each (method, size) runs in a process of its own, so that one
 * configuration's memory never hides another's: this program, the driver,
 * starts itself with --child METHOD N for each, reads the child's one result
 * line from a pipe and its peak resident set from wait4()'s rusage
 * (ru_maxrss of that child alone). Every child runs under a budget the
 * driver sets before exec: RLIMIT_AS (--mem-limit-gib, default 16; address
 * space: an allocation beyond it fails and the child reports it, or dies of
 * it), RLIMIT_CPU (--cpu-limit-s, default 900: SIGXCPU) and a wall-clock
 * alarm (--wall-limit-s, default 1800: SIGALRM, kept across exec). A
 * configuration that fails or exceeds its budget keeps its row, with its
 * status, the reason in `note` and what it had measured before it ended
 * (the child reports its set-up and its warm-up step as it goes); the same
 * method is then not tried at the larger sizes (status skipped, and why), so
 * nothing is left out silently.
 *
 * Methods, each from the harness's own configs and integrators
 * (cb_scene_from_config, cb_integrator_from_config; no scene or solver
 * here): on configs/hanging.ini (10 m, 1 kg per vertex, k = 8000 N/m,
 * dt = 1/30 s, two top corners pinned), mesh.n = N:
 *   explicit            symplectic Euler at dt = 1e-5 s (its cost per step;
 *                       its stable step is far below 1/30 s);
 *   newton_cholmod      one Newton iteration (Baraff-Witkin), CHOLMOD;
 *   newton_cg32         one Newton iteration, CG cut at 32 iterations;
 *   newton_cheb32       one Newton iteration, Chebyshev-Jacobi cut at 32
 *                       iterations (alpha and rho auto, estimate amortised);
 *   newton_pcg_matched  one Newton iteration, block-Jacobi PCG to the
 *                       accuracy of newton_cholmod at the same size: its
 *                       solver.tol is CHOLMOD's step's relative |grad F|
 *                       (column rel_grad_hat) times --match-frac (default
 *                       0.5), so the inexact solve adds at most about half
 *                       of the nonlinear remainder CHOLMOD's exact solve
 *                       leaves: the two steps are equally accurate to within
 *                       that, and the row records both;
 *   newton_petsc-gamg_matched, newton_petsc-hypre_matched,
 *   newton_petsc-ml_matched, newton_petsc-icc_matched
 *                       the same with the PETSc presets (CG with GAMG,
 *                       BoomerAMG, ML, ICC; docs/solvers-petsc.md);
 *   pd10                projective dynamics, 10 local/global iterations
 *                       (Liu et al. 2013), CHOLMOD factor once at set-up;
 *   lbfgs32             L-BFGS with pd's matrix as initial Hessian, at most
 *                       32 iterations;
 * and on configs/lab.ini (pins 0 and N-1):
 *   lab                 the GAMES103 lab's frame, chebyshev-nl, 32 iterations.
 * Every child: the scene and the integrator (set-up, including CHOLMOD's
 * analysis and pd's factorisation), one warm-up step from the initial state
 * (first_step_ms: it also pays the first touch of the factor's pages), then
 * steps from the state reached until about --budget-ms of stepping or 15
 * steps, at least one; step_ms is their median, with min and max. A warm-up
 * step longer than --max-warm-s (default 120) is itself the step measured
 * (steps_timed = 0), so that the largest sizes cost one step. Accuracy
 * of the timed steps: rel_grad_hat = |grad F(x1)| / |grad F(xhat)| (median;
 * the implicit-Euler objective every implicit method minimises; empty for
 * explicit) and the inner solve's relative residual.
 * Fits (side file results/bench_scale_fit.csv): the growth exponent of
 * step_ms and of peak RSS in the number of vertices, least squares on
 * log-log (gsl_fit_linear) over every measured size, and over the three
 * largest.
 * Output: results/bench_scale.csv; scripts/readme-bench-scale.py writes the
 * README's table, plots/bench_scale.gp the figure. */
#define _GNU_SOURCE
#include <errno.h>
#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/time.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>

#include <gsl/gsl_fit.h>

#include <clothbench/integrator.h>
#include <clothbench/scene.h>
#include <clothbench/status.h>
#include <clothbench/timer.h>
#include <clothbench/timer.h>
#include "bind.h"
#include "csv.h"
#include "experiment.h"
#include "provenance.h"
#include "stats.h"

typedef struct {
  const char *name, *config;
  const char *sets[8];
  int matched; /* solver.tol from newton_cholmod's accuracy at the same size */
} scale_method;

static const scale_method METHODS[] = {
    {"explicit", "hanging.ini", {"integrator.method=explicit", "integrator.dt=1e-5", NULL}, 0},
    {"newton_cholmod",
     "hanging.ini",
     {"integrator.method=newton", "integrator.max_iters=1", "integrator.tol=0", "solver.method=cholmod", NULL},
     0},
    {"newton_cg32",
     "hanging.ini",
     {"integrator.method=newton", "integrator.max_iters=1", "integrator.tol=0", "solver.method=cg",
      "solver.max_iters=32", "solver.tol=0", NULL},
     0},
    {"newton_cheb32",
     "hanging.ini",
     {"integrator.method=newton", "integrator.max_iters=1", "integrator.tol=0", "solver.method=chebyshev",
      "solver.max_iters=32", "solver.tol=0", "solver.alpha=auto", "solver.rho=auto"},
     0},
    {"newton_pcg_matched",
     "hanging.ini",
     {"integrator.method=newton", "integrator.max_iters=1", "integrator.tol=0", "solver.method=pcg",
      "solver.max_iters=100000", NULL},
     1},
#define PETSC_MATCHED(preset) \
  { \
    "newton_" preset "_matched", "hanging.ini", \
        {"integrator.method=newton", "integrator.max_iters=1",  "integrator.tol=0", \
         "solver.method=" preset,    "solver.max_iters=100000", NULL}, \
        1 \
  }
    /* the PETSc family (docs/solvers-petsc.md) at newton_cholmod's accuracy, as newton_pcg_matched */
    PETSC_MATCHED("petsc-gamg"),
    PETSC_MATCHED("petsc-hypre"),
    PETSC_MATCHED("petsc-ml"),
    PETSC_MATCHED("petsc-icc"),
#undef PETSC_MATCHED
    {"lab", "lab.ini", {"integrator.method=chebyshev-nl", "integrator.iters=32", NULL}, 0},
    {"pd10", "hanging.ini", {"integrator.method=pd", "integrator.iters=10", "solver.method=cholmod", NULL}, 0},
    {"lbfgs32", "hanging.ini", {"integrator.method=lbfgs", "integrator.iters=32", "solver.method=cholmod", NULL}, 0},
};
enum { NMETHODS = (int)(sizeof METHODS / sizeof METHODS[0]), MAXSIZES = 16, MAXSTEPS = 15 };

static const scale_method *method_find(const char *name) {
  for (int m = 0; m < NMETHODS; m++)
    if (!strcmp(METHODS[m].name, name)) return &METHODS[m];
  return NULL;
}

/* ---- the child: one (method, size), one line on stdout ---- */

/* "fail <status> <message>" (commas and newlines replaced: it becomes a CSV field) */
static int child_fail(int st, const char *what) {
  char msg[512];
  snprintf(msg, sizeof msg, "%s: %s", what, cb_error_message());
  for (char *p = msg; *p; p++)
    if (*p == ',' || *p == '\n' || *p == '\r') *p = ';';
  printf("fail %s %s\n", cb_status_name(st), msg);
  fflush(stdout);
  return 0;
}

static int child(const char *configs, const char *mname, int n, double tol, double budget_ms, double max_warm_ms) {
  const scale_method *m = method_find(mname);
  if (!m) {
    fprintf(stderr, "bench_scale: unknown method '%s'\n", mname);
    return 1;
  }
  double t0 = cb_now_ms();
  char path[4096], setn[64], pins[64], tols[64];
  snprintf(path, sizeof path, "%s/%s", configs, m->config);
  cb_config c;
  int st = cb_config_load(path, &c);
  if (st) return child_fail(st, "config");
  snprintf(setn, sizeof setn, "mesh.n=%d", n);
  snprintf(pins, sizeof pins, "scene.pins=0 %d", n - 1);
  snprintf(tols, sizeof tols, "solver.tol=%.17g", tol);
  st = cb_config_set(&c, setn);
  if (!st && !strcmp(m->config, "lab.ini")) st = cb_config_set(&c, pins);
  for (int i = 0; !st && i < 8 && m->sets[i]; i++) st = cb_config_set(&c, m->sets[i]);
  if (!st && m->matched) st = cb_config_set(&c, tols);
  if (st) return child_fail(st, "config");
  cb_scene *s = NULL;
  if ((st = cb_scene_from_config(&c, &s))) return child_fail(st, "scene");
  cb_integrator *it = NULL;
  if ((st = cb_integrator_from_config(&c, s, NULL, &it))) return child_fail(st, "integrator");
  double setup_ms = cb_now_ms() - t0;
  /* what is known so far, in case the budget ends the child before its result line */
  printf("setup %d %d %.6g\n", s->mesh.nv, s->sys.A.n, setup_ms);
  fflush(stdout);
  int nv3 = 3 * s->mesh.nv;
  double *x = malloc((size_t)nv3 * sizeof *x), *v = malloc((size_t)nv3 * sizeof *v);
  if (!x || !v) return child_fail(CB_ENOMEM, "state arrays");
  memcpy(x, s->x0, (size_t)nv3 * sizeof *x);
  memcpy(v, s->v0, (size_t)nv3 * sizeof *v);
  cb_step_stats stt;
  st = cb_integrator_step(it, x, v, &stt);
  if (cb_status_is_fatal(st)) return child_fail(st, "warm-up step");
  double first_ms = stt.wall_ms;
  double first_relg = stt.rel_grad_hat;
  printf("warm %.6g\n", first_ms);
  fflush(stdout);
  double wall[MAXSTEPS], relg[MAXSTEPS], relr[MAXSTEPS], iters = 0, liters = 0, stepped = 0;
  int k = 0, timed = first_ms <= max_warm_ms; /* else the warm-up step is the one measured (steps_timed = 0) */
  if (!timed) {
    wall[0] = first_ms;
    relg[0] = stt.rel_grad_hat;
    relr[0] = it->solver ? it->solver->stats.rel_residual : NAN;
    iters = stt.newton_iters;
    liters = stt.linear_iters;
  }
  while (timed && k < MAXSTEPS && (k == 0 || stepped < budget_ms)) {
    st = cb_integrator_step(it, x, v, &stt);
    if (cb_status_is_fatal(st)) return child_fail(st, "timed step");
    wall[k] = stt.wall_ms;
    relg[k] = stt.rel_grad_hat;
    relr[k] = it->solver ? it->solver->stats.rel_residual : NAN;
    iters += stt.newton_iters;
    liters += stt.linear_iters;
    stepped += stt.wall_ms;
    k++;
  }
  int nk = timed ? k : 1;
  double lo = wall[0], hi = wall[0];
  for (int i = 1; i < nk; i++) {
    lo = fmin(lo, wall[i]);
    hi = fmax(hi, wall[i]);
  }
  double med = cb_median(wall, nk), g = cb_median(relg, nk), r = cb_median(relr, nk);
  int is_explicit = !strcmp(it->type->name, "explicit");
  int direct = it->solver && it->solver->stats.factor_nnz > 0;
  /* ok <vertices> <dofs> <steps> <step> <min> <max> <first> <setup> <analyze> <rel_grad_hat> <rel_residual>
   *    <iters/step> <linear iters/step> <nnz_l> <the warm-up step's rel_grad_hat> <status of the last step>; "-" = not
   * applicable */
  printf("ok %d %d %d %.6g %.6g %.6g %.6g %.6g ", s->mesh.nv, s->sys.A.n, k, med, lo, hi, first_ms, setup_ms);
  if (it->solver) printf("%.6g ", it->solver->stats.analyze_ms);
  else printf("- ");
  if (is_explicit) printf("- ");
  else printf("%.17g ", g);
  if (it->solver && !direct && isfinite(r)) printf("%.17g ", r);
  else printf("- ");
  printf("%.6g %.6g ", iters / nk, liters / nk);
  if (direct) printf("%.17g ", it->solver->stats.factor_nnz);
  else printf("- ");
  if (is_explicit) printf("- ");
  else printf("%.17g ", first_relg);
  printf("%s\n", cb_status_name(st));
  fflush(stdout);
  cb_integrator_free(it);
  cb_scene_free(s);
  free(x);
  free(v);
  return 0;
}

/* ---- the driver ---- */

typedef struct {
  int ok; /* 1: measured */
  char status[64], note[600];
  int vertices, dofs, steps;
  double step, lo, hi, first, setup, analyze, relg, relr, iters, liters, nnzl, rss_bytes, wall_s, tol, first_relg;
} result;

/* a field of the child's line: "-" is not applicable */
static double field(const char *s) { return strcmp(s, "-") ? strtod(s, NULL) : NAN; }

static void run_child(const char *self, const char *configs, const char *mname, int n, double tol, double budget_ms,
                      double max_warm_s, double mem_gib, double cpu_s, double wall_s, result *r) {
  memset(r, 0, sizeof *r);
  r->tol = tol;
  int fd[2];
  if (pipe(fd)) {
    snprintf(r->status, sizeof r->status, "failed");
    snprintf(r->note, sizeof r->note, "pipe: %s", strerror(errno));
    return;
  }
  char ns[32], ts[64], bs[64], ws_[64];
  snprintf(ns, sizeof ns, "%d", n);
  snprintf(ts, sizeof ts, "%.17g", tol);
  snprintf(bs, sizeof bs, "%.17g", budget_ms);
  snprintf(ws_, sizeof ws_, "%.17g", max_warm_s * 1000);
  double t0 = cb_now_ms();
  fflush(NULL);
  pid_t pid = fork();
  if (pid == 0) {
    close(fd[0]);
    if (dup2(fd[1], 1) < 0) _exit(127);
    close(fd[1]);
    struct rlimit as = {(rlim_t)(mem_gib * 1073741824.0), (rlim_t)(mem_gib * 1073741824.0)};
    struct rlimit cpu = {(rlim_t)cpu_s, (rlim_t)cpu_s + 5};
    if (mem_gib > 0) setrlimit(RLIMIT_AS, &as);
    if (cpu_s > 0) setrlimit(RLIMIT_CPU, &cpu);
    if (wall_s > 0) alarm((unsigned)ceil(wall_s)); /* kept across exec: SIGALRM ends the child */
    execl(self, self, "--child", mname, ns, "--configs", configs, "--tol", ts, "--budget-ms", bs, "--max-warm-ms", ws_,
          (char *)NULL);
    _exit(127);
  }
  close(fd[1]);
  if (pid < 0) {
    close(fd[0]);
    snprintf(r->status, sizeof r->status, "failed");
    snprintf(r->note, sizeof r->note, "fork: %s", strerror(errno));
    return;
  }
  char line[4096] = "";
  size_t len = 0;
  for (;;) {
    ssize_t got = read(fd[0], line + len, sizeof line - 1 - len);
    if (got < 0 && errno == EINTR) continue;
    if (got <= 0) break;
    len += (size_t)got;
    if (len >= sizeof line - 1) break;
  }
  line[len] = 0;
  close(fd[0]);
  int ws = 0;
  struct rusage ru;
  memset(&ru, 0, sizeof ru);
  while (wait4(pid, &ws, 0, &ru) < 0 && errno == EINTR) {}
  r->wall_s = (cb_now_ms() - t0) / 1000.0;      /* (r->wall_s: this child's; wall_s: the budget) */
  r->rss_bytes = (double)ru.ru_maxrss * 1024.0; /* Linux: kilobytes */
  /* the last line is the result; "setup" and "warm" lines say how far a child that did not finish got */
  char *last = line, *p = line; /* p: the line being read */
  for (char *nl; (nl = strchr(p, '\n')); p = nl + 1) {
    *nl = 0;
    if (!strncmp(p, "setup ", 6)) sscanf(p + 6, "%d %d %lf", &r->vertices, &r->dofs, &r->setup);
    else if (!strncmp(p, "warm ", 5)) r->first = strtod(p + 5, NULL);
    last = p;
  }
  memmove(line, last, strlen(last) + 1);
  char got_to[160] = "";
  if (r->first > 0)
    snprintf(got_to, sizeof got_to, "; it had set up in %.3g s and taken its warm-up step in %.3g s", r->setup / 1000,
             r->first / 1000);
  else if (r->setup > 0) snprintf(got_to, sizeof got_to, "; it had set up in %.3g s", r->setup / 1000);
  if (!strncmp(line, "ok ", 3)) {
    char f[16][64];
    int nf = sscanf(line + 3, "%63s %63s %63s %63s %63s %63s %63s %63s %63s %63s %63s %63s %63s %63s %63s %63s", f[0],
                    f[1], f[2], f[3], f[4], f[5], f[6], f[7], f[8], f[9], f[10], f[11], f[12], f[13], f[14], f[15]);
    if (nf == 16) {
      r->ok = 1;
      r->vertices = atoi(f[0]);
      r->dofs = atoi(f[1]);
      r->steps = atoi(f[2]);
      r->step = field(f[3]);
      r->lo = field(f[4]);
      r->hi = field(f[5]);
      r->first = field(f[6]);
      r->setup = field(f[7]);
      r->analyze = field(f[8]);
      r->relg = field(f[9]);
      r->relr = field(f[10]);
      r->iters = field(f[11]);
      r->liters = field(f[12]);
      r->nnzl = field(f[13]);
      r->first_relg = field(f[14]);
      snprintf(r->status, sizeof r->status, "%s", f[15]);
      return;
    }
  }
  if (!strncmp(line, "fail ", 5)) {
    char stname[64] = "failed";
    int used = 0;
    sscanf(line + 5, "%63s %n", stname, &used);
    snprintf(r->status, sizeof r->status, "%s", stname);
    snprintf(r->note, sizeof r->note, "%s (RLIMIT_AS %.3g GiB; peak RSS %.3g GiB)", line + 5 + used, mem_gib,
             r->rss_bytes / 1073741824.0);
    return;
  }
  if (WIFSIGNALED(ws) && WTERMSIG(ws) == SIGXCPU) {
    snprintf(r->status, sizeof r->status, "over_budget");
    snprintf(r->note, sizeof r->note, "CPU time budget exceeded (RLIMIT_CPU %.0f s) at peak RSS %.3g GiB%s", cpu_s,
             r->rss_bytes / 1073741824.0, got_to);
  } else if (WIFSIGNALED(ws) && WTERMSIG(ws) == SIGALRM) {
    snprintf(r->status, sizeof r->status, "over_budget");
    snprintf(r->note, sizeof r->note, "wall-clock budget exceeded (%.0f s) at peak RSS %.3g GiB%s", wall_s,
             r->rss_bytes / 1073741824.0, got_to);
  } else if (WIFSIGNALED(ws)) {
    snprintf(r->status, sizeof r->status, "killed");
    snprintf(r->note, sizeof r->note, "killed by signal %d (%s) at peak RSS %.3g GiB under RLIMIT_AS %.3g GiB%s",
             WTERMSIG(ws), strsignal(WTERMSIG(ws)), r->rss_bytes / 1073741824.0, mem_gib, got_to);
  } else {
    snprintf(r->status, sizeof r->status, "failed");
    snprintf(r->note, sizeof r->note, "exit %d without a result line", WIFEXITED(ws) ? WEXITSTATUS(ws) : -1);
  }
  for (char *c = r->note; *c; c++)
    if (*c == ',' || *c == '\n' || *c == '\r') *c = ';';
}

static void put_num(FILE *f, double v, const char *fmt) {
  if (isnan(v)) cb_csv_printf(f, ",%.17g", cb_csv_na());
  else cb_csv_printf(f, fmt, v);
}

/* the growth exponent of y in vertices over points [a, b) of (lv, ly), and its fit row */
static void fit_row(FILE *f, const char *method, const char *quantity, const char *range, const double *lv,
                    const double *ly, const int *ns, int a, int b) {
  int k = b - a;
  if (k < 2) return;
  double c0, c1, cov00, cov01, cov11, sumsq, mean = 0, ss = 0;
  gsl_fit_linear(lv + a, 1, ly + a, 1, (size_t)k, &c0, &c1, &cov00, &cov01, &cov11, &sumsq);
  for (int i = a; i < b; i++) mean += ly[i] / k;
  for (int i = a; i < b; i++) ss += (ly[i] - mean) * (ly[i] - mean);
  double na = cb_csv_na();
  cb_csv_printf(f, "%s,%s,%s,%d,%d,%d,%.6g,%.6g,%.6g\n", method, quantity, range, k, ns[a], ns[b - 1], c1,
                k > 2 ? sqrt(cov11) : na, ss > 0 ? 1.0 - sumsq / ss : na);
}

static int parse_list(const char *s, int *out, int cap) {
  int k = 0;
  while (*s && k < cap) {
    char *end;
    long v = strtol(s, &end, 10);
    if (end == s || v < 4 || v > 4096) return -1;
    out[k++] = (int)v;
    s = end;
    if (*s == ',') s++;
    else if (*s) return -1;
  }
  return k;
}

int main(int argc, char **argv) {
  /* the child: no CPU lock (the driver holds it exclusively), no CSV */
  if (argc >= 4 && !strcmp(argv[1], "--child")) {
    if (cb_runtime_init()) {
      fprintf(stderr, "bench_scale: %s\n", cb_error_message());
      return 1;
    }
    const char *configs = "configs";
    double tol = 0, budget = 3000, max_warm = 120000;
    for (int i = 4; i + 1 < argc; i += 2) {
      if (!strcmp(argv[i], "--configs")) configs = argv[i + 1];
      else if (!strcmp(argv[i], "--tol")) tol = strtod(argv[i + 1], NULL);
      else if (!strcmp(argv[i], "--budget-ms")) budget = strtod(argv[i + 1], NULL);
      else if (!strcmp(argv[i], "--max-warm-ms")) max_warm = strtod(argv[i + 1], NULL);
    }
    return child(configs, argv[2], atoi(argv[3]), tol, budget, max_warm);
  }
  /* the driver's own options, then the common ones */
  int sizes[MAXSIZES] = {64, 128, 256, 512, 1024}, nsizes = 5;
  const scale_method *run[NMETHODS];
  int nrun = NMETHODS;
  for (int m = 0; m < NMETHODS; m++) run[m] = &METHODS[m];
  double mem_gib = 16, cpu_s = 900, wall_s = 1800, budget_ms = 3000, match_frac = 0.2, max_warm_s = 120;
  int sizes_given = 0;
  char **rest = malloc((size_t)(argc + 1) * sizeof *rest);
  int nrest = 0;
  if (!rest) return 1;
  rest[nrest++] = argv[0];
  for (int i = 1; i < argc; i++) {
    const char *a = argv[i];
    int has = i + 1 < argc;
    if (!strcmp(a, "--sizes") && has) {
      if ((nsizes = parse_list(argv[++i], sizes, MAXSIZES)) < 1) {
        fprintf(stderr,
                "bench_scale: --sizes '%s': expected grid sizes (vertices per side, 4..4096) separated by commas\n",
                argv[i]);
        return 1;
      }
      sizes_given = 1;
    } else if (!strcmp(a, "--methods") && has) {
      char buf[1024];
      snprintf(buf, sizeof buf, "%s", argv[++i]);
      nrun = 0;
      for (char *t = strtok(buf, ","); t; t = strtok(NULL, ",")) {
        const scale_method *m = method_find(t);
        if (!m || nrun >= NMETHODS) {
          fprintf(stderr, "bench_scale: --methods: unknown method '%s'; known:", t);
          for (int q = 0; q < NMETHODS; q++) fprintf(stderr, " %s", METHODS[q].name);
          fputc('\n', stderr);
          return 1;
        }
        run[nrun++] = m;
      }
    } else if ((!strcmp(a, "--mem-limit-gib") || !strcmp(a, "--cpu-limit-s") || !strcmp(a, "--wall-limit-s") ||
                !strcmp(a, "--budget-ms") || !strcmp(a, "--max-warm-s") || !strcmp(a, "--match-frac")) &&
               has) {
      char *end;
      double v = strtod(argv[++i], &end);
      if (*end || !(v >= 0) || !isfinite(v) || (!strcmp(a, "--match-frac") && !(v > 0 && v <= 1))) {
        fprintf(stderr, "bench_scale: %s '%s': expected a number >= 0%s\n", a, argv[i],
                !strcmp(a, "--match-frac") ? " in (0, 1]" : "");
        return 1;
      }
      if (!strcmp(a, "--mem-limit-gib")) mem_gib = v;
      else if (!strcmp(a, "--cpu-limit-s")) cpu_s = v;
      else if (!strcmp(a, "--wall-limit-s")) wall_s = v;
      else if (!strcmp(a, "--max-warm-s")) max_warm_s = v;
      else if (!strcmp(a, "--budget-ms")) budget_ms = v;
      else match_frac = v;
    } else if (!strcmp(a, "--help") || !strcmp(a, "-h")) {
      printf("bench_scale options: [--sizes 64,128,...] [--methods a,b,...] [--mem-limit-gib G (16; 0 = none)]\n"
             "  [--cpu-limit-s S (900 per configuration; 0 = none)] [--wall-limit-s S (1800 per configuration; 0 = "
             "none)]\n"
             "  [--budget-ms MS (3000: stepping time per configuration)] [--max-warm-s S (120: a longer warm-up step "
             "is the one measured)]\n"
             "  [--match-frac F (0.2: newton_pcg_matched's solver.tol = F x newton_cholmod's rel_grad_hat)]\n"
             "  --quick: sizes 32 and 64. Methods:");
      for (int q = 0; q < NMETHODS; q++) printf(" %s", METHODS[q].name);
      printf("\n\n");
      rest[nrest++] = argv[i];
    } else rest[nrest++] = argv[i];
  }
  rest[nrest] = NULL;
  cb_experiment e;
  int r = cb_experiment_begin(&e, "bench_scale",
                              "Time per step and peak RSS against the number of vertices, one process per "
                              "configuration.",
                              nrest, rest);
  if (r) return r > 0 ? 0 : 1;
  e.argc = argc; /* the provenance echoes the whole command */
  e.argv = argv;
  if (e.quick && !sizes_given) {
    sizes[0] = 32;
    sizes[1] = 64;
    nsizes = 2;
  }
  cb_experiment_timed(&e);
  char extra[3072], fit_path[2100];
  double mem_total = (double)sysconf(_SC_PHYS_PAGES) * (double)sysconf(_SC_PAGESIZE);
  snprintf(extra, sizeof extra,
           "# mem_total_bytes: %.17g\n"
           "# one process per (method, n): the driver starts itself with --child and reads the child's peak RSS from "
           "wait4() (ru_maxrss)\n"
           "# budgets per child: RLIMIT_AS %.3g GiB (0 = none), RLIMIT_CPU %.0f s (0 = none), wall clock %.0f s "
           "(SIGALRM; 0 = none);\n"
           "#   a failure or an exceeded budget keeps its row (status, note; what the child measured before it ended: "
           "set-up, warm-up step, peak RSS),\n"
           "#   and the method is then skipped at the larger sizes (status skipped)\n"
           "# step_ms: median (min, max) of steps after one warm-up step from the initial state, as many as fit in "
           "%.0f ms of stepping (1 to 15);\n"
           "#   a warm-up step longer than %.3g s is itself the step measured (steps_timed = 0; it also pays the first "
           "touch of the factor's pages)\n"
           "# setup_ms: scene + integrator (CHOLMOD's analysis; pd's and lbfgs's factorisation); first_step_ms: the "
           "warm-up step\n"
           "# rel_grad_hat: |grad F(x1)| / |grad F(xhat)| of the timed steps (median); first_rel_grad_hat: the same of "
           "the warm-up step (from the initial state,\n"
           "#   the same step for every method: the accuracies to compare where a row measured its warm-up step); "
           "rel_residual: the inner solve's |b - Ax| / |b| (median)\n"
           "# newton_pcg_matched: solver.tol = %.3g x newton_cholmod's rel_grad_hat at the same n (its "
           "first_rel_grad_hat where steps_timed = 0) (tol)\n",
           mem_total, mem_gib, cpu_s, wall_s, budget_ms, max_warm_s, match_frac);
  cb_experiment_side_path(&e, "fit.csv", fit_path, sizeof fit_path);
  cb_outfile csv, fit;
  if (cb_experiment_csv(&e, &csv, NULL, extra,
                        "method,n,vertices,dofs,steps_timed,step_ms,step_min_ms,step_max_ms,first_step_ms,setup_ms,"
                        "analyze_ms,peak_rss_bytes,"
                        "rel_grad_hat,first_rel_grad_hat,rel_residual,iters_per_step,linear_iters_per_step,nnz_l,tol,"
                        "wall_s,status,note") ||
      cb_experiment_csv(&e, &fit, fit_path,
                        "# growth exponent p of y ~ c vertices^p: least squares on (log vertices, log y) "
                        "(gsl_fit_linear), over the sizes measured (range all)\n"
                        "#   or the three largest measured (range top3); exponent_err: its standard error from the "
                        "fit's residuals (empty for 2 points)\n"
                        "# quantity: step_ms (time per step) or peak_rss_bytes (peak resident set of the child "
                        "process)\n",
                        "method,kind,part,samples,n_min,n_max,exponent,exponent_err,fit_r2")) {
    fprintf(stderr, "bench_scale: %s\n", cb_error_message());
    return 2;
  }
  static result res[NMETHODS][MAXSIZES];
  int nsteps = nrun * nsizes, done = 0;
  double t_all = cb_now_ms();
  for (int si = 0; si < nsizes; si++) {
    int n = sizes[si];
    for (int q = 0; q < nrun; q++) {
      const scale_method *m = run[q];
      result *rr = &res[q][si];
      double tol = 0;
      /* the method failed at a smaller size: skipped, with why */
      int prev = si - 1;
      if (prev >= 0 && !res[q][prev].ok) {
        char why[sizeof rr->status];
        snprintf(why, sizeof why, "%s", res[q][prev].status);
        memset(rr, 0, sizeof *rr);
        snprintf(rr->status, sizeof rr->status, "skipped");
        snprintf(rr->note, sizeof rr->note, "not run: %s at n = %d (%s)",
                 !strcmp(why, "skipped") ? "skipped" : "failed", sizes[prev], why);
      } else {
        if (m->matched) { /* newton_cholmod's accuracy at this size, measured just before */
          int qc = -1;
          for (int z = 0; z < nrun; z++)
            if (!strcmp(run[z]->name, "newton_cholmod")) qc = z;
          if (qc < 0 || qc > q || !res[qc][si].ok || !(res[qc][si].relg > 0)) {
            memset(rr, 0, sizeof *rr);
            snprintf(rr->status, sizeof rr->status, "skipped");
            snprintf(rr->note, sizeof rr->note, "not run: no newton_cholmod accuracy to match at n = %d%s", n,
                     qc < 0 || qc > q ? " (newton_cholmod not run before it)" : "");
            goto record;
          }
          /* the accuracy of the timed steps; of the warm-up step when that is what CHOLMOD's row measured */
          tol = match_frac * (res[qc][si].steps > 0 ? res[qc][si].relg : res[qc][si].first_relg);
        }
        fprintf(stderr, "bench_scale: [%d/%d] %s at %d^2 ...\n", done + 1, nsteps, m->name, n);
        run_child("/proc/self/exe", e.configs, m->name, n, tol, budget_ms, max_warm_s, mem_gib, cpu_s, wall_s, rr);
      }
    record:
      done++;
      {
        double na = cb_csv_na();
        FILE *f = csv.f;
        cb_csv_printf(f, "%s,%d", m->name, n);
        if (rr->ok) cb_csv_printf(f, ",%d,%d,%d", rr->vertices, rr->dofs, rr->steps);
        else if (rr->vertices > 0) cb_csv_printf(f, ",%d,%d,%.17g", rr->vertices, rr->dofs, na);
        else cb_csv_printf(f, ",%d,%.17g,%.17g", n * n, na, na);
        put_num(f, rr->ok ? rr->step : NAN, ",%.6g");
        put_num(f, rr->ok ? rr->lo : NAN, ",%.6g");
        put_num(f, rr->ok ? rr->hi : NAN, ",%.6g");
        put_num(f, rr->first > 0 ? rr->first : NAN, ",%.6g"); /* also what a child that did not finish had measured */
        put_num(f, rr->setup > 0 ? rr->setup : NAN, ",%.6g");
        put_num(f, rr->ok ? rr->analyze : NAN, ",%.6g");
        put_num(f, rr->rss_bytes > 0 ? rr->rss_bytes : NAN, ",%.17g");
        put_num(f, rr->ok ? rr->relg : NAN, ",%.6g");
        put_num(f, rr->ok ? rr->first_relg : NAN, ",%.6g");
        put_num(f, rr->ok ? rr->relr : NAN, ",%.6g");
        put_num(f, rr->ok ? rr->iters : NAN, ",%.6g");
        put_num(f, rr->ok ? rr->liters : NAN, ",%.6g");
        put_num(f, rr->ok ? rr->nnzl : NAN, ",%.17g");
        put_num(f, m->matched && rr->tol > 0 ? rr->tol : NAN, ",%.6g");
        put_num(f, rr->wall_s > 0 ? rr->wall_s : NAN, ",%.3f");
        cb_csv_printf(f, ",%s,%s\n", rr->status, rr->note);
        fflush(f);
      }
      if (rr->ok)
        fprintf(stderr,
                "bench_scale: [%d/%d] %s at %d^2: step %.4g ms, peak RSS %.0f MiB, rel |grad F| %.3g (%.1f s; %.0f s "
                "so far)\n",
                done, nsteps, m->name, n, rr->step, rr->rss_bytes / 1048576.0, rr->relg, rr->wall_s,
                (cb_now_ms() - t_all) / 1000);
      else fprintf(stderr, "bench_scale: [%d/%d] %s at %d^2: %s: %s\n", done, nsteps, m->name, n, rr->status, rr->note);
    }
  }
  /* growth exponents over the measured sizes */
  for (int q = 0; q < nrun; q++) {
    double lv[MAXSIZES], lt[MAXSIZES], lm[MAXSIZES];
    int ns[MAXSIZES], k = 0;
    for (int si = 0; si < nsizes; si++) {
      const result *rr = &res[q][si];
      if (!rr->ok || !(rr->step > 0) || !(rr->rss_bytes > 0)) continue;
      lv[k] = log((double)rr->vertices);
      lt[k] = log(rr->step);
      lm[k] = log(rr->rss_bytes);
      ns[k] = sizes[si];
      k++;
    }
    fit_row(fit.f, run[q]->name, "step_ms", "all", lv, lt, ns, 0, k);
    fit_row(fit.f, run[q]->name, "peak_rss_bytes", "all", lv, lm, ns, 0, k);
    if (k > 3) {
      fit_row(fit.f, run[q]->name, "step_ms", "top3", lv, lt, ns, k - 3, k);
      fit_row(fit.f, run[q]->name, "peak_rss_bytes", "top3", lv, lm, ns, k - 3, k);
    }
  }
  if (cb_outfile_commit(&fit) || cb_outfile_commit(&csv)) {
    fprintf(stderr, "bench_scale: %s\n", cb_error_message());
    return 2;
  }
  fprintf(stderr, "bench_scale: wrote %s and %s in %.0f s\n", e.out, fit_path, (cb_now_ms() - t_all) / 1000);
  free(rest);
  return 0;
}
