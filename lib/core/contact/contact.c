/* The contact-response registry (contact.h): one X(id) line per response,
 * each defined in its own file lib/core/contact/contact_<name>.c ending with
 * `const cb_contact_type cb_contact_<id> = {...}`. */
#include <clothbench/contact.h>

#include <math.h>
#include <string.h>

#include <clothbench/status.h>

#define CB_CONTACT_REGISTRY(X) \
  X(none)    /* no contact response */ \
  X(penalty) /* contact_penalty.c */ \
  X(ipc)     /* contact_ipc.c */ \
  X(bridson) /* contact_bridson.c */ \
  /* one X(id) line per response, above this line */
#define CB_CONTACT_DECLARE(id) extern const cb_contact_type cb_contact_##id;
#define CB_CONTACT_ENTRY(id) &cb_contact_##id,
#define CB_CONTACT_NAME(id) #id,
CB_CONTACT_REGISTRY(CB_CONTACT_DECLARE)
const cb_contact_type *const cb_contact_types[] = {CB_CONTACT_REGISTRY(CB_CONTACT_ENTRY) NULL};
const char *const cb_contact_names[] = {CB_CONTACT_REGISTRY(CB_CONTACT_NAME) NULL};

/* `none`: no keys, no term. */
const cb_contact_type cb_contact_none = {.name = "none", .keys = NULL, .term_alloc = NULL};

const cb_contact_type *cb_contact_type_find(const char *name) {
  for (int i = 0; name && cb_contact_types[i]; i++)
    if (strcmp(cb_contact_types[i]->name, name) == 0) return cb_contact_types[i];
  return NULL;
}

cb_contact_params cb_contact_params_default(void) {
  return (cb_contact_params){.cookie = CB_PARAMS_COOKIE,
                             .thickness = 1e-3,
                             .friction = 0,
                             .stiffness = 1e4,
                             .kappa = 1e8,
                             .epsv = 1e-3,
                             .bridson_iters = 10};
}

int cb_contact_params_check(const char *name, const cb_contact_params *p) {
  int st = cb_params_check(p->cookie, "contact", "cb_contact_params_default");
  if (st) return st;
  const cb_contact_type *t = cb_contact_type_find(name);
  if (!t) return cb_fail("contact.method: unknown response '%s'", name ? name : "(null)");
  if (!t->term_alloc && !t->response) return CB_OK;
  if (!(p->thickness > 0) || !isfinite(p->thickness))
    return cb_fail("contact.thickness: must be > 0 (m), got %g", p->thickness);
  if (!(p->friction >= 0) || !isfinite(p->friction))
    return cb_fail("contact.friction: must be >= 0, got %g", p->friction);
  if (!(p->epsv > 0) || !isfinite(p->epsv)) return cb_fail("contact.epsv: must be > 0 (m/s), got %g", p->epsv);
  if (p->friction > 0 && !t->friction)
    return cb_fail("contact.friction: %g: contact.method = %s has no friction yet (only 0 is accepted; ipc and bridson "
                   "have it)",
                   p->friction, t->name);
  if (!(p->stiffness > 0) || !isfinite(p->stiffness))
    return cb_fail("contact.stiffness: must be > 0 (N/m), got %g", p->stiffness);
  if (p->bridson_iters < 0) return cb_fail("contact.bridson_iters: must be >= 0, got %d", p->bridson_iters);
  return CB_OK;
}
