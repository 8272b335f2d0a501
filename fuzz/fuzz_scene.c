/* libFuzzer harness: building a scene on a small mesh. The input is an OBJ
 * file; the scene reads it with bending springs, gravity and a pinned first
 * vertex, then takes one implicit (Newton + CHOLMOD) and one explicit step.
 * Any mesh must give a scene or a message, and a step must give a status,
 * never a crash. Inputs over FUZZ_MAX_VERTICES vertices are skipped so one
 * execution stays fast. */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <clothbench/clothbench.h>

#include "bind.h"
#include "fuzz_input.h"

#define FUZZ_MAX_LINES 200

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
  size_t lines = 0;
  for (size_t i = 0; i < size; i++) lines += data[i] == '\n';
  if (lines > FUZZ_MAX_LINES) return 0;
  const char *path = cb_fuzz_input_file("obj", data, size);
  if (!path) return 0;
  for (int k = 0; k < 2; k++) {
    cb_config c;
    cb_config_defaults(&c);
    char set[CB_PATH_LEN + 32];
    snprintf(set, sizeof set, "mesh.file=%s", path);
    if (cb_config_set(&c, "mesh.type=obj") || cb_config_set(&c, set) || cb_config_set(&c, "material.bend=spring") ||
        cb_config_set(&c, "scene.pins=0") || cb_config_set(&c, k ? "integrator.method=explicit" : "integrator.method=newton"))
      abort(); /* the harness's own keys are valid */
    cb_scene *s = NULL;
    int st = cb_scene_from_config(&c, &s);
    if (st != CB_OK) {
      if (cb_error_message()[0] == '\0') abort();
      return 0;
    }
    cb_integrator *it = NULL;
    if (cb_integrator_from_config(&c, s, NULL, &it) == CB_OK) {
      cb_run r;
      if (cb_run_init(&r, s, it) == CB_OK) {
        int rs = cb_run_step(&r);
        (void)cb_status_name(rs);
        cb_run_free(&r);
      }
      cb_integrator_free(it);
    }
    cb_scene_free(s);
  }
  return 0;
}
