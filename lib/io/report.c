/*
 * report.c - the report of a measurement: a table, key=value pairs or
 * JSON, the latter two the same sixteen keys in the same order: fourteen
 * numbers, then the two points where the Hausdorff distances are reached.
 */
#include "report.h"

void
vdt_report_write(FILE *f, const struct vdt_measure_result *r, enum vdt_report_format fmt,
                 int one_sided)
{
	static const char *keys[14] = {
		"hausdorff", "hausdorff_pct", "mean", "mean_pct", "rms", "rms_pct",
		"ab_hausdorff", "ab_rms", "ba_hausdorff", "ba_rms", "samples", "flipped",
		"faces", "diag"};
	static const char *names[3] = {"A->B", "B->A", "symmetric"};
	const struct vdt_dist_stats sym = {.max = r->max, .mean = r->mean, .rms = r->rms};
	const struct vdt_dist_stats *rows[3] = {&r->ab, &r->ba, &sym};
	double pct = r->diag > 0 ? 100 / r->diag : 0;
	/* the counts (keys 10 to 12) as the integers they are, not doubles */
	size_t samples = r->ab.vertex_samples + r->ab.face_samples + r->ba.vertex_samples +
	                 r->ba.face_samples;
	size_t counts[3] = {samples, r->normals.flipped, r->normals.faces};
	double v[14] = {r->max,    r->max * pct, r->mean,   r->mean * pct, r->rms, r->rms * pct,
	                r->ab.max, r->ab.rms,    r->ba.max, r->ba.rms,     0,      0,
	                0,         r->diag};

	if (fmt != VDT_REPORT_TEXT) {
		int json = fmt == VDT_REPORT_JSON;
		for (int i = 0; i < 14; i++) {
			fprintf(f, json ? "%s\"%s\": " : "%s%s=",
			        i ? (json ? ", " : " ") : (json ? "{" : ""), keys[i]);
			if (i >= 10 && i <= 12)
				fprintf(f, "%zu", counts[i - 10]);
			else
				fprintf(f, "%.6g", v[i]);
		}
		for (int i = 0; i < 2; i++) {
			const double *p = i ? r->ba.max_at : r->ab.max_at;
			fprintf(f, json ? ", \"%s\": [%.6g, %.6g, %.6g]" : " %s=%.6g,%.6g,%.6g",
			        i ? "ba_hausdorff_at" : "ab_hausdorff_at", p[0], p[1], p[2]);
		}
		fputs(json ? "}\n" : "\n", f);
		return;
	}
	fprintf(f, "%-10s %22s %22s %22s\n", "", "hausdorff", "mean", "rms");
	for (int i = 0; i < (one_sided ? 1 : 3); i++)
		fprintf(f, "%-10s %12.6g (%6.4f%%) %12.6g (%6.4f%%) %12.6g (%6.4f%%)\n", names[i],
		       rows[i]->max, rows[i]->max * pct, rows[i]->mean, rows[i]->mean * pct,
		       rows[i]->rms, rows[i]->rms * pct);
	fprintf(f, "diagonal of A %.6g, %zu samples, %zu of %zu faces of B flipped\n", r->diag,
	        samples, r->normals.flipped, r->normals.faces);
	fprintf(f, "farthest: A->B at (%.6g, %.6g, %.6g)", r->ab.max_at[0], r->ab.max_at[1],
	        r->ab.max_at[2]);
	if (!one_sided)
		fprintf(f, ", B->A at (%.6g, %.6g, %.6g)", r->ba.max_at[0], r->ba.max_at[1],
		        r->ba.max_at[2]);
	fputc('\n', f);
}
