/* libFuzzer target for the arm file loader (problems/arm_file.c): any bytes
 * give EA_OK with an arm that passes ea_arm_validate, or an error status
 * with a message; never a crash, leak or undefined behaviour.
 * Corpus: fuzz/corpus/arm (data/elasticarm.yaml and near-valid variants). */
#include "ea_problems.h"

#include <stddef.h>
#include <stdint.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
  ea_arm_t arm;
  ea_error_t err = {0};
  const ea_status_t st = ea_arm_load_string("fuzz.yaml", (const char *)data, size, &arm, &err);
  if (st != EA_OK && err.msg[0] == '\0') __builtin_trap();
  if (st == EA_OK && ea_arm_validate(&arm, NULL) != EA_OK) __builtin_trap();
  return 0;
}
