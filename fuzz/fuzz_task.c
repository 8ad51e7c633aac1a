/* libFuzzer target for the task loader: any bytes must give EA_OK or an
 * error status with a message, never a crash, leak or undefined behaviour.
 * Build: cmake -DEA_FUZZ=ON -DCMAKE_C_COMPILER=clang; run:
 * build-fuzz/fuzz_task -max_total_time=60 build-fuzz/corpus-fuzz_task fuzz/corpus/task
 * (seeds: the example tasks without arm_file, and near misses). */
#include "ea_problems.h"

#include <stddef.h>
#include <stdint.h>
#include <string.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
  ea_task_t task;
  ea_error_t err;
  /* No arm_file from the input may be read: the built-in arm is used, and
   * an arm_file key pointing anywhere just fails with EA_ERR_IO. */
  const ea_status_t st =
      ea_task_load_string("fuzz.yaml", (const char *)data, size, NULL, &task, &err);
  if (st != EA_OK && err.msg[0] == '\0') __builtin_trap();
  return 0;
}
