/**
 * @file ea_abi.h
 * @brief The layout of the public structs as the compiler laid them out, for
 *        bindings that load libelasticarm without a compiler (the Python
 *        package, python/, through cffi's ABI mode) (planner/bind/abi.c).
 *
 * A binding that declares a struct by hand checks its declaration against
 * these (python/tests/test_abi.py: every field's offset and every size), so a
 * header that changes without its binding fails a test instead of reading
 * the wrong bytes; for a struct it does not declare (ea_task_t, ea_study_t,
 * ea_refine_info_t) it allocates ea_abi_sizeof() bytes and reads the few fields
 * it needs at ea_abi_offsetof().
 */
#ifndef EA_ABI_H
#define EA_ABI_H

#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

/** sizeof of a public struct named by its typedef ("ea_task_t"); 0 when the
 *  name is not one of those listed in planner/bind/abi.c. */
size_t ea_abi_sizeof(const char *type);
/** offsetof(type, field) of a listed field: field is a member designator as
 *  C writes it ("limits", "dynamics.modes"); (size_t)-1 when not listed. */
size_t ea_abi_offsetof(const char *type, const char *field);

#ifdef __cplusplus
}
#endif
#endif /* EA_ABI_H */
