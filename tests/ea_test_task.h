/* Test helper: load an example task (problems/examples/NAME below the source folder). */
#ifndef EA_TEST_TASK_H
#define EA_TEST_TASK_H

#include "ea_problems.h"

#include <stdio.h>

/* 0 on success; else prints the loader's message and returns 1. */
static inline int ea_test_load_example(const char *src, const char *name, ea_task_t *t) {
  char path[1200];
  ea_error_t e = {0};
  snprintf(path, sizeof path, "%s/problems/examples/%s", src, name);
  const ea_status_t st = ea_task_load(path, NULL, t, &e);
  if (st) printf("load %s: %s\n", path, e.msg);
  return st != EA_OK;
}

#endif
