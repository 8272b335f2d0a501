/* Allocation-failure injection (CHOLMOD's Tcov habit; status.h): a small
 * scene is built from a config and stepped, once to count its allocations
 * (N), then N more times with the k-th allocation failing, k = 1 .. N. Every
 * one of those runs must stop with CB_ENOMEM and a message, never crash, and
 * leave nothing allocated: glibc's heap in use is the same before and after
 * each run (mallinfo2), and under AddressSanitizer (make san) LeakSanitizer's
 * check after each sweep finds no leak.
 *
 * What counts as an allocation: every cb_malloc, cb_calloc and cb_realloc
 * (all of lib/'s own heap allocations in the scene, integrator and solver
 * code), the GSL workspaces of the Hessian projection (projection.c ticks
 * the counter before each GSL allocation), and CHOLMOD's: this test routes
 * SuiteSparse_config's malloc/calloc/realloc through cb_alloc_tick. Not
 * counted: allocations inside GSL, METIS (its own allocator), OpenBLAS and
 * libgomp, and the C library's own (stdio buffers of the OBJ reader).
 *
 * The cases come from the registries, so a new integrator, linear solver,
 * stretch or bending model, collider or definiteness policy is covered by
 * being registered: every integrator (each one that takes a linear solver,
 * with every solver), Newton's Baraff-Witkin and line-search variants, and
 * every material, collider and policy on Newton with CHOLMOD. */
#include <criterion/criterion.h>
#include <limits.h>
#include <malloc.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include <SuiteSparse_config.h>

#include "support.h"

#if defined(__SANITIZE_ADDRESS__)
#define CB_ASAN 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define CB_ASAN 1
#endif
#endif
#ifdef CB_ASAN
#include <sanitizer/lsan_interface.h>
#endif

/* ---- CHOLMOD's allocations through the counter ---------------------------- */

static long cholmod_ticks; /* CHOLMOD's allocations counted, for the summary */
static int cholmod_failed; /* the injected failure was one of CHOLMOD's */

static int ss_tick(void) {
  int fail = cb_alloc_tick();
  cholmod_ticks++;
  cholmod_failed |= fail;
  return fail;
}
static void *ss_malloc(size_t n) { return ss_tick() ? NULL : malloc(n); }
static void *ss_calloc(size_t n, size_t size) { return ss_tick() ? NULL : calloc(n, size); }
static void *ss_realloc(void *p, size_t n) { return ss_tick() ? NULL : realloc(p, n); }

static void setup(void) {
  SuiteSparse_config.malloc_func = ss_malloc;
  SuiteSparse_config.calloc_func = ss_calloc;
  SuiteSparse_config.realloc_func = ss_realloc;
  SuiteSparse_config.free_func = free;
}

#ifndef CB_ASAN
/* glibc's per-thread cache (tcache) keeps freed chunks that mallinfo2 counts
 * as in use, so the heap check needs it off: the tunable is read at start-up
 * only, so the program starts itself again with it set. */
#define NO_TCACHE "glibc.malloc.tcache_count=0"
__attribute__((constructor)) static void without_tcache(int argc, char **argv) {
  (void)argc;
  const char *t = getenv("GLIBC_TUNABLES");
  if (t && strstr(t, NO_TCACHE)) return;
  char buf[1024];
  snprintf(buf, sizeof buf, "%s%s" NO_TCACHE, t ? t : "", t ? ":" : "");
  if (setenv("GLIBC_TUNABLES", buf, 1) == 0) execv("/proc/self/exe", argv);
  /* if that fails, heap_in_use returns 0 and the heap check is skipped */
}
#endif

TestSuite(enomem, .init = setup);

/* ---- one run ---------------------------------------------------------------- */

/* The scene: a 4x4 cloth pinned at two corners, a little stretched. */
static const char *const BASE[] = {"mesh.n=4",
                                   "material.stretch_k=100",
                                   "material.vertex_mass=0.1",
                                   "scene.pins=top-corners",
                                   "scene.initial_scale=1.1",
                                   "integrator.dt=0.01",
                                   "integrator.max_iters=4",
                                   "integrator.iters=4",
                                   "solver.max_iters=50",
                                   NULL};
#define STEPS 2
#define MAX_SETS 16

typedef struct {
  char label[160];
  char sets[MAX_SETS][128];
  int nsets;
} run_case;

static void case_add(run_case *rc, const char *key, const char *value) {
  cr_assert_lt(rc->nsets, MAX_SETS);
  snprintf(rc->sets[rc->nsets++], sizeof rc->sets[0], "%s=%s", key, value);
  size_t n = strlen(rc->label);
  snprintf(rc->label + n, sizeof rc->label - n, "%s%s=%s", n ? " " : "", key, value);
}

/* Builds the scene and the integrator of c and takes STEPS steps. Returns
 * the first error: of the scene, the integrator, the run, or a fatal step
 * status; CB_OK otherwise (not_converged included). */
static long integrator_begin, integrator_end; /* the allocations counted before and after the integrator's */

static int run_once(const cb_config *c) {
  cb_scene *s = NULL;
  int st = cb_scene_from_config(c, &s);
  if (st) return st;
  integrator_begin = cb_alloc_count();
  cb_integrator *it = NULL;
  st = cb_integrator_from_config(c, s, NULL, &it);
  integrator_end = cb_alloc_count();
  if (st == CB_OK) {
    cb_run r;
    st = cb_run_init(&r, s, it);
    if (st == CB_OK) {
      for (int k = 0; k < STEPS && st == CB_OK; k++) {
        int rs = cb_run_step(&r);
        if (cb_status_is_fatal(rs)) st = rs;
      }
      cb_run_free(&r);
    }
    cb_integrator_free(it);
  }
  cb_scene_free(s);
  return st;
}

/* Bytes of glibc's heap in use, when glibc's tcache is off (above); else 0,
 * and under ASan, whose allocator is its own and LeakSanitizer checks. */
static size_t heap_in_use(void) {
  const char *t = getenv("GLIBC_TUNABLES");
  if (!t || !strstr(t, "glibc.malloc.tcache_count=0")) return 0;
  struct mallinfo2 mi = mallinfo2();
  return mi.uordblks + mi.hblkhd;
}

#ifdef CB_ASAN
/* Overwrites the stack below the caller's frame, so that LeakSanitizer (a
 * conservative scan) does not take a dead frame's pointer for a live one. */
__attribute__((noinline)) static void scrub_stack(void) {
  volatile char buf[1 << 16];
  memset((char *)buf, 0, sizeof buf);
}
#endif

static long total_points, total_cases;

/* 1 when c's solver allocates through a library that keeps growing bookkeeping for the process (PETSc's logs
 * and registries gain 128-528 bytes now and then as objects come and go, which is no leak): the heap cannot be
 * compared for it; LeakSanitizer still checks it under make san, and the statuses are checked here. */
static int library_heap(const cb_config *c) {
  const cb_solver_type *t = cb_solver_type_find(c->solver);
  const cb_integrator_type *it = cb_integrator_type_find(c->method);
  return t && it && (it->flags & CB_INTEGRATOR_LINEAR_SOLVER) && (t->flags & CB_SOLVER_LIBRARY_HEAP);
}

/* The sweep over k for one case; returns the number of allocations. */
static long sweep(const run_case *rc) {
  cb_config c;
  cb_config_defaults(&c);
  for (int i = 0; BASE[i]; i++) cr_assert_eq(cb_config_set(&c, BASE[i]), CB_OK, "%s", cb_error_message());
  for (int i = 0; i < rc->nsets; i++)
    cr_assert_eq(cb_config_set(&c, rc->sets[i]), CB_OK, "%s: %s", rc->label, cb_error_message());
  /* a run without failure, twice: the first warms up what the libraries keep
   * for the process (OpenBLAS's buffers); the second counts */
  cr_assert_eq(run_once(&c), CB_OK, "%s: the run without failure: %s", rc->label, cb_error_message());
  long ss0 = cholmod_ticks;
  cb_alloc_fail_at(LONG_MAX);
  int st = run_once(&c);
  long n = cb_alloc_count(), ibegin = integrator_begin, iend = integrator_end;
  cb_alloc_fail_at(0);
  long nss = cholmod_ticks - ss0;
  cr_assert_eq(st, CB_OK, "%s: the counting run: %s", rc->label, cb_error_message());
  cr_assert_gt(n, 0, "%s: no allocation counted", rc->label);
  long recovered = 0; /* CHOLMOD's failures that CHOLMOD worked around */
  for (long k = 1; k <= n; k++) {
    size_t heap0 = heap_in_use();
    cb_error_clear();
    cholmod_failed = 0;
    cb_alloc_fail_at(k);
    st = run_once(&c);
    long seen = cb_alloc_count();
    cb_alloc_fail_at(0);
    cr_assert_geq(seen, k, "%s: allocation %ld of %ld was never made (the count is not deterministic)", rc->label, k,
                  n);
    /* CHOLMOD may work around a failed allocation of cholmod_analyze (it
     * falls back to another ordering), which runs when the integrator is
     * made: then the run succeeds. Anywhere else, a failure must stop it. */
    if (st == CB_OK && cholmod_failed && k > ibegin && k <= iend) recovered++;
    else {
      cr_assert_eq(st, CB_ENOMEM, "%s: allocation %ld of %ld failed%s, and the run returned %s (%d): %s", rc->label, k,
                   n, cholmod_failed ? " (in CHOLMOD)" : "", cb_status_name(st), st, cb_error_message());
      cr_assert_neq(cb_error_message()[0], '\0', "%s: allocation %ld of %ld failed without a message", rc->label, k, n);
    }
    size_t heap1 = heap_in_use();
    cr_assert(heap1 == heap0 || library_heap(&c), "%s: allocation %ld of %ld failed, and %zd bytes stayed allocated",
              rc->label, k, n, (ssize_t)(heap1 - heap0));
  }
#ifdef CB_ASAN
  scrub_stack();
  cr_assert_eq(__lsan_do_recoverable_leak_check(), 0, "%s: LeakSanitizer found a leak (above)", rc->label);
#endif
  if (!getenv("CB_QUIET"))
    printf("enomem: %4ld allocations (%3ld of them CHOLMOD's, %ld failures it worked around): %s\n", n, nss, recovered,
           rc->label);
  total_points += n;
  total_cases++;
  return n;
}

static int count(const char *const *names) {
  int n = 0;
  while (names[n]) n++;
  return n;
}

/* Every integrator; one that takes a linear solver, with every solver. */
Test(enomem, every_integrator_and_solver) {
  int nint = 0, nsolvers = 0;
  while (cb_integrator_name(nint)) nint++;
  while (cb_solver_name(nsolvers)) nsolvers++;
  cr_assert_gt(nint, 0);
  cr_assert_gt(nsolvers, 0);
  for (int i = 0; i < nint; i++) {
    const cb_integrator_type *t = cb_integrator_type_find(cb_integrator_name(i));
    int with_solver = (t->flags & CB_INTEGRATOR_LINEAR_SOLVER) != 0;
    for (int j = 0; j < (with_solver ? nsolvers : 1); j++) {
      run_case rc = {0};
      case_add(&rc, "integrator.method", t->name);
      if (with_solver) case_add(&rc, "solver.method", cb_solver_name(j));
      cr_assert_gt(sweep(&rc), 0);
    }
  }
  if (!getenv("CB_QUIET")) printf("enomem: %ld cases, %ld injected failures\n", total_cases, total_points);
}

/* Newton's variants: Baraff-Witkin's single iteration, the line search. */
Test(enomem, newton_variants) {
  static const char *const variants[][2] = {{"integrator.max_iters", "1"}, {"integrator.line_search", "1"}};
  for (size_t v = 0; v < sizeof variants / sizeof variants[0]; v++) {
    run_case rc = {0};
    case_add(&rc, "integrator.method", "newton");
    case_add(&rc, variants[v][0], variants[v][1]);
    sweep(&rc);
  }
}

/* Every integrator's options from its key table: each choice of a choice
 * key, a bool key on, an `auto` key set to auto (solver types with CHOLMOD). */
Test(enomem, every_integrator_option) {
  for (int i = 0; cb_integrator_name(i); i++) {
    const cb_integrator_type *t = cb_integrator_type_find(cb_integrator_name(i));
    for (const cb_param_key *k = t->keys; k && k->name; k++) {
      char key[96];
      snprintf(key, sizeof key, "integrator.%s", k->name);
      const char *values[16];
      int nvalues = 0;
      if (k->kind == CB_PARAM_CHOICE)
        for (int c = 0; k->choices[c] && nvalues < 16; c++) values[nvalues++] = k->choices[c];
      else if (k->kind == CB_PARAM_BOOL) values[nvalues++] = "1";
      else if (k->kind == CB_PARAM_DOUBLE_AUTO) values[nvalues++] = "auto";
      for (int v = 0; v < nvalues; v++) {
        if (strcmp(values[v], k->def) == 0) continue; /* the default: every_integrator_and_solver runs it */
        run_case rc = {0};
        case_add(&rc, "integrator.method", t->name);
        case_add(&rc, key, values[v]);
        sweep(&rc);
      }
    }
  }
}

/* Every stretch and bending model, collider and definiteness policy, on
 * Newton with CHOLMOD (choi-ko also with the spring stretch it needs). */
Test(enomem, every_material_collider_policy) {
  for (int i = 0; i < count(cb_stretch_names); i++) {
    run_case rc = {0};
    case_add(&rc, "material.stretch", cb_stretch_names[i]);
    sweep(&rc);
  }
  for (int i = 0; i < count(cb_bend_names); i++) {
    run_case rc = {0};
    case_add(&rc, "material.bend", cb_bend_names[i]);
    case_add(&rc, "material.bend_k", "0.01");
    sweep(&rc);
  }
  char obstacle[256]; /* the `mesh` collider's obstacle: a tetrahedron, turning */
  snprintf(obstacle, sizeof obstacle, "%s",
           test_tmpfile(".obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n"));
  for (int i = 0; i < count(cb_collider_names); i++) {
    run_case rc = {0};
    case_add(&rc, "collider.type", cb_collider_names[i]);
    case_add(&rc, "collider.centre", "0.5 -0.2 0.5");
    if (!strcmp(cb_collider_names[i], "mesh")) {
      case_add(&rc, "collider.file", obstacle);
      case_add(&rc, "collider.angular_speed", "1");
    }
    sweep(&rc);
  }
  remove(obstacle);
  for (int i = 0; i < count(cb_definiteness_names); i++) {
    run_case rc = {0};
    case_add(&rc, "integrator.definiteness", cb_definiteness_names[i]);
    sweep(&rc);
  }
}

/* Every contact response, against a flat obstacle under the sheet (so pairs are active from the start) and with
 * self-contact: the term, its broad phases and candidate arrays, the step bound. */
Test(enomem, every_contact_response) {
  char obstacle[256];
  snprintf(obstacle, sizeof obstacle, "%s", test_tmpfile(".obj", "v -5 0 -5\nv 0 0 5\nv 5 0 -5\nf 1 2 3\n"));
  for (int i = 0; cb_contact_names[i]; i++) {
    run_case rc = {0};
    case_add(&rc, "contact.method", cb_contact_names[i]);
    case_add(&rc, "contact.thickness", "0.3");
    case_add(&rc, "contact.kappa", "1");
    case_add(&rc, "collider.type", "mesh");
    case_add(&rc, "collider.file", obstacle);
    case_add(&rc, "collider.centre", "0 -0.2 0");
    case_add(&rc, "integrator.line_search", "1");
    sweep(&rc);
  }
  {
    /* ipc's friction: its pairs frozen at every step's start */
    run_case rc = {0};
    case_add(&rc, "contact.method", "ipc");
    case_add(&rc, "contact.thickness", "0.3");
    case_add(&rc, "contact.kappa", "1");
    case_add(&rc, "contact.friction", "0.5");
    case_add(&rc, "collider.type", "mesh");
    case_add(&rc, "collider.file", obstacle);
    case_add(&rc, "collider.centre", "0 -0.2 0");
    case_add(&rc, "integrator.line_search", "1");
    sweep(&rc);
  }
  /* bridson with friction, straight to its rigid impact zones (no impulse passes), under the explicit step */
  run_case rc = {0};
  case_add(&rc, "contact.method", "bridson");
  case_add(&rc, "contact.thickness", "0.3");
  case_add(&rc, "contact.friction", "0.4");
  case_add(&rc, "contact.bridson_iters", "0");
  case_add(&rc, "collider.type", "mesh");
  case_add(&rc, "collider.file", obstacle);
  case_add(&rc, "collider.centre", "0 -0.2 0");
  case_add(&rc, "integrator.method", "explicit");
  sweep(&rc);
  remove(obstacle);
}

/* Vertex block descent with each energy response (docs/contact.md, VBD): the collect's trees, pair lists and
 * bounds allocated at its set-up, its start-state check, and the steps (with a collect before every sweep), with
 * active obstacle and self pairs. */
Test(enomem, vbd_contact) {
  char obstacle[256];
  snprintf(obstacle, sizeof obstacle, "%s", test_tmpfile(".obj", "v -5 0 -5\nv 0 0 5\nv 5 0 -5\nf 1 2 3\n"));
  const char *const methods[] = {"penalty", "ipc"};
  for (int i = 0; i < 2; i++) {
    run_case rc = {0};
    case_add(&rc, "integrator.method", "vbd");
    case_add(&rc, "contact.method", methods[i]);
    case_add(&rc, "contact.thickness", "0.3");
    case_add(&rc, "contact.kappa", "1");
    case_add(&rc, "collider.type", "mesh");
    case_add(&rc, "collider.file", obstacle);
    case_add(&rc, "collider.centre", "0 -0.2 0");
    sweep(&rc);
  }
  remove(obstacle);
}

/* The OBJ reader (its growing buffers) on a small file. */
Test(enomem, obj_mesh) {
  const char *path = test_tmpfile(".obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nf 1 2 3\nf 2 4 3\n");
  run_case rc = {0};
  case_add(&rc, "mesh.type", "obj");
  case_add(&rc, "mesh.file", path);
  case_add(&rc, "scene.pins", "0");
  sweep(&rc);
  remove(path);
}

/* The heap check sees a leak: a block allocated between the two readings. */
Test(enomem, heap_check_sees_a_block) {
#ifdef CB_ASAN
  cr_skip_test("ASan's allocator: LeakSanitizer checks leaks instead");
#else
  size_t h0 = heap_in_use();
  cr_assert_gt(h0, 0, "the heap check is off (GLIBC_TUNABLES=%s)", getenv("GLIBC_TUNABLES"));
  void *volatile p = malloc(100);
  cr_assert_geq(heap_in_use(), h0 + 100);
  free(p);
  cr_assert_eq(heap_in_use(), h0);
#endif
}
