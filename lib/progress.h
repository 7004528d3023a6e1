/*
 * progress.h - how long-running library calls report progress without
 * printing: the caller passes a callback that the library calls now and then
 * with the fraction done in [0,1] and a short phase name. NULL means none.
 * Also the clock their statistics are timed with.
 */
#ifndef VDT_PROGRESS_H
#define VDT_PROGRESS_H

#include <time.h>

struct vdt_progress {
	void (*fn)(void *ctx, const char *phase, double fraction);
	void *ctx;
};

static inline void
vdt_progress_report(const struct vdt_progress *p, const char *phase, double f)
{
	if (p != NULL && p->fn != NULL)
		p->fn(p->ctx, phase, f);
}

/* Seconds since an arbitrary start, monotonic: for the times statistics report. */
static inline double
vdt_seconds(void)
{
	struct timespec ts;

	clock_gettime(CLOCK_MONOTONIC, &ts);
	return (double)ts.tv_sec + (double)ts.tv_nsec * 1e-9;
}

#endif
