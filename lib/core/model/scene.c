#include <clothbench/scene.h>

#include <ctype.h>
#include <errno.h>
#include <float.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <clothbench/status.h>
#include "vec.h"

static int cmp_int(const void *a, const void *b) {
  int p = *(const int *)a, q = *(const int *)b;
  return (p > q) - (p < q);
}

/* `halfspace a b c d`: the vertices whose rest position p has a.p <= d, to
 * 1e-9 of the mesh's bounding-box diagonal (so vertices on the plane count). */
static int pins_halfspace(const char *spec, const cb_mesh *m, int *list, int *cnt) {
  double h[4];
  const char *p = spec + strlen("halfspace");
  int k = 0;
  for (;;) {
    while (*p == ' ' || *p == '\t' || *p == ',') p++;
    if (!*p) break;
    char *end;
    double v = k < 4 ? strtod(p, &end) : 0;
    if (k >= 4 || end == p || !isfinite(v) || (*end && *end != ' ' && *end != '\t' && *end != ',')) {
      k = -1;
      break;
    }
    h[k++] = v;
    p = end;
  }
  /* (a, b, c, d) / max |a|, |b|, |c| first: the set is the same, and a b c near 1e-300 do not underflow the norm */
  double hs = k == 4 ? fmax(fabs(h[0]), fmax(fabs(h[1]), fabs(h[2]))) : 0;
  for (int a = 0; hs > 0 && a < 4; a++) h[a] /= hs;
  double nn = hs > 0 ? sqrt(h[0] * h[0] + h[1] * h[1] + h[2] * h[2]) : 0;
  if (hs > 0 && !isfinite(h[3] / nn))
    return cb_fail("scene.pins: '%s': the plane's offset d / |(a, b, c)| is not a finite double", spec);
  if (!(nn > 0) || !isfinite(nn) || !isfinite(h[3] / nn))
    return cb_fail("scene.pins: '%s' is not `halfspace a b c d` (4 finite numbers separated by spaces or commas, "
                   "(a, b, c) not zero): the vertices whose rest position p has a p_x + b p_y + c p_z <= d",
                   spec);
  double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY}, diag = 0;
  for (int i = 0; i < m->nv; i++)
    for (int a = 0; a < 3; a++) {
      lo[a] = fmin(lo[a], m->x[3 * i + a]);
      hi[a] = fmax(hi[a], m->x[3 * i + a]);
    }
  for (int a = 0; m->nv > 0 && a < 3; a++) diag += (hi[a] - lo[a]) * (hi[a] - lo[a]);
  double tol = 1e-9 * sqrt(diag);
  for (int i = 0; i < m->nv; i++) {
    const double *x = m->x + 3 * i;
    if ((h[0] * x[0] + h[1] * x[1] + h[2] * x[2] - h[3]) / nn <= tol) list[(*cnt)++] = i;
  }
  return CB_OK;
}

int cb_pins_resolve(const char *spec, const cb_mesh *m, int **out, int *n) {
  *out = NULL;
  *n = 0;
  if (!*spec) return cb_fail("scene.pins: empty; use `none` for no pins");
  /* an index list has at most strlen(spec) entries; a named set at most nv */
  int *list = cb_malloc((size_t)m->nv + strlen(spec) + 8, sizeof(int));
  if (!list) return CB_ENOMEM;
  int cnt = 0, gn = m->grid_n, gm = m->grid_m;
  int named = strcmp(spec, "none") == 0 || strcmp(spec, "corners") == 0 || strcmp(spec, "top-corners") == 0 ||
              strcmp(spec, "top-edge") == 0;
  if (named && strcmp(spec, "none") != 0 && gn <= 0) {
    free(list);
    return cb_fail("scene.pins: named set '%s' needs a grid mesh; give vertex indices for an OBJ mesh", spec);
  }
  if (named && gm == 1) { /* a chain: its top is vertex n-1, its corners are its two ends */
    if (strcmp(spec, "corners") == 0) list[cnt++] = 0;
    if (strcmp(spec, "none") != 0) list[cnt++] = gn - 1;
  } else if (strcmp(spec, "corners") == 0) {
    list[cnt++] = 0;
    list[cnt++] = gn - 1;
    list[cnt++] = (gm - 1) * gn;
    list[cnt++] = gm * gn - 1;
  } else if (strcmp(spec, "top-corners") == 0) {
    list[cnt++] = (gm - 1) * gn;
    list[cnt++] = gm * gn - 1;
  } else if (strcmp(spec, "top-edge") == 0) {
    for (int i = 0; i < gn; i++) list[cnt++] = (gm - 1) * gn + i;
  } else if (strncmp(spec, "halfspace", 9) == 0 && (!spec[9] || spec[9] == ' ' || spec[9] == '\t' || spec[9] == ',')) {
    int st = pins_halfspace(spec, m, list, &cnt);
    if (st) {
      free(list);
      return st;
    }
  } else if (!named) { /* 0-based indices separated by spaces or commas */
    const char *p = spec;
    while (*p) {
      while (*p == ' ' || *p == '\t' || *p == ',') p++;
      if (!*p) break;
      if (!isdigit((unsigned char)*p)) {
        free(list);
        return cb_fail("scene.pins: '%s' is not a named set (none, corners, top-corners, top-edge), "
                       "`halfspace a b c d` or a list of 0-based vertex indices",
                       spec);
      }
      char *end;
      errno = 0;
      long v = strtol(p, &end, 10);
      if (*end && *end != ' ' && *end != '\t' && *end != ',') {
        free(list);
        return cb_fail("scene.pins: bad vertex index near '%.20s'", p);
      }
      if (errno == ERANGE || v >= m->nv) { /* the index as written: strtol clamps an overflow to LONG_MAX */
        free(list);
        return cb_fail("scene.pins: vertex %.*s out of range (the mesh has %d vertices, 0-based)",
                       (int)(end - p > 40 ? 40 : end - p), p, m->nv);
      }
      list[cnt++] = (int)v;
      p = end;
    }
  }
  qsort(list, (size_t)cnt, sizeof(int), cmp_int);
  int u = 0;
  for (int k = 0; k < cnt; k++)
    if (u == 0 || list[k] != list[u - 1]) list[u++] = list[k];
  *out = list;
  *n = u;
  return CB_OK;
}

void cb_scene_free(cb_scene *s) {
  if (!s) return;
  for (int k = 0; k < s->nresponses; k++) cb_response_free(&s->responses[k]);
  cb_system_free(&s->sys);
  cb_mesh_free(&s->mesh);
  cb_topology_free(&s->topo);
  free(s->mass);
  free(s->pinned);
  free(s->free_index);
  free(s->free_vertex);
  free(s->x0);
  free(s->v0);
  free(s);
}

double cb_scene_total_mass(const cb_scene *s) {
  double msum = 0;
  for (int i = 0; i < s->mesh.nv; i++) msum += s->mass[i];
  return msum;
}

cb_scene_def cb_scene_def_default(void) {
  cb_scene_def d = {
      .cookie = CB_PARAMS_COOKIE,
      .mesh = CB_MESH_GRID,
      .grid = cb_grid_params_default(),
      .mesh_file = NULL,
      .density = 1,
      .vertex_mass = 0,
      .stretch = "spring",
      .stretch_k = 8000,
      .fem_hessian = "exact",
      .bend = "none",
      .bend_k = 100,
      .bend_hessian = "gauss-newton",
      .definiteness = "drop",
      .buckling_kb = 0.01,
      .gravity = {0, -9.8, 0},
      .pins = "top-corners",
      .initial_scale = 1,
      .pin_squeeze = {0, 0, 0},
      .diverge_ratio = 10,
      .collider = "none",
      .sphere = {.centre = {0, 0, 0}, .radius = 1, .thickness = 0, .stiffness = 10000, .velocity = {0, 0, 0}},
      .obstacle = cb_obstacle_params_default(),
      .contact = "none",
      .contact_params = cb_contact_params_default(),
      .nresponses = 0};
  return d;
}

/* What the responses see of s (response.h): the obstacle is that of the
 * responses built so far. */
static cb_response_view response_view(const cb_scene *s) {
  return (cb_response_view){
      .mesh = &s->mesh, .mass = s->mass, .free_index = s->free_index, .x0 = s->x0, .obstacle = cb_scene_obstacle(s)};
}

const cb_obstacle *cb_scene_obstacle(const cb_scene *s) {
  for (int k = 0; k < s->nresponses; k++) {
    const cb_obstacle *o = cb_obstacle_of(&s->responses[k]);
    if (o) return o;
  }
  return NULL;
}

double cb_scene_obstacle_time(const cb_scene *s) {
  for (int k = 0; k < s->nresponses; k++) {
    double t = cb_obstacle_time_of(&s->responses[k]);
    if (!isnan(t)) return t;
  }
  return 0.0;
}

void cb_scene_obstacle_set_time(cb_scene *s, double t) {
  for (int k = 0; k < s->nresponses; k++)
    if (cb_obstacle_set_time_of(&s->responses[k], t)) return;
}

const cb_bridson_stats *cb_scene_bridson_stats(const cb_scene *s) {
  for (int k = 0; k < s->nresponses; k++) {
    const cb_bridson_stats *b = cb_bridson_stats_of(&s->responses[k]);
    if (b) return b;
  }
  return NULL;
}

int cb_scene_contacts(const cb_scene *s, const double *x) {
  int n = 0;
  for (int k = 0; k < s->sys.nterms; k++) n += cb_sphere_term_count_contacts(s->sys.terms[k], x);
  for (int k = 0; k < s->nresponses; k++) n += cb_sphere_project_contacts(&s->responses[k]);
  return n;
}

int cb_scene_post_step(const cb_scene *s, const double *x_start, double *x, double *v, double dt) {
  cb_response_view view = response_view(s);
  /* a response's state is its own, not the scene's: the stage runs on a const scene */
  return cb_response_apply_all((cb_response *)s->responses, s->nresponses, &view, x_start, x, v, dt);
}

double cb_scene_kinetic(const cb_scene *s, const double *v) {
  double K = 0.0;
  for (int i = 0; i < s->mesh.nv; i++)
    K += 0.5 * s->mass[i] * (v[3 * i] * v[3 * i] + v[3 * i + 1] * v[3 * i + 1] + v[3 * i + 2] * v[3 * i + 2]);
  return K;
}

/* Sets *key (if asked) for an error about the field that key names. */
static int at_key(int st, const char **key, const char *name) {
  if (st && key) *key = name;
  return st;
}

/* Prefixes the current error message with label: "mesh: grid needs ...". */
static int labelled(int st, const char *label) {
  if (st == CB_OK) return st;
  char msg[1024];
  snprintf(msg, sizeof msg, "%s", cb_error_message());
  return cb_fail_status(st, "%s: %s", label, msg);
}

/* The key that set the mesh: mesh.file for an OBJ, else mesh.size. */
static const char *mesh_key(const cb_scene_def *d) { return d->mesh == CB_MESH_OBJ ? "mesh.file" : "mesh.size"; }

/* An error about vertex i of the mesh, prefixed with where it came from:
 * "mesh.file: cloth.obj:12: ..." (the line of its `v` statement) for an OBJ,
 * "mesh: ..." for a generated mesh; i < 0: about no one vertex. */
__attribute__((format(printf, 4, 5))) static int mesh_fail(const cb_scene_def *d, const cb_mesh *m, int i,
                                                           const char *fmt, ...) {
  char msg[768];
  va_list ap;
  va_start(ap, fmt);
  vsnprintf(msg, sizeof msg, fmt, ap);
  va_end(ap);
  if (d->mesh == CB_MESH_OBJ && d->mesh_file && m->vline && i >= 0 && i < m->nv)
    return cb_fail("mesh.file: %s:%d: %s", d->mesh_file, m->vline[i], msg);
  if (d->mesh == CB_MESH_OBJ && d->mesh_file) return cb_fail("mesh.file: %s: %s", d->mesh_file, msg);
  return cb_fail("mesh: %s", msg);
}

/* Largest |a - b| over the mesh's edges, without overflow in the squares. */
static double longest_edge(const cb_scene *s) {
  double lmax = 0;
  for (int e = 0; e < s->topo.ne; e++) {
    const double *a = s->mesh.x + 3 * s->topo.edge[2 * e], *b = s->mesh.x + 3 * s->topo.edge[2 * e + 1];
    double m = fmax(fabs(a[0] - b[0]), fmax(fabs(a[1] - b[1]), fabs(a[2] - b[2])));
    if (!(m > 0) || !isfinite(m)) {
      lmax = fmax(lmax, m);
      continue;
    }
    double u = (a[0] - b[0]) / m, v = (a[1] - b[1]) / m, w = (a[2] - b[2]) / m;
    lmax = fmax(lmax, m * sqrt(u * u + v * v + w * w));
  }
  return lmax;
}

/* Every derived quantity of the start state is a finite double: x0, the
 * kinetic energy of v0, each term's energy at x0 (so the rest lengths too:
 * an infinite one makes its spring's energy NaN) and the divergence scale.
 * A non-finite one would make row 0 of every run NaN. */
static int check_finite(const cb_scene *s, const cb_scene_def *d, const char **key) {
  int nv = s->mesh.nv;
  for (int i = 0; i < 3 * nv; i++)
    if (!isfinite(s->x0[i]))
      return at_key(cb_fail("scene.initial_scale: vertex %d's initial position, %g x its offset from the centroid, "
                            "is not a finite double",
                            i / 3, d->initial_scale),
                    key, "scene.initial_scale");
  for (int e = 0; e < s->topo.ne; e++) { /* each edge's direction at x0: a squared length that underflows has none */
    const double *a = s->x0 + 3 * s->topo.edge[2 * e], *b = s->x0 + 3 * s->topo.edge[2 * e + 1];
    double l2 = (a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) + (a[2] - b[2]) * (a[2] - b[2]);
    if (l2 >= DBL_MIN) continue;
    const char *what = l2 == 0 ? "zero length" : "a length too small to square";
    if (d->initial_scale == 1) /* the mesh as given */
      return at_key(mesh_fail(d, &s->mesh, -1,
                              "the edge between vertices %d and %d has %s (squared length %g m^2): "
                              "the mesh's coordinates are too small (scale the mesh up)",
                              s->topo.edge[2 * e], s->topo.edge[2 * e + 1], what, l2),
                    key, mesh_key(d));
    return at_key(cb_fail("scene.initial_scale = %g: the edge between vertices %d and %d has %s at the initial state "
                          "(squared length %g m^2): the scaled offsets are below double precision's reach at "
                          "these coordinates",
                          d->initial_scale, s->topo.edge[2 * e], s->topo.edge[2 * e + 1], what, l2),
                  key, "scene.initial_scale");
  }
  double K = cb_scene_kinetic(s, s->v0);
  if (!isfinite(K))
    return at_key(cb_fail("scene.pin_squeeze: the initial kinetic energy of the driven pins is %g J, not a finite "
                          "double (masses up to the mesh's)",
                          K),
                  key, "scene.pin_squeeze");
  double per[CB_MAX_TERMS];
  cb_system_energy(&s->sys, s->x0, NULL, per);
  for (int k = 0; k < s->sys.nterms; k++) {
    if (isfinite(per[k])) continue;
    const char *label = s->sys.terms[k]->label, *tkey = "material.stretch_k";
    char what[96];
    snprintf(what, sizeof what, "material.stretch_k = %g N/m", d->stretch_k);
    if (strcmp(label, "gravity") == 0) {
      tkey = "scene.gravity";
      snprintf(what, sizeof what, "|scene.gravity| = %g m/s^2", cb_v3_norm(d->gravity));
    } else if (strcmp(label, "stretch") != 0) {
      tkey = "material.bend_k";
      snprintf(what, sizeof what, "material.bend_k = %g N/m", d->bend_k);
    }
    return at_key(cb_fail("%s: the %s energy at the initial state is %g J, not a finite double (%s, total mass "
                          "%g kg, longest edge %g m, scene.initial_scale = %g): the scene is too large for double "
                          "precision",
                          tkey, label, per[k], what, cb_scene_total_mass(s), longest_edge(s), d->initial_scale),
                  key, tkey);
  }
  if (!isfinite(s->energy_scale))
    return at_key(labelled(cb_fail("the energy scale S (elastic energy + total mass %g kg x |g| x the bounding-box "
                                   "diagonal %g m) is %g J, not a finite double",
                                   cb_scene_total_mass(s), cb_mesh_bbox_diagonal(&s->mesh), s->energy_scale),
                           mesh_key(d)),
                  key, mesh_key(d));
  return CB_OK;
}

/* A collider error names its key first ("collider.radius: ..."): that key. */
static int collider_error(int st, const char **key) {
  static const char *const keys[] = {"collider.radius",   "collider.thickness",    "collider.stiffness",
                                     "collider.velocity", "collider.centre",       "collider.file",
                                     "collider.axis",     "collider.angular_speed"};
  if (st == CB_OK || !key) return st;
  *key = "collider.type";
  for (size_t k = 0; k < sizeof keys / sizeof keys[0]; k++)
    if (strncmp(cb_error_message(), keys[k], strlen(keys[k])) == 0) *key = keys[k];
  return st;
}

static int build_mesh(const cb_scene_def *d, cb_mesh *mesh, const char **key) {
  if (d->mesh == CB_MESH_OBJ) {
    if (!d->mesh_file) return at_key(cb_fail("mesh.file: required for an OBJ mesh"), key, "mesh.file");
    return at_key(labelled(cb_mesh_read_obj(d->mesh_file, mesh), "mesh.file"), key, "mesh.file");
  }
  if (d->mesh == CB_MESH_CHAIN)
    return at_key(labelled(cb_mesh_chain(d->grid.n, d->grid.size[0], d->grid.plane, mesh), "mesh"), key, "mesh.n");
  return at_key(labelled(cb_mesh_grid(&d->grid, mesh), "mesh"), key, "mesh.n");
}

/* ---- cb_scene_build, phase by phase: each returns CB_OK or the error, with
 * *key (if asked) set to the config key it is about. ----------------------- */

/* The definition's names and responses, before anything is allocated. */
static int check_def(const cb_scene_def *d, const cb_collider **collider, const char **key) {
  int st = cb_params_check(d->cookie, "scene", "cb_scene_def_default");
  if (st == CB_OK) st = cb_params_check(d->contact_params.cookie, "scene: contact_params", "cb_contact_params_default");
  if (st) return st;
  if (!d->bend || !d->definiteness || !d->pins ||
      !d->collider) /* e.g. a copy of cb_scene.def, whose strings are NULL */
    return cb_fail("scene: bend, definiteness, pins and collider must be set (start from cb_scene_def_default())");
  *collider = cb_collider_find(d->collider);
  if (!*collider) return at_key(cb_fail("collider.type: unknown collider '%s'", d->collider), key, "collider.type");
  const cb_contact_type *ct = cb_contact_type_find(d->contact ? d->contact : "none");
  int extra = ((*collider)->response != NULL) + (ct && ct->response != NULL);
  if (d->nresponses + extra > CB_MAX_RESPONSES)
    return cb_fail("scene: %d post-step responses (at most %d)", d->nresponses + extra, CB_MAX_RESPONSES);
  if (d->nresponses < 0 || d->nresponses > CB_MAX_RESPONSES)
    return cb_fail("scene: %d post-step responses (at most %d)", d->nresponses, CB_MAX_RESPONSES);
  for (int k = 0; k < d->nresponses; k++)
    if (!d->responses[k].type || !d->responses[k].type->apply)
      return cb_fail("scene: post-step response %d has no type (or no apply)", k);
  return CB_OK;
}

/* The mesh, its topology, and the per-vertex arrays. */
static int build_geometry(const cb_scene_def *d, cb_scene *s, const char **key) {
  int st = build_mesh(d, &s->mesh, key);
  if (st == CB_OK) st = cb_topology_build(&s->mesh, &s->topo);
  if (st == CB_OK && s->topo.nonmanifold > 0 && strcmp(d->bend, "none") != 0)
    st = at_key(cb_fail("material.bend: the mesh has %d non-manifold edges (shared by more than two triangles); "
                        "bending needs a manifold mesh",
                        s->topo.nonmanifold),
                key, "material.bend");
  if (st) return st;
  int nv = s->mesh.nv;
  s->mass = cb_calloc((size_t)nv, sizeof(double));
  s->free_index = cb_malloc((size_t)nv, sizeof(int));
  s->free_vertex = cb_malloc((size_t)nv, sizeof(int));
  s->x0 = cb_malloc((size_t)3 * nv, sizeof(double));
  s->v0 = cb_calloc((size_t)3 * nv, sizeof(double));
  if (!s->mass || !s->free_index || !s->free_vertex || !s->x0 || !s->v0) return CB_ENOMEM;
  return CB_OK;
}

/* Masses: uniform, or lumped m_i = density * (sum of adjacent rest areas) / 3. */
static int build_masses(const cb_scene_def *d, cb_scene *s, const char **key) {
  int nv = s->mesh.nv;
  if (d->vertex_mass > 0 && !isfinite(1.0 / d->vertex_mass)) /* the methods that divide by m would write NaN */
    return at_key(cb_fail("material.vertex_mass = %g kg: its inverse 1/m is not a finite double (a subnormal mass); "
                          "a mass must be at least %g kg",
                          d->vertex_mass, 1.0 / DBL_MAX),
                  key, "material.vertex_mass");
  if (d->vertex_mass > 0)
    for (int i = 0; i < nv; i++) s->mass[i] = d->vertex_mass;
  else
    for (int t = 0; t < s->mesh.nt; t++) {
      double a = cb_mesh_triangle_area(&s->mesh, s->mesh.x, t);
      if (!isfinite(a))
        return at_key(mesh_fail(d, &s->mesh, -1,
                                "triangle %d has area %g m^2, not a finite double: "
                                "the mesh's coordinates are too large",
                                t + 1, a),
                      key, mesh_key(d));
      if (!(a >= DBL_MIN)) /* its vertices' masses would underflow to nothing */
        return at_key(mesh_fail(d, &s->mesh, -1,
                                "triangle %d has area %g m^2, below the smallest normal double: "
                                "the mesh's coordinates are too small (scale the mesh up)",
                                t + 1, a),
                      key, mesh_key(d));
      for (int k = 0; k < 3; k++) s->mass[s->mesh.tri[3 * t + k]] += d->density * a / 3.0;
    }
  for (int i = 0; i < nv; i++)
    if (!isfinite(s->mass[i]) || (s->mass[i] > 0 && !isfinite(1.0 / s->mass[i])))
      return at_key(cb_fail("material.density: vertex %d's mass, density %g kg/m^2 x its triangles' area / 3, is %g "
                            "kg, "
                            "not a finite double, or one whose inverse is not",
                            i, d->density, s->mass[i]),
                    key, "material.density");
  return CB_OK;
}

/* The pins, and the free vertices' block indices: the model terms are built on. */
static int build_free(const cb_scene_def *d, cb_scene *s, const char **key) {
  int st = at_key(cb_pins_resolve(d->pins, &s->mesh, &s->pinned, &s->npinned), key, "scene.pins");
  if (st) return st;
  int nfree = 0, p = 0;
  for (int i = 0; i < s->mesh.nv; i++) {
    if (p < s->npinned && s->pinned[p] == i) {
      s->free_index[i] = -1;
      p++;
      continue;
    }
    if (!(s->mass[i] > 0)) {
      if (s->mesh.nt == 0) /* a chain, or an OBJ of line elements only */
        return at_key(cb_fail("material.vertex_mass: the mesh has no triangles, so its vertices have no area and no "
                              "mass: set material.vertex_mass > 0 (vertex %d is the first free one)",
                              i),
                      key, "material.vertex_mass");
      return at_key(mesh_fail(d, &s->mesh, i,
                              "vertex %d (0-based; %d in the file's indices) belongs to no triangle "
                              "and has no mass: remove it, pin it (scene.pins), or set material.vertex_mass",
                              i, i + 1),
                    key, mesh_key(d));
    }
    s->free_vertex[nfree] = i;
    s->free_index[i] = nfree++;
  }
  s->model = (cb_model){&s->mesh, &s->topo, s->mass, s->free_index, nfree};
  return CB_OK;
}

/* The Hessian a role's key names (material.fem_hessian for stretch,
 * material.bend_hessian for bend), into *kind; read only for a model that
 * has two Hessians (a row with term_alt), so the key does not apply to the
 * others. */
static int hessian_choice(const cb_material *mat, const char *given, const char *const *names, const char *keyname,
                          int *kind, const char **key) {
  if (!mat->term_alt) return CB_OK;
  const char *h = given ? given : names[0];
  for (int k = 0; names[k]; k++)
    if (strcmp(h, names[k]) == 0) {
      *kind = k;
      return CB_OK;
    }
  return at_key(cb_fail("%s: unknown Hessian '%s' (%s or %s)", keyname, h, names[0], names[1]), key, keyname);
}

/* A contact error names its key first ("contact.thickness: ..."): that key. */
static int contact_error(int st, const char **key) {
  static const char *const keys[] = {"contact.thickness", "contact.friction", "contact.stiffness",
                                     "contact.kappa",     "contact.epsv",     "contact.bridson_iters"};
  if (st == CB_OK || !key) return st;
  *key = "contact.method";
  for (size_t k = 0; k < sizeof keys / sizeof keys[0]; k++)
    if (strncmp(cb_error_message(), keys[k], strlen(keys[k])) == 0) *key = keys[k];
  return st;
}

/* The contact response's term (contact.method), if it has one. */
static int contact_term(const cb_scene_def *d, cb_scene *s, cb_term **term, int *nterms, const char **key) {
  const char *name = d->contact ? d->contact : "none";
  const cb_contact_type *ct = cb_contact_type_find(name);
  if (!ct) return contact_error(cb_fail("contact.method: unknown response '%s'", name), key);
  if (!ct->term_alloc) return CB_OK;
  int st = contact_error(ct->term_alloc(&s->model, &d->contact_params, term), key);
  if (st == CB_OK && *term) (*nterms)++;
  return st;
}

const cb_term *cb_scene_contact_term(const cb_scene *s) {
  for (int k = 0; k < s->sys.nterms; k++)
    if (cb_contact_term_is(s->sys.terms[k])) return s->sys.terms[k];
  return NULL;
}

/* After the responses: the contact term meets the obstacle mesh (collider.type = mesh), and the start state must
 * give it a finite energy (IPC cannot start from touching or intersecting primitives). */
static int build_contact(cb_scene *s, const char **key) {
  cb_term *t = (cb_term *)cb_scene_contact_term(s);
  if (!t) return CB_OK;
  int st = contact_error(cb_contact_term_set_obstacle(t, cb_scene_obstacle(s)), key);
  if (st) return st;
  long nx = 0;
  if (t->type->max_step && (st = cb_contact_term_intersections(t, s->x0, &nx))) return contact_error(st, key);
  if (nx > 0)
    return contact_error(cb_fail("contact.method: %s: the start state intersects (%ld triangle pairs, cloth with "
                                 "itself or with the obstacle): the barrier cannot start from it",
                                 t->type->name, nx),
                         key);
  double E = t->type->energy(t, s->x0, NULL);
  if (!isfinite(E))
    return contact_error(cb_fail("contact.method: %s: the start state has primitives at distance 0 (touching or "
                                 "intersecting, smallest distance %g m): the response cannot start from it",
                                 t->type->name, cb_contact_term_stats(t)->min_dist),
                         key);
  return CB_OK;
}

/* The terms (the stretch material, the bend material, the collider's term,
 * gravity) and the system over them. */
static int build_terms(const cb_scene_def *d, cb_scene *s, const cb_collider *collider, const char **key) {
  memcpy(s->gravity, d->gravity, sizeof s->gravity);
  cb_material_params mp = cb_material_params_default();
  mp.buckling_kb = d->buckling_kb;
  int st = cb_definiteness_from_name(d->definiteness, &mp.definiteness);
  if (st) return st;
  cb_term *terms[CB_MAX_TERMS];
  int nterms = 0, kind = 0;
  const char *stretch = d->stretch ? d->stretch : "spring", *mkey = NULL;
  const cb_material *mat = cb_material_find(CB_MATERIAL_STRETCH, stretch);
  if (!mat)
    return at_key(cb_fail("material.stretch: unknown model '%s' (spring or fem)", stretch), key, "material.stretch");
  st = hessian_choice(mat, d->fem_hessian, cb_fem_hessian_names, "material.fem_hessian", &kind, key);
  if (st) return st;
  mp.k = d->stretch_k;
  mp.fem_hessian = (cb_fem_hessian)kind;
  st = cb_material_term_alloc(mat, &s->model, &mp, &terms[nterms], &mkey);
  if (st) return mkey ? at_key(st, key, mkey) : st;
  if (terms[nterms]) nterms++;
  mat = cb_material_find(CB_MATERIAL_BEND, d->bend);
  if (!mat)
    st = at_key(labelled(cb_fail("unknown bending model '%s'", d->bend), "material.bend"), key, "material.bend");
  mp.k = d->bend_k;
  kind = 0;
  if (st == CB_OK &&
      (st = hessian_choice(mat, d->bend_hessian, cb_bend_hessian_names, "material.bend_hessian", &kind, key)))
    mat = NULL; /* an error of its own key */
  mp.bend_hessian = (cb_bend_hessian)kind;
  if (st == CB_OK) st = cb_material_term_alloc(mat, &s->model, &mp, &terms[nterms], &mkey);
  if (st == CB_OK && terms[nterms]) nterms++;
  else if (st && mkey) st = at_key(st, key, mkey);
  else if (st && mat) st = at_key(labelled(st, "material.bend"), key, "material.bend");
  if (st == CB_OK && collider->term_alloc) {
    st = collider_error(collider->term_alloc(&s->model, &d->sphere, &terms[nterms]), key);
    if (st == CB_OK) nterms++;
  }
  if (st == CB_OK) st = contact_term(d, s, &terms[nterms], &nterms, key);
  if (st == CB_OK && (d->gravity[0] != 0 || d->gravity[1] != 0 || d->gravity[2] != 0)) {
    st = cb_gravity_term_alloc(&s->model, d->gravity, &terms[nterms]);
    if (st == CB_OK) nterms++;
  }
  if (st == CB_OK) return cb_system_init(&s->sys, &s->model, terms, nterms);
  for (int k = 0; k < nterms; k++) cb_term_free(terms[k]);
  return st;
}

/* The start state x0, v0 and the divergence scale; every derived quantity finite. */
static int build_start(const cb_scene_def *d, cb_scene *s, const char **key) {
  int nv = s->mesh.nv;
  /* x0: rest positions scaled about their centroid; v0 = 0 */
  double c[3] = {0, 0, 0};
  for (int i = 0; i < nv; i++)
    for (int a = 0; a < 3; a++) c[a] += s->mesh.x[3 * i + a] / nv;
  for (int i = 0; i < 3 * nv; i++) s->x0[i] = c[i % 3] + d->initial_scale * (s->mesh.x[i] - c[i % 3]);
  /* driven pins: v_i = -sign((p_i - pc).sq) sq, pc = centroid of the pins' initial positions */
  const double *sq = d->pin_squeeze;
  if (s->npinned > 0 && (sq[0] != 0 || sq[1] != 0 || sq[2] != 0)) {
    double pc[3] = {0, 0, 0};
    for (int k = 0; k < s->npinned; k++)
      for (int a = 0; a < 3; a++) pc[a] += s->x0[3 * s->pinned[k] + a] / s->npinned;
    for (int k = 0; k < s->npinned; k++) {
      const double *p = s->x0 + 3 * s->pinned[k];
      double side = (p[0] - pc[0]) * sq[0] + (p[1] - pc[1]) * sq[1] + (p[2] - pc[2]) * sq[2];
      double sg = side > 0 ? -1.0 : side < 0 ? 1.0 : 0.0;
      for (int a = 0; a < 3; a++) s->v0[3 * s->pinned[k] + a] = sg * sq[a];
    }
  }
  /* the divergence scale, less the kinetic energy (cb_run adds it):
   * S = elastic(x0) + (sum m_i) |g| D max(1, initial_scale) + 1e-12 J, D the rest bounding-box diagonal.
   * lib/instruments/stability.c's energy scale is a different one, of a perturbed start state. */
  s->energy_scale =
      cb_system_elastic_energy(&s->sys, s->x0) +
      cb_scene_total_mass(s) * cb_v3_norm(d->gravity) * cb_mesh_bbox_diagonal(&s->mesh) * fmax(1.0, d->initial_scale) +
      1e-12;
  return check_finite(s, d, key);
}

/* Appends a response of type t to s's stage and initialises it with params
 * (seeing the responses built so far); an error of its init goes through
 * `error` (NULL: as it is). A response whose state was allocated is counted,
 * so cb_scene_free releases it even if its init failed. */
static int add_response(cb_scene *s, const cb_response_type *t, const void *params,
                        int (*error)(int st, const char **key), const char **key) {
  cb_response *r = &s->responses[s->nresponses];
  int st = cb_response_alloc(r, t);
  if (st) return st;
  s->nresponses++;
  cb_response_view view = response_view(s);
  st = t->init ? t->init(r, &view, params) : CB_OK;
  return error ? error(st, key) : st;
}

/* The post-step stage: the definition's own responses first, then the
 * collider's, then the contact response's. */
static int build_responses(const cb_scene_def *d, cb_scene *s, const cb_collider *collider, const char **key) {
  for (int k = 0; k < d->nresponses; k++) {
    int st = add_response(s, d->responses[k].type, d->responses[k].params, NULL, key);
    if (st) return st;
  }
  if (collider->response) {
    int st = add_response(s, collider->response, collider->params(&d->sphere, &d->obstacle), collider_error, key);
    if (st) return st;
  }
  /* the contact response's (contact.method = bridson), last: it sees the collider's obstacle */
  const cb_contact_type *ct = cb_contact_type_find(d->contact ? d->contact : "none");
  if (!ct || !ct->response) return CB_OK;
  int st = contact_error(cb_contact_params_check(ct->name, &d->contact_params), key);
  if (st) return st;
  return add_response(s, ct->response, &d->contact_params, contact_error, key);
}

int cb_scene_build(const cb_scene_def *d, cb_scene **out, const char **key) {
  *out = NULL;
  if (key) *key = NULL;
  const cb_collider *collider = NULL;
  int st = check_def(d, &collider, key);
  if (st) return st;
  cb_scene *s = cb_calloc(1, sizeof *s);
  if (!s) return CB_ENOMEM;
  s->def = *d;
  s->def.mesh_file = s->def.bend = s->def.bend_hessian = s->def.definiteness = s->def.pins = s->def.collider =
      s->def.contact = NULL;
  s->def.obstacle.file = NULL;
  for (int k = 0; k < d->nresponses; k++) s->def.responses[k].params = NULL;
  s->diverge_ratio = d->diverge_ratio;
  st = build_geometry(d, s, key);
  if (st == CB_OK) st = build_masses(d, s, key);
  if (st == CB_OK) st = build_free(d, s, key);
  if (st == CB_OK) st = build_terms(d, s, collider, key);
  if (st == CB_OK) st = build_start(d, s, key);
  if (st == CB_OK) st = build_responses(d, s, collider, key);
  if (st == CB_OK) st = build_contact(s, key);
  if (st) {
    cb_scene_free(s);
    return st;
  }
  *out = s;
  return CB_OK;
}
