#include "scene_decl.h"
#include "bind.h"

#include <stdio.h>
#include <string.h>

#include <clothbench/status.h>

static int named(const cb_scene_decl *d, int st) {
  char msg[1024];
  snprintf(msg, sizeof msg, "%s", cb_error_message());
  return cb_fail_status(st, "scene %s (%s): %s", d->label, d->config ? d->config : "no config", msg);
}

int cb_scene_decl_config(const cb_experiment *e, const cb_scene_decl *d, const char *const *more, cb_config *out) {
  cb_config_defaults(out);
  if (!d->label || !d->config || !d->role) return cb_fail("scene declaration without a label, config or role");
  int st = cb_experiment_config(e, d->config, d->overrides, out);
  for (int i = 0; st == CB_OK && more && more[i]; i++) st = cb_config_set(out, more[i]);
  if (st == CB_OK) st = cb_config_validate(out);
  return st ? named(d, st) : CB_OK;
}

int cb_scene_decl_build(const cb_experiment *e, const cb_scene_decl *d, const char *const *more, cb_config *cfg,
                        cb_scene **out) {
  cb_config own, *c = cfg ? cfg : &own;
  *out = NULL;
  int st = cb_scene_decl_config(e, d, more, c);
  if (st == CB_OK && (st = cb_scene_from_config(c, out))) return named(d, st);
  return st;
}

int cb_scene_decl_is(const cb_scene_decl *d, const char *role) { return d->role && !strcmp(d->role, role); }

const char *cb_scene_decl_override(const cb_scene_decl *d, const char *key) {
  const char *v = NULL;
  size_t n = strlen(key);
  for (int i = 0; i < CB_SCENE_DECL_MAX_SETS && d->overrides[i]; i++) {
    const char *a = d->overrides[i];
    while (*a == ' ') a++;
    if (strncmp(a, key, n)) continue;
    const char *b = a + n;
    while (*b == ' ') b++;
    if (*b != '=') continue;
    for (b++; *b == ' ';) b++;
    v = b;
  }
  return v;
}

long cb_scene_decl_vertices(const cb_config *c) {
  if (!strcmp(c->mesh_type, "grid")) return (long)c->mesh_n * (c->mesh_m > 0 ? c->mesh_m : c->mesh_n);
  if (!strcmp(c->mesh_type, "chain")) return c->mesh_n;
  return 0;
}
