/* libFuzzer target for the trajectory reader (planner/traj/trajectory.c,
 * ea_traj_read; docs/trajectory-format.md). The input is written to a
 * temporary file, since the reader takes a path. Invariants: an error has a
 * message and leaves no data; a trajectory read has at least 2 samples, all
 * finite, with strictly increasing time, and finite masses >= 0. Corpus: fuzz/corpus/traj (written
 * by `elasticarm plan`). */
#include "ea_traj.h"
#include "fuzz_tmp.h"

#include <math.h>
#include <stddef.h>
#include <stdint.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
  const char *path = ea__fuzz_tmp_write(".csv", data, size, NULL, 0);
  ea_traj_t tr = {0};
  ea_error_t err = {0};
  const ea_status_t st = ea_traj_read(&tr, path, &err);
  if (st != EA_OK) {
    if (err.msg[0] == '\0' || tr.data || tr.n) __builtin_trap();
    return 0;
  }
  if (tr.n < 2 || !tr.data) __builtin_trap();
  if (!(isfinite(tr.payload_kg) && tr.payload_kg >= 0)) __builtin_trap();
  if (!(isfinite(tr.tip_mass_kg) && tr.tip_mass_kg >= 0)) __builtin_trap();
  for (int i = 0; i < tr.n; ++i) {
    for (int c = 0; c < EA_TRAJ_NCOL; ++c)
      if (!isfinite(EA_TRAJ_AT(&tr, i, c))) __builtin_trap();
    if (i && !(EA_TRAJ_AT(&tr, i, EA_TRAJ_t) > EA_TRAJ_AT(&tr, i - 1, EA_TRAJ_t))) __builtin_trap();
  }
  ea_traj_free(&tr);
  return 0;
}
