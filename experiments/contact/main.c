/* contact: the contact responses of contact.method on the field's contact scenes, every frame checked
 * exactly for intersections (issue 34 §3; claim C1). docs/experiments/contact.md explains every choice.
 *
 * C1  results/contact.csv: for each scene of the table below (configs/sheet_on_table.ini: a sheet falls
 *     onto the table and folds over its corner; configs/rotating_sphere.ini: Codim-IPC's sheet dropped
 *     on a sphere turning at 180 deg/s, friction 0), each registered contact response (every name of
 *     cb_contact_names but "none": a response added to the registry joins the sweep by its registry
 *     line), each time step dt and each drop speed (an initial downward velocity of every free vertex,
 *     on top of the scene's fall from 0.1 m), the scene runs for the same simulated time; at the start
 *     and after every step (frame):
 *       self_intersections      the cloth's intersecting non-adjacent triangle pairs (exactly,
 *                               lib/instruments/intersections.h);
 *       obstacle_intersections  intersecting (cloth triangle, obstacle triangle) pairs, with the obstacle
 *                               where the scene has moved it at that frame (every pair whose boxes
 *                               touch, exactly: cb_tri_tri_intersect);
 *       min_separation_m        the smallest distance of a primitive pair within the response's reach
 *                               (contact.thickness; its term's statistics at the frame, cb_contact_term_
 *                               stats), empty when no pair is within reach or the response has no term;
 *       contacts                the pairs within that reach (the term's active pairs).
 *     The integrator is the scene's (Newton), or, if it refuses the response, the first of FALLBACK
 *     that accepts it (a response for the explicit family, e.g. Bridson's impulses); a response no
 *     integrator accepts gets one row with status `refused`. A step that fails keeps its row with its
 *     status (and the frame's counts when the positions are finite) and ends the cell; a scene that
 *     cannot be built (ipc refuses a start that intersects) is one row with its status.
 * C2  results/contact_c2.csv: the stick-slip threshold of ipc's friction on configs/slope.ini against tan theta
 *     (experiments/contact/c2.c).
 * C3  results/contact_c3.csv: per scene, the state after W frames of ipc under Newton (the scene's config,
 *     dt = 1/30 s, no drop speed: W = 12, --quick 6, --smoke 2), then one step from it by each method, at a
 *     ladder of iteration caps (Newton: integrator.max_iters 1..32 with tol = tol_dx = 0; L-BFGS: integrator.iters
 *     1..64; VBD with its contact bounds: integrator.iters 1..1024, --quick 512), against IPC's converged step x*
 *     (Newton from the same state, at most 500 iterations, tol 1e-10): step_error = |x - x*| / |x* - x_W| (2-norms
 *     over all coordinates), the step's wall time (median of interleaved repeats, with min, max, each and their
 *     count: c3_cell) and the exact intersection count of its result. One warm scene per scene; every step starts
 *     from its saved state with the obstacle's clock rewound. Decided by cb_check_C3 (claims/check_contact.c).
 * --quick: mesh.n = 12, two dt and two speeds, 0.5 s. --smoke: mesh.n = 8, one dt and one speed, 3
 * steps, both scenes and every response (seconds). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <clothbench/contact.h>
#include <clothbench/energy.h>
#include <clothbench/integrator.h>
#include <clothbench/intersect.h>
#include <clothbench/obstacle.h>
#include <clothbench/run.h>
#include <clothbench/scene.h>
#include <clothbench/status.h>
#include "bind.h"
#include "c2.h"
#include "csv.h"
#include "intersections.h"
#include "sweep.h"

static const char *const ABOUT =
    "Runs every registered contact response (contact.method) on the sheet falling onto a table and the sheet\n"
    "dropped on a rotating sphere, over a sweep of dt and drop speed, and counts at every frame, exactly, the\n"
    "intersecting non-adjacent triangle pairs (cloth-cloth and cloth-obstacle), the smallest separation and\n"
    "the contact count: C1 (IPC stays intersection-free where a penalty without CCD tunnels). C2: the stick-slip\n"
    "threshold of IPC's friction on a slope against tan theta. C3: one step from a contact-rich state by VBD with\n"
    "contact, IPC's Newton and L-BFGS at a ladder of iteration counts, error against IPC's converged step against\n"
    "wall time (timed), every result checked for intersections.";

/* Scenes. Role "c1": C1's sweep. level: 2 in --smoke too, 1 in --quick too, 0 full run only. */
typedef struct {
  cb_scene_decl scene;
  int level;
} scene_plan;
static const scene_plan SCENES[] = {
    {{"sheet_on_table", "sheet_on_table.ini", {NULL}, "c1"}, 2},
    {{"rotating_sphere", "rotating_sphere.ini", {NULL}, "c1"}, 2},
};
enum { NSCENES = sizeof SCENES / sizeof SCENES[0] };

/* The integrators a cell tries after the scene's own, in order, when that one refuses the response. */
static const char *const FALLBACK[] = {"xpbd", NULL};

/* The sweep of each run kind: dt (s), drop speeds (m/s), simulated time (s; smoke: steps), mesh.n. */
static const double DT_FULL[] = {1.0 / 15, 1.0 / 30, 1.0 / 60}, DT_QUICK[] = {1.0 / 15, 1.0 / 30},
                    DT_SMOKE[] = {1.0 / 15};
static const double SPEED_FULL[] = {0, 4, 12}, SPEED_QUICK[] = {0, 12}, SPEED_SMOKE[] = {12};

enum { MAXRESP = 16 };
typedef struct {
  cb_experiment *e;
  int scene[NSCENES], nscenes;
  const char *resp[MAXRESP];
  int nresp;
  const double *dt, *speed;
  int ndt, nspeed;
  double duration; /* s; 0: smoke_steps steps */
  int smoke_steps;
  int mesh_n; /* 0: the config's */
  long nv[NSCENES];
  int c3_warm; /* C3: frames of ipc Newton before the compared step */
} plan;

typedef struct {
  int scene, resp, dt, speed;
} cell_ix;

static cell_ix cell_of(const plan *p, long i) {
  cell_ix c;
  c.speed = (int)(i % p->nspeed);
  i /= p->nspeed;
  c.dt = (int)(i % p->ndt);
  i /= p->ndt;
  c.resp = (int)(i % p->nresp);
  c.scene = (int)(i / p->nresp);
  return c;
}

static int steps_of(const plan *p, double dt) {
  return p->duration > 0 ? (int)lround(p->duration / dt) : p->smoke_steps;
}

static double cost(long i, void *ctx) {
  const plan *p = ctx;
  cell_ix c = cell_of(p, i);
  return steps_of(p, p->dt[c.dt]) * (double)p->nv[c.scene] / 256.0;
}

/* Intersecting (cloth triangle, obstacle triangle) pairs at cloth positions x, obstacle positions y:
 * every pair whose closed boxes touch goes to the exact test (a pair that meets has touching boxes). */
static long obstacle_intersections(const cb_mesh *m, const double *x, const cb_mesh *om, const double *y,
                                   double *obox) {
  for (int b = 0; b < om->nt; b++) {
    double *bx = obox + 6 * b;
    for (int k = 0; k < 3; k++) bx[k] = INFINITY, bx[3 + k] = -INFINITY;
    for (int a = 0; a < 3; a++)
      for (int k = 0; k < 3; k++) {
        double v = y[3 * om->tri[3 * b + a] + k];
        bx[k] = fmin(bx[k], v);
        bx[3 + k] = fmax(bx[3 + k], v);
      }
  }
  long n = 0;
  for (int a = 0; a < m->nt; a++) {
    const int *p = m->tri + 3 * a;
    double lo[3], hi[3];
    for (int k = 0; k < 3; k++) {
      lo[k] = fmin(x[3 * p[0] + k], fmin(x[3 * p[1] + k], x[3 * p[2] + k]));
      hi[k] = fmax(x[3 * p[0] + k], fmax(x[3 * p[1] + k], x[3 * p[2] + k]));
    }
    for (int b = 0; b < om->nt; b++) {
      const double *bx = obox + 6 * b;
      if (bx[0] > hi[0] || bx[3] < lo[0] || bx[1] > hi[1] || bx[4] < lo[1] || bx[2] > hi[2] || bx[5] < lo[2]) continue;
      const int *q = om->tri + 3 * b;
      n += cb_tri_tri_intersect(x + 3 * p[0], x + 3 * p[1], x + 3 * p[2], y + 3 * q[0], y + 3 * q[1], y + 3 * q[2]);
    }
  }
  return n;
}

static int all_finite(const double *x, int n) {
  for (int i = 0; i < n; i++)
    if (!isfinite(x[i])) return 0;
  return 1;
}

/* The scene and an integrator that accepts its response: the scene's own integrator, else the first of
 * FALLBACK. *refused = 1 when the scene built but no integrator accepted it. cfg->method names the one. */
static int build(const plan *p, const cell_ix *c, cb_scene **s, cb_integrator **it, cb_config *cfg, int *refused) {
  char sdt[64], sn[32], sm[64], si[64];
  snprintf(sdt, sizeof sdt, "integrator.dt=%.17g", p->dt[c->dt]);
  snprintf(sm, sizeof sm, "contact.method=%s", p->resp[c->resp]);
  snprintf(sn, sizeof sn, "mesh.n=%d", p->mesh_n);
  const cb_scene_decl *d = &SCENES[p->scene[c->scene]].scene;
  *refused = 0;
  int st = CB_OK;
  for (int k = -1; k < (int)(sizeof FALLBACK / sizeof FALLBACK[0]); k++) {
    const char *integ = k < 0 ? NULL : FALLBACK[k];
    if (k >= 0 && !integ) break;
    int m = 0;
    const char *more[5] = {NULL};
    more[m++] = sdt;
    more[m++] = sm;
    if (p->mesh_n > 0) more[m++] = sn;
    if (integ) {
      snprintf(si, sizeof si, "integrator.method=%s", integ);
      more[m++] = si;
    }
    st = cb_scene_decl_build(p->e, d, more, cfg, s);
    if (st) return st; /* the scene itself (ipc refuses an intersecting start): no integrator helps */
    st = cb_integrator_from_config(cfg, *s, NULL, it);
    if (st == CB_OK) return CB_OK;
    if (!getenv("CB_QUIET")) fprintf(stderr, "contact: %s, %s: %s\n", d->label, p->resp[c->resp], cb_error_message());
    cb_scene_free(*s);
    *s = NULL;
    *it = NULL;
  }
  *refused = 1;
  return st ? st : CB_EINVAL;
}

static int run_cell(long i, void *ctx, FILE *const *out) {
  const plan *p = ctx;
  FILE *f = out[0];
  cell_ix c = cell_of(p, i);
  const char *label = SCENES[p->scene[c.scene]].scene.label, *resp = p->resp[c.resp];
  double dt = p->dt[c.dt], speed = p->speed[c.speed];
  int steps = steps_of(p, dt);
  cb_scene *s = NULL;
  cb_integrator *it = NULL;
  cb_config cfg;
  int refused = 0;
  int st = build(p, &c, &s, &it, &cfg, &refused);
  if (st) {
    /* one row: the scene could not start, or no integrator takes the response */
    cb_csv_printf(f, "%s,,%s,,%.17g,%.17g,,,,,,,,,,%s\n", label, resp, dt, speed,
                  refused ? "refused" : cb_status_name(st));
    return CB_OK;
  }
  const char *integ = cfg.method;
  /* the drop speed: every free vertex starts moving down at speed (on top of the config's v0) */
  int nv = s->mesh.nv, n3 = 3 * nv;
  {
    int k = 0;
    for (int v = 0; v < nv; v++) {
      while (k < s->npinned && s->pinned[k] < v) k++;
      if (k < s->npinned && s->pinned[k] == v) continue;
      s->v0[3 * v + 1] -= speed;
    }
  }
  const cb_obstacle *o = cb_scene_obstacle(s);
  const cb_term *term = cb_scene_contact_term(s);
  double *obox = o ? malloc((size_t)6 * (size_t)(o->mesh.nt > 0 ? o->mesh.nt : 1) * sizeof *obox) : NULL;
  cb_intersections self;
  int ist = cb_intersections_init(&self, &s->mesh);
  cb_run run;
  int rst = ist ? ist : (o && !obox) ? CB_ENOMEM : cb_run_init(&run, s, it);
  if (rst) {
    cb_csv_printf(f, "%s,%d,%s,%s,%.17g,%.17g,,,,,,,,,,%s\n", label, nv, resp, integ, dt, speed, cb_status_name(rst));
    if (!ist) cb_intersections_free(&self);
    free(obox);
    cb_integrator_free(it);
    cb_scene_free(s);
    return CB_OK;
  }
  for (int k = 0; k <= steps; k++) {
    int sst = k == 0 ? run.last.status : cb_run_step(&run);
    double wall = k == 0 ? cb_csv_na() : run.last.wall_ms, iters = k == 0 ? cb_csv_na() : run.last.newton_iters;
    double nself = cb_csv_na(), nobst = cb_csv_na(), nall = cb_csv_na(), sep = cb_csv_na(), contacts = cb_csv_na();
    if (all_finite(run.x, n3)) {
      long ns = 0;
      if (cb_intersections_count(&self, run.x, &ns) == CB_OK) nself = (double)ns;
      long no = o ? obstacle_intersections(&s->mesh, run.x, &o->mesh, o->x, obox) : 0;
      nobst = (double)no;
      if (!isnan(nself)) nall = nself + nobst;
      if (term) {
        (void)term->type->energy(term, run.x, NULL); /* refreshes the term's pair statistics at this frame */
        const cb_contact_stats *cs = cb_contact_term_stats(term);
        if (cs) {
          sep = isfinite(cs->min_dist) ? cs->min_dist : cb_csv_na();
          contacts = (double)cs->active;
        }
      }
    }
    cb_csv_printf(f, "%s,%d,%s,%s,%.17g,%.17g,%d,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.6f,%s\n", label, nv, resp,
                  integ, dt, speed, k, k * dt, nself, nobst, nall, sep, contacts, iters, wall, cb_status_name(sst));
    if (cb_status_is_fatal(sst)) break;
  }
  cb_run_free(&run);
  cb_intersections_free(&self);
  free(obox);
  cb_integrator_free(it);
  cb_scene_free(s);
  return CB_OK;
}

/* ---- C3: one step from a contact-rich state, error against IPC's converged step against wall time ---- */

typedef struct {
  const char *method; /* integrator.method */
  const char *key;    /* its iteration key */
  int max_iters[3];   /* the ladder 1, 2, 4, ... up to this: full run, --quick, --smoke */
} c3_method;
/* VBD's cap, from a measurement (docs/experiments/contact.md, C3): its error falls by about 0.5 per doubling of the
 * sweeps on the sphere and 0.8 on the fold at 12^2 (--quick: 0.018 and 0.11 at 512 sweeps, 1.3-2.6 s and 0.3-0.9 s),
 * slower at 16^2 (full run: 0.19 and 0.41 at 1024 sweeps, 9.8 s and 2.0 s), so 1e-3, even 1e-2, would take some 10^4
 * sweeps or more: the full run stops at 1024, --quick at 512 (a longer ladder adds seconds, not a verdict) */
static const c3_method C3_METHODS[] = {
    {"newton", "integrator.max_iters", {32, 32, 2}},
    {"lbfgs", "integrator.iters", {64, 64, 2}},
    {"vbd", "integrator.iters", {1024, 512, 4}},
};
enum { NC3 = sizeof C3_METHODS / sizeof C3_METHODS[0], C3_MAXRUNGS = 48 };

/* One rung of a method's ladder: its integrator on the warm scene, its first (untimed) step's result, and its
 * timed repeats. */
typedef struct {
  const c3_method *cm;
  int k;             /* iteration cap */
  cb_integrator *it; /* NULL: refused (note, status) */
  int st, tst;       /* set-up status; the step's status */
  double err, nint;  /* step_error; intersections (NaN: not counted) */
  double *x;         /* the first step's result (3 nv) */
  cb_timing t;       /* the timed repeats (ms) */
  double dev;        /* the largest |x_repeat - x_first| / |x* - x_start| over the repeats */
  long truncated;    /* vbd: vertex updates its displacement bounds shortened in the first step (-1: not vbd) */
  char note[256];
} c3_rung;

/* The cell's scene after `warm` frames of ipc under the config's Newton: *x, *v the state (3 nv, allocated). */
static int c3_warm_scene(const plan *p, int scene, int warm, cb_scene **s, double **x, double **v) {
  char sn[32];
  snprintf(sn, sizeof sn, "mesh.n=%d", p->mesh_n);
  const cb_scene_decl *d = &SCENES[p->scene[scene]].scene;
  const char *base[] = {"contact.method=ipc", p->mesh_n > 0 ? sn : NULL, NULL};
  static cb_config c0;
  *s = NULL, *x = NULL, *v = NULL;
  cb_integrator *w = NULL;
  int st = cb_scene_decl_build(p->e, d, base, &c0, s);
  if (st == CB_OK) st = cb_integrator_from_config(&c0, *s, NULL, &w);
  if (st) return st;
  int n3 = 3 * (*s)->mesh.nv;
  *x = malloc((size_t)n3 * sizeof **x), *v = malloc((size_t)n3 * sizeof **v);
  if (!*x || !*v) {
    cb_integrator_free(w);
    return CB_ENOMEM;
  }
  memcpy(*x, (*s)->x0, (size_t)n3 * sizeof **x);
  memcpy(*v, (*s)->v0, (size_t)n3 * sizeof **v);
  for (int k = 0; k < warm && st == CB_OK; k++) {
    cb_step_stats ss;
    memset(&ss, 0, sizeof ss);
    st = cb_integrator_step(w, *x, *v, &ss);
    if (!cb_status_is_fatal(st)) st = CB_OK;
  }
  cb_integrator_free(w);
  return st;
}

/* An integrator on the warm scene s from the scene's config with `trial` (NULL-terminated) on top. */
static int c3_integrator(const plan *p, int scene, cb_scene *s, const char *const *trial, cb_integrator **it) {
  char sn[32];
  snprintf(sn, sizeof sn, "mesh.n=%d", p->mesh_n);
  const char *more[16] = {"contact.method=ipc", p->mesh_n > 0 ? sn : NULL};
  int m = more[1] ? 2 : 1;
  for (int k = 0; trial[k] && m < 15; k++) more[m++] = trial[k];
  more[m] = NULL;
  static cb_config c1;
  *it = NULL;
  int st = cb_scene_decl_config(p->e, &SCENES[p->scene[scene]].scene, more, &c1);
  return st ? st : cb_integrator_from_config(&c1, s, NULL, it);
}

/* One step of it from the warm state (xw, vw, the obstacle's clock at tw) into x (v: scratch). */
static int c3_step(cb_scene *s, cb_integrator *it, const double *xw, const double *vw, double tw, double *x, double *v,
                   cb_step_stats *ss) {
  size_t n = 3 * (size_t)s->mesh.nv * sizeof *x;
  memcpy(x, xw, n);
  memcpy(v, vw, n);
  cb_scene_obstacle_set_time(s, tw);
  memset(ss, 0, sizeof *ss);
  return cb_integrator_step(it, x, v, ss);
}

static double dist2(const double *a, const double *b, int n) {
  double q = 0;
  for (int i = 0; i < n; i++) q += (a[i] - b[i]) * (a[i] - b[i]);
  return sqrt(q);
}

/* The intersecting triangle pairs of x (cloth-cloth, and cloth-obstacle with the obstacle where it is now), NaN when
 * they cannot be counted. */
static double c3_intersections(const cb_scene *s, cb_intersections *self, int have_self, const double *x) {
  int n3 = 3 * s->mesh.nv;
  long ns = 0;
  if (!have_self || !all_finite(x, n3) || cb_intersections_count(self, x, &ns) != CB_OK) return NAN;
  const cb_obstacle *o = cb_scene_obstacle(s);
  if (!o) return (double)ns;
  double *obox = malloc((size_t)6 * (size_t)(o->mesh.nt > 0 ? o->mesh.nt : 1) * sizeof *obox);
  if (!obox) return NAN;
  long no = obstacle_intersections(&s->mesh, x, &o->mesh, o->x, obox);
  free(obox);
  return (double)(ns + no);
}

static void c3_note(char *note, size_t n, const char *msg) {
  snprintf(note, n, "%s", msg);
  for (char *q = note; *q; q++)
    if (*q == ',' || *q == '\n' || *q == '"') *q = ';';
}

/* One scene: the warm state (once), the reference step, then every rung of every method's ladder: its first step
 * (untimed: the result, its error and intersections, and the caches warmed), then interleaved timed rounds over all
 * rungs (stats.h: 3 with --quick, 2-5 in a full run by cost, 1 with --smoke; a step under 25 ms timed right after an
 * untimed one of its own). Every step starts from the same saved state with the obstacle's clock rewound, so each
 * repeat must end where the rung's first step did, bit for bit (counted in the note otherwise). */
static int c3_cell(long i, void *ctx, FILE *const *out) {
  const plan *p = ctx;
  FILE *f = out[1];
  const char *label = SCENES[p->scene[i]].scene.label;
  int warm = p->c3_warm, kind = p->e->smoke ? 2 : p->e->quick ? 1 : 0;
  cb_scene *s = NULL;
  double *xw = NULL, *vw = NULL;
  int st = c3_warm_scene(p, (int)i, warm, &s, &xw, &vw);
  if (st) {
    cb_csv_printf(f, "%s,,reference,newton,,,%d,,,,,,,,,,%s\n", label, warm, cb_status_name(st));
    free(xw), free(vw), cb_scene_free(s);
    return CB_OK;
  }
  int nv = s->mesh.nv, n3 = 3 * nv;
  const cb_obstacle *o = cb_scene_obstacle(s);
  double tw = o ? o->t : 0.0;
  cb_scene_size sz;
  double dt = cb_sweep_scene_size(p->e, &SCENES[p->scene[i]].scene, &sz) == CB_OK ? sz.dt : cb_csv_na();
  static c3_rung rungs[C3_MAXRUNGS];
  int nr = 0;
  double *xref = malloc((size_t)n3 * sizeof *xref), *x = malloc((size_t)n3 * sizeof *x),
         *v = malloc((size_t)n3 * sizeof *v);
  cb_intersections self;
  int have_self = cb_intersections_init(&self, &s->mesh) == CB_OK;
  /* the reference: Newton from the warm state to convergence */
  static const char *const ref_sets[] = {"integrator.method=newton", "integrator.max_iters=500", "integrator.tol=1e-10",
                                         "integrator.tol_dx=1e-12", NULL};
  cb_integrator *ref = NULL;
  st = xref && x && v ? c3_integrator(p, (int)i, s, ref_sets, &ref) : CB_ENOMEM;
  cb_step_stats rs;
  memset(&rs, 0, sizeof rs);
  int rst = st ? st : c3_step(s, ref, xw, vw, tw, xref, v, &rs);
  cb_integrator_free(ref);
  double scale = st ? NAN : dist2(xref, xw, n3);
  if (st || cb_status_is_fatal(rst) || !(scale > 0)) {
    cb_csv_printf(f, "%s,%d,reference,newton,%d,%.17g,%d,,%.6f,,,,,,,,%s\n", label, nv, rs.newton_iters, dt, warm,
                  rs.wall_ms,
                  st             ? cb_status_name(st)
                  : !(scale > 0) ? "invalid"
                                 : cb_status_name(rst));
    goto done;
  }
  cb_csv_printf(f, "%s,%d,reference,newton,%d,%.17g,%d,0,%.6f,,,,,%.17g,%.17g,,%s\n", label, nv, rs.newton_iters, dt,
                warm, rs.wall_ms, c3_intersections(s, &self, have_self, xref), scale, cb_status_name(rst));
  /* the rungs: each method's integrator at each iteration cap, and its first step */
  for (int m = 0; m < NC3; m++) {
    const c3_method *cm = &C3_METHODS[m];
    for (int k = 1; k <= cm->max_iters[kind] && nr < C3_MAXRUNGS; k *= 2) {
      c3_rung *r = &rungs[nr++];
      memset(r, 0, sizeof *r);
      r->cm = cm, r->k = k, r->err = r->nint = NAN;
      char sm[64], sk[64];
      snprintf(sm, sizeof sm, "integrator.method=%s", cm->method);
      snprintf(sk, sizeof sk, "%s=%d", cm->key, k);
      const char *sets[] = {sm, sk, "integrator.tol=0", "integrator.tol_dx=0", NULL};
      if (strcmp(cm->method, "newton")) sets[2] = NULL;
      r->st = c3_integrator(p, (int)i, s, sets, &r->it);
      if (r->st) { /* the method refuses the scene: its reason, and no longer rungs */
        c3_note(r->note, sizeof r->note, cb_error_message());
        break;
      }
      if (!(r->x = malloc((size_t)n3 * sizeof *r->x))) {
        r->st = CB_ENOMEM;
        break;
      }
      cb_step_stats ss;
      r->tst = c3_step(s, r->it, xw, vw, tw, r->x, v, &ss);
      if (all_finite(r->x, n3)) r->err = dist2(r->x, xref, n3) / scale;
      r->nint = c3_intersections(s, &self, have_self, r->x);
      r->truncated = cb_vbd_truncated(r->it);
    }
  }
  /* the timed rounds, interleaved over the rungs */
  double spent = 0;
  for (int round = 0; kind == 2 ? round < 1 : cb_timing_more(p->e->quick, round, spent); round++)
    for (int j = 0; j < nr; j++) {
      c3_rung *r = &rungs[j];
      if (!r->it || !r->x || cb_status_is_fatal(r->tst)) continue;
      cb_step_stats ss;
      c3_step(s, r->it, xw, vw, tw, x, v, &ss);
      if (cb_timing_warm(ss.wall_ms)) c3_step(s, r->it, xw, vw, tw, x, v, &ss); /* that was its warm-up */
      cb_timing_add(&r->t, ss.wall_ms);
      spent += ss.wall_ms;
      r->dev = fmax(r->dev, dist2(x, r->x, n3) / scale);
    }
  for (int j = 0; j < nr; j++) {
    c3_rung *r = &rungs[j];
    const char *name = r->cm->method;
    if (r->st) {
      cb_csv_printf(f, "%s,%d,%s,%s,%d,%.17g,%d,,,,,,,,,%s,%s\n", label, nv, name, name, r->k, dt, warm, r->note,
                    r->st == CB_EINVAL ? "refused" : cb_status_name(r->st));
      continue;
    }
    /* a repeat may end a few ulps elsewhere (the contact term's trees, refit after other rungs' steps, list pairs
     * in another order); one that ends measurably elsewhere did other work than the first step: invalid */
    int differs = r->t.n > 0 && !(r->dev <= 1e-9 + 1e-3 * r->err);
    int u = 0;
    /* (the deviation is quoted only when it invalidates the row: how many repeats ran, and so the largest
     * deviation seen, depends on the timings, and the CSV's other columns must not: tests/determinism.sh) */
    if (differs) u = snprintf(r->note, sizeof r->note, "a repeat ended %.2g from the first step;", r->dev);
    if (r->truncated >= 0 && u >= 0 && (size_t)u < sizeof r->note)
      snprintf(r->note + u, sizeof r->note - (size_t)u, "bounds shortened %ld vertex updates", r->truncated);
    cb_csv_printf(f, "%s,%d,%s,%s,%d,%.17g,%d,%.17g,", label, nv, name, name, r->k, dt, warm,
                  isnan(r->err) ? cb_csv_na() : r->err);
    cb_timing_csv_repeats(f, r->t.n ? &r->t : NULL);
    cb_csv_printf(f, ",%.17g,,%s,%s\n", isnan(r->nint) ? cb_csv_na() : r->nint, r->note,
                  differs ? "invalid" : cb_status_name(r->tst));
  }
done:
  for (int j = 0; j < nr; j++) {
    cb_integrator_free(rungs[j].it);
    free(rungs[j].x);
  }
  if (have_self) cb_intersections_free(&self);
  free(xw), free(vw), free(xref), free(x), free(v);
  cb_scene_free(s);
  return CB_OK;
}

/* C2's theta list by run kind (degrees) and its simulated time per run (s) */
static const double C2_THETA_FULL[] = {10, 20, 30}, C2_THETA_QUICK[] = {10, 30}, C2_THETA_SMOKE[] = {20};
static contact_c2_plan c2_plan;
static int c2_cell(long i, void *ctx, FILE *const *out) {
  (void)ctx;
  return contact_c2_cell(&c2_plan, i, out[2]);
}

int main(int argc, char **argv) {
  cb_experiment e;
  int b = cb_experiment_begin(&e, "contact", ABOUT, argc, argv);
  if (b) return b > 0 ? 0 : 1;
  /* C1 counts intersections and C2 measures slides: no claim reads their wall times, so their cells share the
   * CPU; C3's error against time is timed (its cells run alone) */
  cb_experiment_timed_cells(&e, (const char *const[]){"C1", "C2", NULL});
  plan p = {.e = &e};
  int need = e.smoke ? 2 : e.quick ? 1 : 0;
  for (int i = 0; i < NSCENES; i++)
    if (SCENES[i].level >= need && cb_scene_decl_is(&SCENES[i].scene, "c1")) p.scene[p.nscenes++] = i;
  for (int k = 0; cb_contact_names[k] && p.nresp < MAXRESP; k++)
    if (strcmp(cb_contact_names[k], "none")) p.resp[p.nresp++] = cb_contact_names[k];
  if (e.smoke) {
    p.dt = DT_SMOKE, p.ndt = 1, p.speed = SPEED_SMOKE, p.nspeed = 1, p.smoke_steps = 3, p.mesh_n = 8, p.c3_warm = 2;
  } else if (e.quick) {
    p.dt = DT_QUICK, p.ndt = 2, p.speed = SPEED_QUICK, p.nspeed = 2, p.duration = 0.5, p.mesh_n = 12, p.c3_warm = 6;
  } else {
    p.dt = DT_FULL, p.ndt = 3, p.speed = SPEED_FULL, p.nspeed = 3, p.duration = 1.0, p.c3_warm = 12;
  }
  for (int k = 0; k < p.nscenes; k++) {
    cb_scene_size sz;
    int st = cb_sweep_scene_size(&e, &SCENES[p.scene[k]].scene, &sz);
    if (st) return cb_experiment_end(&e, st), 1;
    p.nv[k] = p.mesh_n > 0 ? (long)p.mesh_n * p.mesh_n : sz.nv > 0 ? sz.nv : 256;
  }
  char extra[512];
  int u = snprintf(extra, sizeof extra,
                   "# c1: every frame of %s%.3g s per cell (the start is frame 0); drop speed = an initial downward "
                   "velocity of every free vertex; mesh.n = %d (0: the config's); obstacle_intersections with the "
                   "obstacle where it is at that frame\n",
                   p.duration > 0 ? "" : "(smoke: 3 steps) ", p.duration, p.mesh_n);
  if (u < 0 || (size_t)u >= sizeof extra) return cb_experiment_end(&e, CB_EINVAL), 1;
  if (cb_experiment_table(&e, NULL, extra,
                          "scene,vertices,response,integrator,dt_s,speed_m_per_s,frame,t_s,self_intersections,"
                          "obstacle_intersections,intersections,min_separation_m,contacts,newton_iters,wall_ms,"
                          "status") != 0)
    return cb_experiment_end(&e, CB_EIO), 2;
  if (cb_experiment_table(&e, "c3",
                          "# c3: one step from the state after the warm-up frames of ipc under Newton (column frame); "
                          "step_error = |x - x*| / |x* - x_start| (2-norms), x* = the reference row's step (Newton, "
                          "<= 500 iterations, tol 1e-10); ref_step_m = |x* - x_start|; iters = the method's iteration "
                          "cap (Newton: max_iters with tol = tol_dx = 0; lbfgs, vbd: integrator.iters); the reference "
                          "row's iters are the iterations it took\n",
                          "scene,vertices,method,integrator,iters,dt_s,frame,step_error,wall_ms,wall_min_ms,"
                          "wall_max_ms,wall_each_ms,wall_repeats,intersections,ref_step_m,note,status") != 1)
    return cb_experiment_end(&e, CB_EIO), 2;
  c2_plan = (contact_c2_plan){.e = &e,
                              .theta = e.smoke   ? C2_THETA_SMOKE
                                       : e.quick ? C2_THETA_QUICK
                                                 : C2_THETA_FULL,
                              .ntheta = e.smoke   ? 1
                                        : e.quick ? 2
                                                  : 3,
                              .t_end = e.smoke   ? 0.1
                                       : e.quick ? 0.5
                                                 : 1.0};
  char c2_extra[512];
  u = snprintf(c2_extra, sizeof c2_extra,
               "# c2: configs/slope.ini (ipc, Newton), %.3g s a run; slide rows at mu = f tan theta, f in {0.5, 0.9, "
               "1.1, 1.5, 2}; the threshold row: mu* by bisection on slide > 1 cm (t_end / 1 s)^2, to 2%% of tan "
               "theta; creep_m = the slide at the holding end of the last bracket; a vbd row at mu = 0.5 tan theta\n",
               c2_plan.t_end);
  if (u < 0 || (size_t)u >= sizeof c2_extra) return cb_experiment_end(&e, CB_EINVAL), 1;
  if (cb_experiment_table(&e, "c2", c2_extra, CONTACT_C2_COLUMNS) != 2) return cb_experiment_end(&e, CB_EIO), 2;
  const cb_sweep sweeps[] = {{"C1", (long)p.nscenes * p.nresp * p.ndt * p.nspeed, run_cell, cost, &p, NULL},
                             {"C3", p.nscenes, c3_cell, NULL, &p, NULL},
                             {"C2", c2_plan.ntheta, c2_cell, NULL, &p, NULL}};
  int st = cb_sweep_run(&e, sweeps, 3);
  st = cb_experiment_end(&e, st);
  return st == CB_OK ? 0 : st == CB_EIO ? 2 : 1;
}
