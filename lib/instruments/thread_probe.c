#include "thread_probe.h"

#include <cblas.h>
#include <cholmod.h>
#include <dirent.h>
#include <errno.h>
#include <stdlib.h>
#include <string.h>
#include <sys/types.h>
#include <time.h>

#include <clothbench/status.h>

/* ---- per-thread CPU time of every task of this process ---- */

enum { MAX_TASKS = 512 };
typedef struct {
  int n;
  pid_t tid[MAX_TASKS];
  long long ns[MAX_TASKS];
} task_times;

/* The CPU clock of thread tid of this process: glibc's pthread_getcpuclockid
 * builds the same id (Linux's CPUCLOCK_SCHED | CPUCLOCK_PERTHREAD_MASK). */
static clockid_t thread_clock(pid_t tid) { return (clockid_t)((~(unsigned)tid) << 3 | 6u); }

static int snapshot(task_times *t) {
  DIR *d = opendir("/proc/self/task");
  if (!d) return cb_fail_status(CB_EIO, "threads: cannot open /proc/self/task: %s", strerror(errno));
  t->n = 0;
  for (struct dirent *de; (de = readdir(d)) && t->n < MAX_TASKS;) {
    if (de->d_name[0] < '0' || de->d_name[0] > '9') continue;
    pid_t tid = (pid_t)atol(de->d_name);
    struct timespec ts;
    if (clock_gettime(thread_clock(tid), &ts)) continue; /* the thread has exited */
    t->tid[t->n] = tid;
    t->ns[t->n++] = (long long)ts.tv_sec * 1000000000LL + ts.tv_nsec;
  }
  closedir(d);
  return CB_OK;
}

int cb_threads_count_during(void (*fn)(void *), void *ctx) {
  static task_times before, after; /* large; one caller at a time */
  int st = snapshot(&before);
  if (st) return st;
  fn(ctx);
  st = snapshot(&after);
  if (st) return st;
  int ran = 0;
  for (int i = 0; i < after.n; i++) {
    long long t0 = 0; /* a thread born during fn starts from 0 */
    for (int j = 0; j < before.n; j++)
      if (before.tid[j] == after.tid[i]) t0 = before.ns[j];
    ran += after.ns[i] > t0;
  }
  return ran;
}

/* ---- the probes ---- */

/* The fewest threads that ran in one of 3 repetitions: a thread that merely
 * spin-waits at the time (OpenBLAS's idle worker spins for ~0.1 s after
 * start-up when OPENBLAS_NUM_THREADS is unset) counts only if it does so
 * every time. */
static int min_count(void (*fn)(void *), void *ctx) {
  int best = -1;
  for (int r = 0; r < 3; r++) {
    int k = cb_threads_count_during(fn, ctx);
    if (k < 0) return k;
    if (best < 0 || k < best) best = k;
  }
  return best;
}

typedef struct {
  cholmod_sparse *A;
  cholmod_factor *L;
  cholmod_common *c;
} chol_probe;

static void run_factor(void *ctx) {
  chol_probe *p = ctx;
  cholmod_factorize(p->A, p->L, p->c);
}

/* Upper triangle of the 5-point Laplacian (plus 1e-3 I) on an m x m grid. */
static cholmod_sparse *laplacian(int m, cholmod_common *c) {
  int n = m * m;
  cholmod_sparse *A = cholmod_allocate_sparse((size_t)n, (size_t)n, (size_t)3 * n, 1, 1, 1, CHOLMOD_REAL, c);
  if (!A) return NULL;
  int *Ap = A->p, *Ai = A->i, q = 0;
  double *Ax = A->x;
  for (int j = 0; j < n; j++) {
    Ap[j] = q;
    if (j >= m) {
      Ai[q] = j - m;
      Ax[q++] = -1.0;
    } /* (j - m, j) */
    if (j % m) {
      Ai[q] = j - 1;
      Ax[q++] = -1.0;
    } /* (j - 1, j) */
    Ai[q] = j;
    Ax[q++] = 4.001; /* diagonal */
  }
  Ap[n] = q;
  return A;
}

int cb_thread_probe_cholmod(void) {
  cholmod_common c;
  cholmod_start(&c);
  c.print = 0;
  c.error_handler = NULL;
  c.supernodal = CHOLMOD_SUPERNODAL;
  chol_probe p = {laplacian(96, &c), NULL, &c};
  int ran = -1;
  if (p.A) p.L = cholmod_analyze(p.A, &c);
  if (p.L) {
    cholmod_factorize(p.A, p.L, &c); /* warm-up: libgomp creates its pool on the first region */
    ran = min_count(run_factor, &p);
  }
  cholmod_free_factor(&p.L, &c);
  cholmod_free_sparse(&p.A, &c);
  cholmod_finish(&c);
  return ran;
}

typedef struct {
  int n;
  double *a, *b, *c;
} gemm_probe;

static void run_gemm(void *ctx) {
  gemm_probe *g = ctx;
  cblas_dgemm(CblasColMajor, CblasNoTrans, CblasNoTrans, g->n, g->n, g->n, 1.0, g->a, g->n, g->b, g->n, 0.0, g->c,
              g->n);
}

int cb_thread_probe_dgemm(void) {
  gemm_probe g = {384, NULL, NULL, NULL};
  size_t nn = (size_t)g.n * (size_t)g.n;
  g.a = malloc(nn * sizeof(double));
  g.b = malloc(nn * sizeof(double));
  g.c = malloc(nn * sizeof(double));
  int ran = -1;
  if (g.a && g.b && g.c) {
    for (size_t i = 0; i < nn; i++) {
      g.a[i] = 1.0 / (double)(i % 97 + 1);
      g.b[i] = (double)(i % 13);
    }
    run_gemm(&g);
    ran = min_count(run_gemm, &g);
  }
  free(g.a);
  free(g.b);
  free(g.c);
  return ran;
}
