/* The library's version (ea_version.h, generated from project()). */
#include "ea_version.h"

const char *ea_version(void) {
  return EA_VERSION_STRING;
}
