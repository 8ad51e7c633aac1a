/* Private: the worker thread of the two-part evaluations (plan_par.c). */
#ifndef EA_PAR_IMPL_H
#define EA_PAR_IMPL_H

/** A worker thread for two-part evaluations (plan_par.c). */
typedef struct ea__par ea__par_t;
/** Start the worker (NULL: no thread could be started; ea__par_run then runs both parts). */
ea__par_t *ea__par_new(void);
void ea__par_free(ea__par_t *p);
/** fn(ctx, 1) on the worker while the caller runs fn(ctx, 0); returns when both are done
 *  (p NULL: both on the caller, part 0 first). */
void ea__par_run(ea__par_t *p, void (*fn)(void *ctx, int part), void *ctx);
/** Processors online (>= 1). */
int ea__par_cpus(void);

#endif
