/*
 * span.h - the run of a row of pixels where a test monotone along the row
 * holds, found from a guess by the test itself. The rasterisers
 * (lib/raster.c, lib/silhouette.c) walk each row of a triangle's box only
 * over the run its three edges share, so that a sliver costs the pixels
 * it covers plus the rows it spans rather than its box, while every pixel
 * still gets the test it always had.
 */
#ifndef VDT_SPAN_H
#define VDT_SPAN_H

/* Rows of a box narrower than this many columns are tested whole: finding
 * the ends of the run costs about as much as testing them. */
#define VDT_SPAN_MIN 8

/*
 * Narrow the columns [*lo, *hi] of a row to those where keep(e, x) holds,
 * for a test monotone along the row: with dir > 0 it holds left of some
 * column and nowhere right of it, with dir < 0 the other way round, with
 * dir 0 everywhere or nowhere. guess is a column near that end, any
 * double (truncated, clamped to the row, NaN taken as *lo). keep is
 * called only at columns in [*lo, *hi]: from guess to the end and once
 * past it, so the cost is the distance from guess to the end plus two
 * calls (inline, so that keep is inlined too). An empty run ends with
 * *lo > *hi.
 */
static inline void
vdt_span_clip(int *lo, int *hi, int dir, double guess, int (*keep)(const void *e, int x),
              const void *e)
{
	if (*lo > *hi)
		return;
	if (dir == 0) {
		if (!keep(e, *lo))
			*hi = *lo - 1;
		return;
	}
	int d = dir > 0 ? 1 : -1, *end = d > 0 ? hi : lo, far = *end, near = d > 0 ? *lo : *hi;
	int x = guess >= *hi ? *hi : guess >= *lo ? (int)guess : *lo;
	if (keep(e, x))
		while (x != far && keep(e, x + d))
			x += d;
	else
		do
			x -= d;
		while (x != near - d && !keep(e, x));
	*end = x;
}

#endif
