/* libFuzzer harness: building a scene on a small mesh and stepping it. The
 * input is an OBJ file. If its first line is a comment ("#..."), the bytes
 * after the '#' choose the physical keys, one byte each, in this order (a
 * missing byte keeps the default; each is taken modulo its table's size):
 *   0 integrator.method      (every registered integrator)
 *   1 material.bend          (none spring dihedral quadratic)
 *   2 material.stretch       (spring fem)
 *   3 collider.type          (none penalty project; a unit sphere below the mesh)
 *   4 integrator.definiteness (none drop mirror shift choi-ko)
 *   5 scene.pins             (PINS below: indices, none, halfspaces, extremes)
 *   6 material.stretch_k     (EXTREME below)
 *   7 material.bend_k        (EXTREME)
 *   8 integrator.dt          (DTS below)
 *   9 scene.initial_scale    (SCALES below)
 *  10 number of steps, 1 + byte % 3
 *  11 integrator.iters and integrator.substeps, a pair (SWEEPS below: small
 *     ones, and ones the range or the iters x substeps limit refuses; the
 *     latter, 1e8 iterations, only for pbd and xpbd)
 *  12 integrator.rho        (RHOS below; the Chebyshev variants' rho)
 *  13 integrator.pbd_stiffness (STIFF below)
 *  14 integrator.lbfgs_window (WINDOWS below)
 *  15 integrator.lbfgs_line_search (armijo wolfe)
 *  16 integrator.vbd_init   (inertia previous adaptive)
 *  17 integrator.vbd_line_search (0 1)
 * (issue 35: the newer integrators' keys: pbd, xpbd, vbd, lbfgs)
 * so the fuzzer reaches tiny and huge stiffnesses, steps and scales (issue
 * 21: k = 1e-300 hung the eigensolver, which a harness with the default keys
 * could not find). The OBJ reader ignores the comment line. Without it: bend
 * = spring, vertex 0 pinned, one Newton and one explicit step, as before.
 * Any input must give a scene or a message, and a step a status, never a
 * crash or a hang. Inputs over FUZZ_MAX_LINES lines are skipped so one
 * execution stays fast. */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <clothbench/definiteness.h>
#include <clothbench/integrator.h>
#include <clothbench/material.h>
#include <clothbench/run.h>
#include <clothbench/scene.h>
#include <clothbench/status.h>

#include "bind.h"
#include "fuzz_input.h"

#define FUZZ_MAX_LINES 200

static const char *const PINS[] = {"0",
                                   "none",
                                   "0 1",
                                   "0,2",
                                   "halfspace 1 0 0 0",
                                   "halfspace 1e-300 0 0 0",
                                   "halfspace 0 1 0 1e300",
                                   "99999999999999999999",
                                   "corners",
                                   "2147483647"};
static const char *const EXTREME[] = {"0", "1e-300", "1e-200", "1e-12", "1", "100", "8000", "1e6", "1e12", "1e15"};
static const char *const DTS[] = {"1/30", "1e-300", "1e-160", "1e-154", "1e-6", "0.001", "0.1", "1", "1e6"};
static const char *const SCALES[] = {"1", "1e-300", "1e-200", "1e-100", "0.5", "2", "1e6"};
static const char *const SWEEPS[][2] = {{"1", "1"}, {"2", "3"},       {"32", "1"}, {"7", "4"}, {"100000000", "1000000"},
                                        {"0", "1"}, {"3", "1000001"}, {"1", "64"}};
static const char *const RHOS[] = {"0", "0.5", "0.995", "1", "-1", "nan", "1e-300"};
static const char *const STIFF[] = {"1", "0.5", "1e-300", "0", "2"};
static const char *const WINDOWS[] = {"0", "1", "2", "5", "64", "-3"};
static const char *const LBFGS_LS[] = {"armijo", "wolfe"};
static const char *const VBD_INIT[] = {"inertia", "previous", "adaptive"};

#define COUNT(a) (sizeof(a) / sizeof(a)[0])

static int count_names(const char *const *names) {
  int n = 0;
  while (names[n]) n++;
  return n;
}

/* Sets key=value; a value the config refuses must come with a message. 1 if it was set. */
static int set_key(cb_config *c, const char *key, const char *value) {
  char set[256];
  snprintf(set, sizeof set, "%s=%s", key, value);
  if (cb_config_set(c, set) == CB_OK) return 1;
  if (cb_error_message()[0] == '\0') abort();
  return 0;
}

/* Builds the scene and the integrator, takes steps; returns nothing: every
 * outcome is a status or a message. */
static void run_once(cb_config *c, int steps) {
  cb_scene *s = NULL;
  int st = cb_scene_from_config(c, &s);
  if (st != CB_OK) {
    if (cb_error_message()[0] == '\0') abort();
    return;
  }
  cb_integrator *it = NULL;
  if (cb_integrator_from_config(c, s, NULL, &it) == CB_OK) {
    cb_run r;
    if (cb_run_init(&r, s, it) == CB_OK) {
      for (int k = 0; k < steps; k++) {
        int rs = cb_run_step(&r);
        (void)cb_status_name(rs);
        if (cb_status_is_fatal(rs)) break;
      }
      cb_run_free(&r);
    }
    cb_integrator_free(it);
  } else if (cb_error_message()[0] == '\0') abort();
  cb_scene_free(s);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
  size_t lines = 0;
  for (size_t i = 0; i < size; i++) lines += data[i] == '\n';
  if (lines > FUZZ_MAX_LINES) return 0;
  const char *path = cb_fuzz_input_file("obj", data, size);
  if (!path) return 0;
  cb_config c;
  cb_config_defaults(&c);
  char set[CB_PATH_LEN + 32];
  snprintf(set, sizeof set, "mesh.file=%s", path);
  if (cb_config_set(&c, "mesh.type=obj") || cb_config_set(&c, set)) abort(); /* the harness's own keys are valid */
  if (size == 0 || data[0] != '#') { /* the default keys: spring bending, a pinned vertex, Newton then explicit */
    for (int k = 0; k < 2; k++) {
      if (cb_config_set(&c, "material.bend=spring") || cb_config_set(&c, "scene.pins=0") ||
          cb_config_set(&c, k ? "integrator.method=explicit" : "integrator.method=newton"))
        abort();
      run_once(&c, 1);
    }
    return 0;
  }
  /* the selector bytes: the first line after '#' */
  size_t nsel = 0;
  while (1 + nsel < size && data[1 + nsel] != '\n') nsel++;
  const uint8_t *sel = data + 1;
  int nmethods = 0;
  while (cb_integrator_name(nmethods)) nmethods++;
  if (nsel > 0) set_key(&c, "integrator.method", cb_integrator_name(sel[0] % nmethods));
  if (nsel > 1) set_key(&c, "material.bend", cb_bend_names[sel[1] % count_names(cb_bend_names)]);
  if (nsel > 2) set_key(&c, "material.stretch", cb_stretch_names[sel[2] % count_names(cb_stretch_names)]);
  if (nsel > 3) {
    set_key(&c, "collider.type", cb_collider_names[sel[3] % count_names(cb_collider_names)]);
    set_key(&c, "collider.centre", "0.5 0.5 -1.2");
  }
  if (nsel > 4)
    set_key(&c, "integrator.definiteness", cb_definiteness_names[sel[4] % count_names(cb_definiteness_names)]);
  set_key(&c, "scene.pins", nsel > 5 ? PINS[sel[5] % COUNT(PINS)] : "0");
  if (nsel > 6) set_key(&c, "material.stretch_k", EXTREME[sel[6] % COUNT(EXTREME)]);
  if (nsel > 7) set_key(&c, "material.bend_k", EXTREME[sel[7] % COUNT(EXTREME)]);
  if (nsel > 8) set_key(&c, "integrator.dt", DTS[sel[8] % COUNT(DTS)]);
  if (nsel > 9) set_key(&c, "scene.initial_scale", SCALES[sel[9] % COUNT(SCALES)]);
  /* the pair past INT_MAX sweeps is for pbd and xpbd, which refuse it; other
   * methods would run its 1e8 iterations (legal, and no harness input) */
  int big = nsel > 11 && !strcmp(SWEEPS[sel[11] % COUNT(SWEEPS)][0], "100000000");
  if (nsel > 11 && (!big || !strcmp(c.method, "pbd") || !strcmp(c.method, "xpbd"))) {
    set_key(&c, "integrator.iters", SWEEPS[sel[11] % COUNT(SWEEPS)][0]);
    set_key(&c, "integrator.substeps", SWEEPS[sel[11] % COUNT(SWEEPS)][1]);
  }
  if (nsel > 12) set_key(&c, "integrator.rho", RHOS[sel[12] % COUNT(RHOS)]);
  if (nsel > 13) set_key(&c, "integrator.pbd_stiffness", STIFF[sel[13] % COUNT(STIFF)]);
  if (nsel > 14) set_key(&c, "integrator.lbfgs_window", WINDOWS[sel[14] % COUNT(WINDOWS)]);
  if (nsel > 15) set_key(&c, "integrator.lbfgs_line_search", LBFGS_LS[sel[15] % COUNT(LBFGS_LS)]);
  if (nsel > 16) set_key(&c, "integrator.vbd_init", VBD_INIT[sel[16] % COUNT(VBD_INIT)]);
  if (nsel > 17) set_key(&c, "integrator.vbd_line_search", sel[17] % 2 ? "1" : "0");
  run_once(&c, nsel > 10 ? 1 + sel[10] % 3 : 1);
  return 0;
}
