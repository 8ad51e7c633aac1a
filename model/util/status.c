/* Status codes, messages and the error context (see EA_STATUS_LIST). */
#include "ea_status.h"

#include <stdarg.h>
#include <stdio.h>

#define EA__STATUS_MSG(name, msg) msg,
#define EA__STATUS_NAME(name, msg) #name,
static const char *const ea__status_msg[] = {EA_STATUS_LIST(EA__STATUS_MSG)};
static const char *const ea__status_names[] = {EA_STATUS_LIST(EA__STATUS_NAME)};

const char *ea_strerror(ea_status_t status) {
  if ((int)status < 0 || status >= EA_STATUS_COUNT) return "unknown status";
  return ea__status_msg[status];
}

const char *ea_status_name(ea_status_t status) {
  if ((int)status < 0 || status >= EA_STATUS_COUNT) return "EA_UNKNOWN";
  return ea__status_names[status];
}

ea_status_t ea_error_set(ea_error_t *err, ea_status_t status, const char *fmt, ...) {
  if (err && status != EA_OK) { /* written only on failure */
    err->status = status;
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(err->msg, sizeof err->msg, fmt, ap);
    va_end(ap);
  }
  return status;
}
