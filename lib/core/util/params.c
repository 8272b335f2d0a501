/* The parameter structs' cookie (params.h). */
#include <clothbench/params.h>

#include <clothbench/status.h>

int cb_params_check(int cookie, const char *what, const char *default_fn) {
  if (cookie == CB_PARAMS_COOKIE) return CB_OK;
  return cb_fail("%s: the parameters were not set up by %s() (cookie %#x): start from %s() and change the fields "
                 "you need, so that every field has its default",
                 what, default_fn, (unsigned)cookie, default_fn);
}
