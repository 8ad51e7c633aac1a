/**
 * @file ea_status.h
 * @brief Status codes of every elasticarm call and the error context that
 *        carries a message (the lowest layer: model/util/status.c).
 *
 * Every call returns an ::ea_status_t. A call that can say more takes an
 * optional ::ea_error_t and writes it only on failure: on EA_OK the caller's
 * error context is left as it was.
 *
 * Includes ea_version.h (EA_VERSION_STRING, ea_version()).
 */
#ifndef EA_STATUS_H
#define EA_STATUS_H

#include "ea_version.h"

#ifdef __cplusplus
extern "C" {
#endif

/* ------------------------------------------------------------------------ */
/* Status codes and error context                                           */
/* ------------------------------------------------------------------------ */

/** X-macro list of every status: name, message. 0 = OK. "Call was wrong"
 *  codes (bad argument, bad input) are kept apart from "solver did not
 *  converge" and "the answer is physically inadmissible". */
#define EA_STATUS_LIST(X)                                                                          \
  X(EA_OK, "ok")                                                                                   \
  X(EA_ERR_ARG, "invalid argument")                                                                \
  X(EA_ERR_NOMEM, "out of memory")                                                                 \
  X(EA_ERR_IO, "input/output error")                                                               \
  X(EA_ERR_PARSE, "syntax error in input")                                                         \
  X(EA_ERR_INPUT, "invalid value in input")                                                        \
  X(EA_ERR_NOCONV, "solver did not converge")                                                      \
  X(EA_ERR_MAXITER, "iteration limit reached")                                                     \
  X(EA_ERR_SINGULAR, "singular Jacobian")                                                          \
  X(EA_ERR_INTEGRATION, "ODE integration failed")                                                  \
  X(EA_ERR_INADMISSIBLE, "configuration is not admissible")                                        \
  X(EA_ERR_INFEASIBLE, "problem is infeasible")                                                    \
  X(EA_ERR_UNSTABLE, "configuration is unstable")                                                  \
  X(EA_ERR_BACKEND, "numerical backend failed")                                                    \
  X(EA_ERR_NET, "network or device error")                                                         \
  X(EA_ERR_PROTOCOL, "protocol violation")                                                         \
  X(EA_ERR_INTERRUPTED, "interrupted")                                                             \
  X(EA_ERR_NOTIMPL, "not implemented")

#define EA__STATUS_ENUM(name, msg) name,
/** Status of every library call. */
typedef enum ea_status { EA_STATUS_LIST(EA__STATUS_ENUM) EA_STATUS_COUNT } ea_status_t;
#undef EA__STATUS_ENUM

/** Static message for a status (never NULL). */
const char *ea_strerror(ea_status_t status);
/** Symbolic name of a status ("EA_ERR_NOCONV"); never NULL. */
const char *ea_status_name(ea_status_t status);

/** Error context filled by calls that can say more than a status code.
 *  Always optional: pass NULL when not wanted. Written only when a call
 *  fails; on EA_OK it keeps what it held. */
typedef struct ea_error {
  ea_status_t status; /**< on failure: the status the call returned */
  char msg[512];      /**< human-readable, with file:line:column where known */
} ea_error_t;

/** Set err (if not NULL) to status and a printf-style message; returns status.
 *  With EA_OK it leaves err alone (an error context is written only on
 *  failure), so `return ea_error_set(err, st, ...)` is right for any st. */
ea_status_t ea_error_set(ea_error_t *err, ea_status_t status, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 3, 4)))
#endif
    ;

#ifdef __cplusplus
}
#endif
#endif /* EA_STATUS_H */
