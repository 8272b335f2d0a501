/* Config -> core structs (bind.h). Core errors about one field name its key
 * (cb_scene_build's *key); here they get the key's location in front. */
#include "bind.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <clothbench/energy.h>
#include <clothbench/status.h>

/* "config.ini:4: " in front of the current error message, for key. */
static int located(int st, const cb_config *c, const char *key) {
  if (st == CB_OK || !key) return st;
  char w[CB_PATH_LEN + 32], msg[1024];
  snprintf(msg, sizeof msg, "%s", cb_error_message());
  return cb_fail_status(st, "%s: %s", cb_config_where(c, key, w, sizeof w), msg);
}

int cb_scene_def_from_config(const cb_config *c, cb_scene_def *d, char *path, size_t npath) {
  *d = cb_scene_def_default();
  char *obstacle_path = path + npath / 2; /* the second half: collider.file */
  size_t nobstacle = npath - npath / 2;
  npath /= 2;
  d->mesh = strcmp(c->mesh_type, "obj") == 0     ? CB_MESH_OBJ
            : strcmp(c->mesh_type, "chain") == 0 ? CB_MESH_CHAIN
                                                 : CB_MESH_GRID;
  if (d->mesh == CB_MESH_OBJ) {
    cb_config_resolve_path(c, c->mesh_file, path, npath); /* relative to the config file's folder */
    d->mesh_file = path;
  }
  d->grid.n = c->mesh_n;
  d->grid.m = c->mesh_m > 0 ? c->mesh_m : c->mesh_n; /* mesh.m = 0: square */
  d->grid.size[0] = c->mesh_size[0];
  d->grid.size[1] = c->mesh_size[1];
  d->grid.plane = strcmp(c->mesh_plane, "xy") == 0   ? CB_PLANE_XY
                  : strcmp(c->mesh_plane, "yz") == 0 ? CB_PLANE_YZ
                                                     : CB_PLANE_XZ;
  d->grid.diagonal = strcmp(c->mesh_diagonal, "alternating") == 0 ? CB_DIAG_ALTERNATING : CB_DIAG_REGULAR;
  d->density = c->density;
  d->vertex_mass = c->vertex_mass;
  d->stretch = cb_config_choice(c, "material.stretch");
  d->stretch_k = c->stretch_k;
  d->fem_hessian = cb_config_choice(c, "material.fem_hessian");
  d->bend = cb_config_choice(c, "material.bend"); /* the registry's name: it outlives c */
  d->bend_hessian = cb_config_choice(c, "material.bend_hessian");
  d->bend_k = c->bend_k;
  const char *def = cb_config_choice(c, "integrator.definiteness"); /* Newton's policy is also the springs' response */
  if (def) d->definiteness = def;
  d->buckling_kb = c->buckling_kb;
  memcpy(d->gravity, c->gravity, sizeof d->gravity);
  if (c->slope != 0) { /* scene.slope: g turned by theta about z */
    double th = c->slope * 3.14159265358979323846 / 180, cs = cos(th), sn = sin(th);
    d->gravity[0] = c->gravity[0] * cs - c->gravity[1] * sn;
    d->gravity[1] = c->gravity[0] * sn + c->gravity[1] * cs;
  }
  d->pins = c->pins;
  d->initial_scale = c->initial_scale;
  memcpy(d->pin_squeeze, c->pin_squeeze, sizeof d->pin_squeeze);
  d->diverge_ratio = c->diverge_ratio;
  d->collider = cb_config_choice(c, "collider.type");
  memcpy(d->sphere.centre, c->collider_centre, sizeof d->sphere.centre);
  d->sphere.radius = c->collider_radius;
  d->sphere.thickness = c->collider_thickness;
  d->sphere.stiffness = c->collider_stiffness;
  memcpy(d->sphere.velocity, c->collider_velocity, sizeof d->sphere.velocity);
  if (!strcmp(d->collider, "mesh")) {
    cb_config_resolve_path(c, c->collider_file, obstacle_path, nobstacle); /* relative to the config's folder */
    d->obstacle.file = c->collider_file[0] ? obstacle_path : NULL;
  }
  memcpy(d->obstacle.centre, c->collider_centre, sizeof d->obstacle.centre);
  memcpy(d->obstacle.axis, c->collider_axis, sizeof d->obstacle.axis);
  d->obstacle.omega = c->collider_angular_speed;
  memcpy(d->obstacle.velocity, c->collider_velocity, sizeof d->obstacle.velocity);
  d->nresponses = 0; /* the collider's `project` response is added by the scene */
  d->contact = cb_config_choice(c, "contact.method");
  if (!d->contact) d->contact = "none";
  return cb_contact_params_from_config(c, &d->contact_params);
}

int cb_contact_params_from_config(const cb_config *c, cb_contact_params *p) {
  *p = cb_contact_params_default();
  for (int t = 0; cb_contact_types[t]; t++)
    for (const cb_param_key *k = cb_contact_types[t]->keys; k && k->name; k++) {
      char key[CB_NAME_LEN + 16];
      snprintf(key, sizeof key, "contact.%s", k->name);
      double v;
      if (cb_config_type_value(c, key, &v)) return cb_fail("%s: not in the config's key table", key);
      if (k->kind == CB_PARAM_INT) { /* range-checked by the config layer */
        int iv = (int)v;
        memcpy((char *)p + k->offset, &iv, sizeof iv);
        continue;
      }
      if (k->kind != CB_PARAM_DOUBLE) return cb_fail("%s: a contact key must be a number", key);
      memcpy((char *)p + k->offset, &v, sizeof v);
    }
  return CB_OK;
}

int cb_scene_from_config(const cb_config *c, cb_scene **out) {
  *out = NULL;
  int st = cb_config_validate(c);
  if (st) return st;
  cb_scene_def d;
  char path[4 * CB_PATH_LEN];
  st = cb_scene_def_from_config(c, &d, path, sizeof path);
  if (st) return st;
  const char *key = NULL;
  st = cb_scene_build(&d, out, &key);
  return located(st, c, key);
}

int cb_integrator_params_from_config(const cb_config *c, cb_integrator_params *p) {
  *p = cb_integrator_params_default();
  p->dt = c->dt;
  p->damping = c->damping;
  return CB_OK;
}

/* A type's keys (cb_integrator_type.keys) into its parameter struct. */
int cb_integrator_type_params_from_config(const cb_config *c, const cb_integrator_type *t, void *params) {
  if (!t->params_size) return CB_OK;
  if (t->params_default) memcpy(params, t->params_default, t->params_size);
  else memset(params, 0, t->params_size);
  for (const cb_param_key *k = t->keys; k && k->name; k++) {
    char key[CB_NAME_LEN + 16];
    snprintf(key, sizeof key, "integrator.%s", k->name);
    double v;
    if (cb_config_type_value(c, key, &v)) return cb_fail("%s: not in the config's key table", key);
    char *field = (char *)params + k->offset;
    switch (k->kind) {
    case CB_PARAM_DOUBLE:
    case CB_PARAM_DOUBLE_AUTO: memcpy(field, &v, sizeof v); break;
    case CB_PARAM_CHOICE: {
      int i = (int)v, value = k->values ? k->values[i] : i;
      memcpy(field, &value, sizeof value);
      break;
    }
    default: { /* INT, BOOL */
      int i = (int)v;
      memcpy(field, &i, sizeof i);
      break;
    }
    }
  }
  return CB_OK;
}

int cb_newton_params_from_config(const cb_config *c, cb_newton_params *p) {
  return cb_integrator_type_params_from_config(c, cb_integrator_type_find("newton"), p);
}

cb_solver_params cb_solver_params_from_config(const cb_config *c) {
  cb_solver_params p = cb_solver_params_default();
  p.tol = c->solver_tol;
  p.max_iters = c->solver_max_iters;
  p.alpha = c->solver_alpha;
  p.rho = c->solver_rho;
  for (int o = 0; cb_order_name(o); o++)
    if (strcmp(c->solver_ordering, cb_order_name(o)) == 0) p.ordering = o;
  for (int k = 0; k < 3; k++) p.nrelax[k] = (int)c->solver_nrelax[k]; /* integers: checked by the config */
  p.upper = strcmp(c->solver_storage, "upper") == 0;
  p.flush_denormals = strcmp(c->solver_denormals, "flush") == 0;
  snprintf(p.petsc_options, sizeof p.petsc_options, "%s", c->solver_petsc); /* the same size: never cut */
  p.pc_reuse = !strcmp(c->solver_pc_reuse, "step")        ? CB_PC_REUSE_STEP
               : !strcmp(c->solver_pc_reuse, "iteration") ? CB_PC_REUSE_ITERATION
                                                          : CB_PC_REUSE_AUTO;
  p.pc_reuse_steps = c->solver_pc_reuse_steps;
  p.rigid_modes = c->solver_rigid_modes;
  return p;
}

int cb_integrator_from_config(const cb_config *c, cb_scene *s, const cb_integrator_params *p, cb_integrator **out) {
  *out = NULL;
  const cb_integrator_type *t = cb_integrator_type_find(c->method);
  if (!t) return cb_fail("unknown integrator '%s'", c->method);
  cb_integrator_params ip;
  if (p) ip = *p;
  else cb_integrator_params_from_config(c, &ip);
  void *tp = NULL;
  if (t->params_size && !(tp = cb_malloc(1, t->params_size))) return CB_ENOMEM;
  int st = cb_integrator_type_params_from_config(c, t, tp);
  cb_solver_params sp = cb_solver_params_from_config(c);
  if (st == CB_OK) st = cb_integrator_alloc(c->method, s, &ip, tp, c->solver, &sp, out);
  free(tp);
  if (st && st != CB_ENOMEM && s->model.nfree == 0) { /* e.g. Chebyshev's rho estimate: "lanczos: empty operator" */
    char msg[1024];
    snprintf(msg, sizeof msg, "%s", cb_error_message());
    st = cb_fail_status(st,
                        "scene.pins: every vertex is pinned, so nothing moves and there is no system to solve; "
                        "integrator.method = %s with solver.method = %s cannot be set up (%s)",
                        c->method, c->solver, msg);
    return located(st, c, "scene.pins");
  }
  return st;
}
