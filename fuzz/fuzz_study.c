/* libFuzzer target for the study spec loader (problems/study_spec.c): any
 * bytes give a checked study (n_cases >= 1, a CSV header that fits) or an
 * error status with a message; never a crash, leak or undefined behaviour.
 * The built-in arm is used; an arm_file key is read relative to the
 * current folder. Corpus: fuzz/corpus/study. */
#include "ea_problems.h"

#include <stddef.h>
#include <stdint.h>
#include <string.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
  ea_study_t s;
  ea_error_t err = {0};
  const ea_status_t st =
      ea_study_load_string("fuzz.yaml", (const char *)data, size, NULL, &s, &err);
  if (st != EA_OK) {
    if (err.msg[0] == '\0') __builtin_trap();
    return 0;
  }
  if (s.n_cases < 1) __builtin_trap();
  char hdr[4096];
  const size_t n = ea_study_csv_header(&s, hdr, sizeof hdr);
  if (n == 0 || n >= sizeof hdr || strncmp(hdr, "case_id,", 8)) __builtin_trap();
  ea_study_free(&s);
  return 0;
}
