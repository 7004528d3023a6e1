/*
 * vtk_cluster - bench driver: VTK's vtkQuadricClustering (Debian
 * libvtk9-dev), Lindstrom's OoCS with quadrics, on a mesh read with
 * vdt_read: the peer of vdt-cluster at equal output size.
 *
 *   vtk_cluster -t TRIANGLES IN OUT
 *
 * vtkQuadricClustering takes a grid, not a triangle count: the divisions
 * (proportional to the bounding box, cubic cells) are searched by bisection
 * for the largest output not above TRIANGLES, and only the final run is
 * timed (building the vtkPolyData, reading and writing are not). Prints
 * one line on stdout:
 *
 *   tool=vtk triangles_in=.. triangles_out=.. seconds=.. peak_rss_kb=.. divisions=..
 */
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <sys/resource.h>
#include <unistd.h>

#include <vtkCellArray.h>
#include <vtkIdList.h>
#include <vtkNew.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkQuadricClustering.h>
#include <vtkSmartPointer.h>

extern "C" {
#include "../../lib/io/meshio.h"
#include "../../lib/progress.h"
}

static const char *progname = "vtk_cluster";

#include "driver.h"

/* Cluster with n cells along the longest side; the output and its time. */
static vtkSmartPointer<vtkPolyData>
cluster(vtkPolyData *in, const double ext[3], int n, double *secs)
{
	double longest = std::fmax(ext[0], std::fmax(ext[1], ext[2]));
	int d[3];
	vtkNew<vtkQuadricClustering> q;

	for (int k = 0; k < 3; k++)
		d[k] = std::max(1, (int)std::ceil(n * ext[k] / longest));
	q->SetInputData(in);
	q->SetNumberOfDivisions(d);
	q->AutoAdjustNumberOfDivisionsOff();
	q->UseInputPointsOff();
	q->UseFeatureEdgesOff();
	q->CopyCellDataOff();
	double t0 = vdt_seconds();
	q->Update();
	*secs = vdt_seconds() - t0;
	vtkSmartPointer<vtkPolyData> out = q->GetOutput();
	return out;
}

int
main(int argc, char **argv)
{
	struct vdt_err err = {};
	struct vdt_mesh in = {}, out = {};
	struct vdt_write_opts wo = {};
	struct vdt_bbox box;
	unsigned long target = 0;
	double ext[3], secs = 0;
	int c;

	while ((c = getopt(argc, argv, "t:")) != -1) {
		if (c != 't')
			usage();
		target = std::strtoul(optarg, nullptr, 10);
	}
	if (target == 0 || argc - optind != 2)
		usage();
	if (vdt_read(argv[optind], &in, nullptr, &err) != 0) {
		fprintf(stderr, "%s: cannot read '%s': %s\n", progname, argv[optind], err.msg);
		return 2;
	}
	vdt_mesh_bbox(&in, &box);
	for (int k = 0; k < 3; k++)
		ext[k] = box.max[k] - box.min[k];

	vtkNew<vtkPoints> pts;
	pts->SetDataTypeToFloat();
	pts->SetNumberOfPoints((vtkIdType)in.vertex_count);
	for (size_t v = 0; v < in.vertex_count; v++)
		pts->SetPoint((vtkIdType)v, in.positions[3 * v], in.positions[3 * v + 1],
		              in.positions[3 * v + 2]);
	vtkNew<vtkCellArray> cells;
	cells->AllocateExact((vtkIdType)in.triangle_count, 3 * (vtkIdType)in.triangle_count);
	for (size_t t = 0; t < in.triangle_count; t++) {
		vtkIdType ids[3] = {in.triangles[3 * t], in.triangles[3 * t + 1], in.triangles[3 * t + 2]};
		cells->InsertNextCell(3, ids);
	}
	vtkNew<vtkPolyData> pd;
	pd->SetPoints(pts);
	pd->SetPolys(cells);

	/* The output grows with n: bisect for the largest not above target. */
	int lo = 1, hi = 2;
	while (hi < (1 << 14)) {
		double s;
		if (cluster(pd, ext, hi, &s)->GetNumberOfPolys() > (vtkIdType)target)
			break;
		lo = hi;
		hi *= 2;
	}
	while (hi - lo > 1) {
		int mid = (lo + hi) / 2;
		double s;
		if (cluster(pd, ext, mid, &s)->GetNumberOfPolys() > (vtkIdType)target)
			hi = mid;
		else
			lo = mid;
	}
	vtkSmartPointer<vtkPolyData> res = cluster(pd, ext, lo, &secs);

	vtkIdType nv = res->GetNumberOfPoints(), nt = res->GetNumberOfPolys();
	if (vdt_mesh_alloc(&out, (size_t)nv, (size_t)nt, 0, &err) != 0) {
		fprintf(stderr, "%s: %s\n", progname, err.msg);
		return 1;
	}
	for (vtkIdType v = 0; v < nv; v++) {
		double p[3];
		res->GetPoint(v, p);
		for (int k = 0; k < 3; k++)
			out.positions[3 * v + k] = (float)p[k];
	}
	vtkCellArray *polys = res->GetPolys();
	vtkNew<vtkIdList> ids;
	polys->InitTraversal();
	for (vtkIdType t = 0; polys->GetNextCell(ids); t++)
		for (int k = 0; k < 3; k++)
			out.triangles[3 * t + k] = (uint32_t)ids->GetId(k);
	if (vdt_write(argv[optind + 1], &out, nullptr, &wo, &err) != 0) {
		fprintf(stderr, "%s: cannot write '%s': %s\n", progname, argv[optind + 1], err.msg);
		return 1;
	}
	printf("tool=vtk triangles_in=%zu triangles_out=%zu seconds=%.6f peak_rss_kb=%ld "
	       "divisions=%d\n",
	       in.triangle_count, out.triangle_count, secs, peak_rss_kb(), lo);
	vdt_mesh_free(&in);
	vdt_mesh_free(&out);
	return 0;
}
