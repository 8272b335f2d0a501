#include <clothbench/scene.h>

#include <ctype.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <clothbench/status.h>
#include <clothbench/vec.h>

static int cmp_int(const void *a, const void *b) {
  int p = *(const int *)a, q = *(const int *)b;
  return (p > q) - (p < q);
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
    list[cnt++] = 0; list[cnt++] = gn - 1; list[cnt++] = (gm - 1) * gn; list[cnt++] = gm * gn - 1;
  } else if (strcmp(spec, "top-corners") == 0) {
    list[cnt++] = (gm - 1) * gn; list[cnt++] = gm * gn - 1;
  } else if (strcmp(spec, "top-edge") == 0) {
    for (int i = 0; i < gn; i++) list[cnt++] = (gm - 1) * gn + i;
  } else if (!named) { /* 0-based indices separated by spaces or commas */
    const char *p = spec;
    while (*p) {
      while (*p == ' ' || *p == '\t' || *p == ',') p++;
      if (!*p) break;
      if (!isdigit((unsigned char)*p)) {
        free(list);
        return cb_fail("scene.pins: '%s' is not a named set (none, corners, top-corners, top-edge) "
                       "or a list of 0-based vertex indices", spec);
      }
      char *end;
      long v = strtol(p, &end, 10);
      if (*end && *end != ' ' && *end != '\t' && *end != ',') {
        free(list);
        return cb_fail("scene.pins: bad vertex index near '%.20s'", p);
      }
      if (v >= m->nv) {
        free(list);
        return cb_fail("scene.pins: vertex %ld out of range (the mesh has %d vertices, 0-based)", v, m->nv);
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
  cb_system_free(&s->sys);
  cb_mesh_free(&s->mesh);
  cb_topology_free(&s->topo);
  free(s->mass); free(s->pinned); free(s->free_index); free(s->free_vertex);
  free(s->x0); free(s->v0);
  free(s);
}

double cb_scene_total_mass(const cb_scene *s) {
  double msum = 0;
  for (int i = 0; i < s->mesh.nv; i++) msum += s->mass[i];
  return msum;
}

double cb_scene_kinetic(const cb_scene *s, const double *v) {
  double K = 0.0;
  for (int i = 0; i < s->mesh.nv; i++)
    K += 0.5 * s->mass[i] * (v[3 * i] * v[3 * i] + v[3 * i + 1] * v[3 * i + 1] + v[3 * i + 2] * v[3 * i + 2]);
  return K;
}

/* Prefixes the current error message with where `key` was set, and returns
 * st: "config.ini:4: mesh: grid needs ...". */
static int at_key(int st, const cb_config *c, const char *key, const char *label) {
  if (st == CB_OK) return st;
  char w[CB_PATH_LEN + 32], msg[1024];
  snprintf(msg, sizeof msg, "%s", cb_error_message());
  return cb_fail_status(st, "%s: %s%s%s", cb_config_where(c, key, w, sizeof w), label, label[0] ? ": " : "", msg);
}

static int build_mesh(const cb_config *c, cb_mesh *mesh) {
  if (strcmp(c->mesh_type, "obj") == 0) {
    char path[2 * CB_PATH_LEN];
    cb_config_resolve_path(c, c->mesh_file, path, sizeof path); /* relative to the config's folder */
    return at_key(cb_mesh_read_obj(path, mesh), c, "mesh.file", "mesh.file");
  }
  cb_plane plane = strcmp(c->mesh_plane, "xy") == 0 ? CB_PLANE_XY : strcmp(c->mesh_plane, "yz") == 0 ? CB_PLANE_YZ : CB_PLANE_XZ;
  if (strcmp(c->mesh_type, "chain") == 0)
    return at_key(cb_mesh_chain(c->mesh_n, c->mesh_size[0], plane, mesh), c, "mesh.n", "mesh");
  cb_grid_params g = cb_grid_params_default();
  g.n = c->mesh_n;
  g.m = c->mesh_m > 0 ? c->mesh_m : c->mesh_n;
  g.size[0] = c->mesh_size[0];
  g.size[1] = c->mesh_size[1];
  g.plane = plane;
  g.diagonal = strcmp(c->mesh_diagonal, "alternating") == 0 ? CB_DIAG_ALTERNATING : CB_DIAG_REGULAR;
  return at_key(cb_mesh_grid(&g, mesh), c, "mesh.n", "mesh");
}

int cb_scene_build(const cb_config *cfg, cb_scene **out) {
  *out = NULL;
  char w[CB_PATH_LEN + 32];
  int st = cb_config_validate(cfg);
  if (st) return st;
  cb_scene *s = cb_calloc(1, sizeof *s);
  if (!s) return CB_ENOMEM;
  s->cfg = *cfg;
  st = build_mesh(cfg, &s->mesh);
  if (st == CB_OK) st = cb_topology_build(&s->mesh, &s->topo);
  if (st == CB_OK && s->topo.nonmanifold > 0 && strcmp(cfg->bend, "none") != 0)
    st = cb_fail("%s: material.bend: the mesh has %d non-manifold edges (shared by more than two triangles); "
                 "bending needs a manifold mesh", cb_config_where(cfg, "material.bend", w, sizeof w), s->topo.nonmanifold);
  int nv = s->mesh.nv;
  if (st == CB_OK) {
    s->mass = cb_calloc((size_t)nv, sizeof(double));
    s->free_index = cb_malloc((size_t)nv, sizeof(int));
    s->free_vertex = cb_malloc((size_t)nv, sizeof(int));
    s->x0 = cb_malloc((size_t)3 * nv, sizeof(double));
    s->v0 = cb_calloc((size_t)3 * nv, sizeof(double));
    if (!s->mass || !s->free_index || !s->free_vertex || !s->x0 || !s->v0) st = CB_ENOMEM;
  }
  /* masses: uniform, or lumped m_i = density * (sum of adjacent rest areas) / 3 */
  if (st == CB_OK) {
    if (cfg->vertex_mass > 0)
      for (int i = 0; i < nv; i++) s->mass[i] = cfg->vertex_mass;
    else
      for (int t = 0; t < s->mesh.nt; t++) {
        double a = cb_mesh_triangle_area(&s->mesh, s->mesh.x, t);
        for (int k = 0; k < 3; k++) s->mass[s->mesh.tri[3 * t + k]] += cfg->density * a / 3.0;
      }
  }
  if (st == CB_OK) {
    st = at_key(cb_pins_resolve(cfg->pins, &s->mesh, &s->pinned, &s->npinned), cfg, "scene.pins", "");
  }
  if (st == CB_OK) {
    int nfree = 0, p = 0;
    for (int i = 0; i < nv; i++) {
      if (p < s->npinned && s->pinned[p] == i) {
        s->free_index[i] = -1;
        p++;
        continue;
      }
      if (!(s->mass[i] > 0)) {
        st = cb_fail("vertex %d has no mass: it belongs to no triangle (remove it, pin it, or set material.vertex_mass; "
                     "chains and line elements always need material.vertex_mass)", i);
        break;
      }
      s->free_vertex[nfree] = i;
      s->free_index[i] = nfree++;
    }
    s->model = (cb_model){&s->mesh, &s->topo, s->mass, s->free_index, nfree};
  }
  /* terms: stretch springs on every edge, optional bending, optional gravity */
  cb_term *terms[CB_MAX_TERMS];
  int nterms = 0;
  if (st == CB_OK) st = cb_spring_term_alloc(&s->model, "stretch", s->topo.ne, s->topo.edge, cfg->stretch_k, &terms[nterms]);
  if (st == CB_OK) nterms++;
  if (st == CB_OK) {
    cb_term *bend = NULL;
    st = cb_bend_term_alloc(cfg->bend, &s->model, cfg->bend_k, &bend);
    if (bend) terms[nterms++] = bend;
  }
  memcpy(s->gravity, cfg->gravity, sizeof s->gravity);
  if (st == CB_OK && (cfg->gravity[0] != 0 || cfg->gravity[1] != 0 || cfg->gravity[2] != 0)) {
    st = cb_gravity_term_alloc(&s->model, cfg->gravity, &terms[nterms]);
    if (st == CB_OK) nterms++;
  }
  /* compressed-spring response of every spring term (Choi-Ko changes the energy) */
  cb_definiteness def = CB_DEF_DROP;
  if (st == CB_OK) st = cb_definiteness_from_name(cfg->definiteness, &def);
  for (int k = 0; st == CB_OK && k < nterms; k++)
    if (terms[k]->type == cb_term_spring) {
      st = cb_spring_term_set_response(terms[k], def, cfg->buckling_kb);
      if (st) {
        char msg[1024];
        snprintf(msg, sizeof msg, "%s", cb_error_message());
        st = cb_fail("%s: material.buckling_kb: %s", cb_config_where(cfg, "material.buckling_kb", w, sizeof w), msg);
      }
    }
  if (st == CB_OK) st = cb_system_init(&s->sys, &s->model, terms, nterms);
  else
    for (int k = 0; k < nterms; k++) cb_term_free(terms[k]);
  if (st == CB_OK) {
    /* x0: rest positions scaled about their centroid; v0 = 0 */
    double c[3] = {0, 0, 0};
    for (int i = 0; i < nv; i++)
      for (int a = 0; a < 3; a++) c[a] += s->mesh.x[3 * i + a] / nv;
    for (int i = 0; i < 3 * nv; i++) s->x0[i] = c[i % 3] + cfg->initial_scale * (s->mesh.x[i] - c[i % 3]);
    /* driven pins: v_i = -sign((p_i - pc).sq) sq, pc = centroid of the pins' initial positions */
    const double *sq = cfg->pin_squeeze;
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
    s->energy_scale = cb_system_elastic_energy(&s->sys, s->x0) +
                      cb_scene_total_mass(s) * cb_v3_norm(cfg->gravity) * cb_mesh_bbox_diagonal(&s->mesh) * fmax(1.0, cfg->initial_scale) +
                      1e-12;
  }
  if (st) {
    cb_scene_free(s);
    return st;
  }
  *out = s;
  return CB_OK;
}
