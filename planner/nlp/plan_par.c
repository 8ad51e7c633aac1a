/* A second thread for the path transcription's evaluations (transcribe/path_*.c): the rows, their
 * Jacobian and the Lagrangian's Hessian split in two fixed parts by knot, part 1 on a worker
 * thread while the caller computes part 0. The parts are the same with one thread (both run
 * in turn by the caller), so a plan does not depend on the thread count.
 *
 * The worker waits for its next part checking for it (yielding the processor between checks)
 * for a few milliseconds, then blocked on a condition variable; the caller waits for the
 * worker's part spinning (the two parts take about as long). */
#include "plan_impl.h"
#include "par_impl.h"

#include <pthread.h>
#include <sched.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <unistd.h>

struct ea__par {
  pthread_t th;
  pthread_mutex_t mu;
  pthread_cond_t cv;
  atomic_ulong go;   /* parts posted (the worker runs one per increment) */
  atomic_ulong done; /* parts the worker finished */
  atomic_int quit;
  void (*fn)(void *ctx, int part);
  void *ctx;
  int busy; /* a run is on (the caller's alone) */
};

/* Spins of a wait before the worker yields between its checks or the caller starts to yield,
 * and how long the worker keeps checking before it blocks: an iteration's callbacks come back
 * after the factorization of its KKT system, sooner than a blocked worker wakes. */
#define EA__PAR_SPIN 20000
#define EA__PAR_WAIT_S 5e-3

static void *ea__par_main(void *arg) {
  ea__par_t *p = arg;
  unsigned long seen = 0;
  for (;;) {
    int spin = 0;
    double t0 = -1.0;
    while (atomic_load_explicit(&p->go, memory_order_acquire) == seen &&
           !atomic_load_explicit(&p->quit, memory_order_acquire)) {
      if (++spin < EA__PAR_SPIN) continue;
      spin = 0;
      const double t = ea__mono_s();
      if (t0 < 0) t0 = t;
      if (t - t0 > EA__PAR_WAIT_S) break;
      sched_yield();
    }
    if (atomic_load_explicit(&p->go, memory_order_acquire) == seen) {
      pthread_mutex_lock(&p->mu);
      while (atomic_load_explicit(&p->go, memory_order_acquire) == seen &&
             !atomic_load_explicit(&p->quit, memory_order_acquire))
        pthread_cond_wait(&p->cv, &p->mu);
      pthread_mutex_unlock(&p->mu);
    }
    if (atomic_load_explicit(&p->quit, memory_order_acquire)) break;
    seen = atomic_load_explicit(&p->go, memory_order_acquire);
    p->fn(p->ctx, 1);
    atomic_store_explicit(&p->done, seen, memory_order_release);
  }
  return NULL;
}

ea__par_t *ea__par_new(void) {
  ea__par_t *p = calloc(1, sizeof *p);
  if (!p) return NULL;
  atomic_init(&p->go, 0);
  atomic_init(&p->done, 0);
  atomic_init(&p->quit, 0);
  if (pthread_mutex_init(&p->mu, NULL)) {
    free(p);
    return NULL;
  }
  if (pthread_cond_init(&p->cv, NULL)) {
    pthread_mutex_destroy(&p->mu);
    free(p);
    return NULL;
  }
  if (pthread_create(&p->th, NULL, ea__par_main, p)) {
    pthread_cond_destroy(&p->cv);
    pthread_mutex_destroy(&p->mu);
    free(p);
    return NULL;
  }
  return p;
}

void ea__par_free(ea__par_t *p) {
  if (!p) return;
  pthread_mutex_lock(&p->mu);
  atomic_store_explicit(&p->quit, 1, memory_order_release);
  pthread_cond_signal(&p->cv);
  pthread_mutex_unlock(&p->mu);
  pthread_join(p->th, NULL);
  pthread_cond_destroy(&p->cv);
  pthread_mutex_destroy(&p->mu);
  free(p);
}

void ea__par_run(ea__par_t *p, void (*fn)(void *ctx, int part), void *ctx) {
  /* both parts here without a worker, and for a run from within a run's part (the worker is
   * busy with the outer part 1, or this is the worker) */
  if (!p || p->busy || pthread_equal(pthread_self(), p->th)) {
    fn(ctx, 0);
    fn(ctx, 1);
    return;
  }
  p->busy = 1;
  p->fn = fn;
  p->ctx = ctx;
  pthread_mutex_lock(&p->mu);
  const unsigned long want = atomic_fetch_add_explicit(&p->go, 1, memory_order_acq_rel) + 1;
  pthread_cond_signal(&p->cv);
  pthread_mutex_unlock(&p->mu);
  fn(ctx, 0);
  for (int spin = 0; atomic_load_explicit(&p->done, memory_order_acquire) != want;)
    if (++spin > EA__PAR_SPIN) sched_yield();
  p->busy = 0;
}

int ea__par_cpus(void) {
  const long n = sysconf(_SC_NPROCESSORS_ONLN);
  return n > 0 ? (int)n : 1;
}
