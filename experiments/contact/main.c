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
 * C3  results/contact_c3.csv (the start of C3; no verdict yet): per scene, the state after W frames of
 *     ipc under Newton (the scene's config, dt = 1/30 s, no drop speed: W = 12, --quick 6, --smoke 2),
 *     then one step from it by each method that takes ipc, at a ladder of iteration counts (Newton:
 *     integrator.max_iters 1..32 with tol = tol_dx = 0; L-BFGS: integrator.iters 1..64), against IPC's
 *     converged step x* (Newton from the same state, at most 500 iterations, tol 1e-10): step_error =
 *     |x - x*| / |x* - x_W| (2-norms over all coordinates), the step's wall time, and the exact
 *     intersection count of its result. VBD refuses a term that bounds its steps (it has no contact
 *     yet): its row records status `refused` and the reason. Each trial warms up its own scene (the same
 *     config and steps, so the same start state, checked bit for bit against the reference's).
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
    "the contact count: C1 (IPC stays intersection-free where a penalty without CCD tunnels).";

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
  int max_iters;      /* the ladder 1, 2, 4, ... up to this (0: one trial, the method may refuse) */
} c3_method;
static const c3_method C3_METHODS[] = {
    {"newton", "integrator.max_iters", 32},
    {"lbfgs", "integrator.iters", 64},
    {"vbd", "integrator.iters", 0},
};
enum { NC3 = sizeof C3_METHODS / sizeof C3_METHODS[0] };

/* The cell's scene after `warm` frames of ipc under the config's Newton, and a second integrator on it from the
 * config with `trial` (NULL-terminated) on top. *x, *v: the state (3 nv, allocated). */
static int c3_start(const plan *p, int scene, const char *const *trial, int warm, cb_scene **s, cb_integrator **it,
                    double **x, double **v) {
  char sn[32];
  snprintf(sn, sizeof sn, "mesh.n=%d", p->mesh_n);
  const cb_scene_decl *d = &SCENES[p->scene[scene]].scene;
  const char *base[] = {"contact.method=ipc", p->mesh_n > 0 ? sn : NULL, NULL};
  const char *more[16] = {base[0], base[1]};
  int m = base[1] ? 2 : 1;
  for (int k = 0; trial[k] && m < 15; k++) more[m++] = trial[k];
  more[m] = NULL;
  static cb_config c0, c1;
  *s = NULL, *it = NULL, *x = NULL, *v = NULL;
  cb_integrator *w = NULL;
  int st = cb_scene_decl_build(p->e, d, base, &c0, s);
  if (st == CB_OK) st = cb_integrator_from_config(&c0, *s, NULL, &w);
  if (st == CB_OK) st = cb_scene_decl_config(p->e, d, more, &c1);
  if (st == CB_OK) st = cb_integrator_from_config(&c1, *s, NULL, it);
  if (st) {
    cb_integrator_free(w);
    return st;
  }
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

static void c3_free(cb_scene *s, cb_integrator *it, double *x, double *v) {
  free(x);
  free(v);
  cb_integrator_free(it);
  cb_scene_free(s);
}

static double dist2(const double *a, const double *b, int n) {
  double q = 0;
  for (int i = 0; i < n; i++) q += (a[i] - b[i]) * (a[i] - b[i]);
  return sqrt(q);
}

static int c3_cell(long i, void *ctx, FILE *const *out) {
  const plan *p = ctx;
  FILE *f = out[1];
  const char *label = SCENES[p->scene[i]].scene.label;
  int warm = p->c3_warm;
  /* the reference: Newton from the warm state to convergence */
  static const char *const ref_sets[] = {"integrator.method=newton", "integrator.max_iters=500", "integrator.tol=1e-10",
                                         "integrator.tol_dx=1e-12", NULL};
  cb_scene *s = NULL;
  cb_integrator *it = NULL;
  double *x = NULL, *v = NULL;
  int st = c3_start(p, (int)i, ref_sets, warm, &s, &it, &x, &v);
  if (st) {
    cb_csv_printf(f, "%s,,reference,newton,,,%d,,,,,,%s\n", label, warm, cb_status_name(st));
    c3_free(s, it, x, v);
    return CB_OK;
  }
  int nv = s->mesh.nv, n3 = 3 * nv;
  cb_scene_size sz;
  double dt = cb_sweep_scene_size(p->e, &SCENES[p->scene[i]].scene, &sz) == CB_OK ? sz.dt : cb_csv_na();
  double *xw = malloc((size_t)n3 * sizeof *xw), *xref = malloc((size_t)n3 * sizeof *xref);
  if (!xw || !xref) {
    free(xw), free(xref);
    c3_free(s, it, x, v);
    return CB_ENOMEM;
  }
  memcpy(xw, x, (size_t)n3 * sizeof *xw);
  cb_step_stats rs;
  memset(&rs, 0, sizeof rs);
  int rst = cb_integrator_step(it, x, v, &rs);
  memcpy(xref, x, (size_t)n3 * sizeof *xref);
  double scale = dist2(xref, xw, n3);
  cb_intersections self;
  int have_self = cb_intersections_init(&self, &s->mesh) == CB_OK;
  long nref = 0;
  if (have_self && all_finite(xref, n3)) (void)cb_intersections_count(&self, xref, &nref);
  cb_csv_printf(f, "%s,%d,reference,newton,%d,%.17g,%d,0,%.6f,%ld,%.17g,,%s\n", label, nv, rs.newton_iters, dt, warm,
                rs.wall_ms, nref, scale, cb_status_name(rst));
  /* the reference's scene stays until the end: self counts on its mesh (the trials' meshes are the same) */
  cb_scene *ref_s = s;
  cb_integrator *ref_it = it;
  free(x), free(v);
  for (int m = 0; m < NC3; m++) {
    const c3_method *cm = &C3_METHODS[m];
    for (int k = 1; k == 1 || k <= cm->max_iters; k *= 2) {
      char sm[64], sk[64];
      snprintf(sm, sizeof sm, "integrator.method=%s", cm->method);
      snprintf(sk, sizeof sk, "%s=%d", cm->key, k);
      const char *sets[] = {sm, sk, "integrator.tol=0", "integrator.tol_dx=0", NULL};
      if (strcmp(cm->method, "newton")) sets[2] = NULL;
      st = c3_start(p, (int)i, sets, warm, &s, &it, &x, &v);
      if (st) {
        /* the method refuses the scene (VBD and ipc's step bound): its reason, commas replaced */
        char note[512];
        snprintf(note, sizeof note, "%s", cb_error_message());
        for (char *q = note; *q; q++)
          if (*q == ',' || *q == '\n') *q = ';';
        cb_csv_printf(f, "%s,%d,%s,%s,%d,%.17g,%d,,,,,%s,%s\n", label, nv, cm->method, cm->method, k, dt, warm, note,
                      st == CB_EINVAL ? "refused" : cb_status_name(st));
        c3_free(s, it, x, v);
        break;
      }
      /* the same start as the reference's, bit for bit (the same config and steps) */
      if (memcmp(x, xw, (size_t)n3 * sizeof *x)) {
        cb_csv_printf(f, "%s,%d,%s,%s,%d,%.17g,%d,,,,,start differs from the reference's,invalid\n", label, nv,
                      cm->method, cm->method, k, dt, warm);
        c3_free(s, it, x, v);
        break;
      }
      cb_step_stats ss;
      memset(&ss, 0, sizeof ss);
      int tst = cb_integrator_step(it, x, v, &ss);
      double err = all_finite(x, n3) ? dist2(x, xref, n3) / scale : NAN;
      long nint = -1;
      if (have_self && all_finite(x, n3)) (void)cb_intersections_count(&self, x, &nint);
      const cb_obstacle *o = cb_scene_obstacle(s);
      double *obox = o ? malloc((size_t)6 * (size_t)o->mesh.nt * sizeof *obox) : NULL;
      if (nint >= 0 && o && obox) nint += obstacle_intersections(&s->mesh, x, &o->mesh, o->x, obox);
      else if (o) nint = -1;
      free(obox);
      cb_csv_printf(f, "%s,%d,%s,%s,%d,%.17g,%d,%.17g,%.6f,%.17g,,,%s\n", label, nv, cm->method, cm->method, k, dt,
                    warm, err, ss.wall_ms, nint < 0 ? cb_csv_na() : (double)nint, cb_status_name(tst));
      c3_free(s, it, x, v);
      if (cm->max_iters == 0) break;
    }
  }
  if (have_self) cb_intersections_free(&self);
  c3_free(ref_s, ref_it, NULL, NULL);
  free(xw);
  free(xref);
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
                          "scene,vertices,method,integrator,iters,dt_s,frame,step_error,wall_ms,intersections,"
                          "ref_step_m,note,status") != 1)
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
