/* libFuzzer harness: the config parser (cb_config_load on a file holding the
 * input, then the cross-key validation and the effective-key writer).
 * Any input must give CB_OK or a message, never a crash, a leak or a hang. */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>

#include <clothbench/status.h>

#include "bind.h"
#include "config.h"
#include "fuzz_input.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
  const char *path = cb_fuzz_input_file("ini", data, size);
  if (!path) return 0;
  cb_config c;
  int st = cb_config_load(path, &c);
  if (st == CB_OK) st = cb_config_validate(&c);
  if (st != CB_OK && cb_error_message()[0] == '\0') abort(); /* every failure says why */
  if (st == CB_OK) {
    FILE *null = fopen("/dev/null", "w");
    if (null) {
      cb_config_write(&c, null, " ");
      fclose(null);
    }
  }
  return 0;
}
