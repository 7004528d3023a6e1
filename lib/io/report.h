/*
 * report.h - the report of a measurement (measure.h) as vdt-measure(1)
 * prints it: a table for people, or the same numbers as one line of
 * key=value pairs or one JSON object for scripts. The keys, their order
 * and the number forms are an interface: vdt-measure(1), "Output keys".
 */
#ifndef VDT_REPORT_H
#define VDT_REPORT_H

#include <stdio.h>

#include "../measure.h"

/* The formats, in the order of vdt-measure's -F names. */
enum vdt_report_format {
	VDT_REPORT_TEXT = 0, /* "text": a table of hausdorff, mean, rms per
	                        direction, then a line of totals */
	VDT_REPORT_KV,       /* "kv": key=value pairs on one line */
	VDT_REPORT_JSON,     /* "json": one object on one line */
};

/*
 * Write the report of r to f in format fmt. Distances come with their
 * share of the diagonal of A in percent (0 when the diagonal is 0); counts
 * are written as the integers they are. The table has the row A->B
 * alone when one_sided, else the rows A->B, B->A and symmetric; its last
 * line, and the last two keys, give the samples where the Hausdorff
 * distance of each direction is reached (on A for A->B, on B for B->A). Write
 * errors are left in f's error indicator for the caller's flush or close
 * to report.
 */
void vdt_report_write(FILE *f, const struct vdt_measure_result *r,
                      enum vdt_report_format fmt, int one_sided);

#endif
