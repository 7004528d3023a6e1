/*
 * test_assimp.c - skinned animations baked into frames (lib/io/assimp.cc),
 * on Valve SMD files written here: a text format whose bones, key poses
 * and bone weights can be set by hand, so that every baked position is
 * known exactly.
 */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include <cmocka.h>

#include "../../lib/io/anim.h"

/*
 * An arm: bone "arm" sits at (1,0,0) on the root and turns by 90 degrees
 * about z from key time 0 to key time 2; at time 1 only the root has a
 * key, so the arm is halfway there (45 degrees, by slerp).
 *
 *        y
 *        |
 *        2          5            triangle A (0,1,2) on the root
 *        | \        | \          triangle B (3,4,5) on the arm
 *        0--1       3--4 .  8    triangle C (6,7,8): 6 half on each
 *                      6--7      bone, 7 and 8 on the arm
 *   ------------------------ x
 *        0  1       1  2  2  3
 *
 * (C is drawn below B: its corners are (2,0,0), (3,0,0) and (2,-1,0).)
 * At time 2 a point p on the arm goes to (1,0,0) + R90 (p - (1,0,0)):
 * (2,0,0) -> (1,1,0), (1,1,0) -> (0,0,0), (3,0,0) -> (1,2,0),
 * (2,-1,0) -> (2,1,0); vertex 6 is the mean of (2,0,0) and (1,1,0).
 */
static const char arm_smd[] =
	"version 1\n"
	"nodes\n"
	"0 \"root\" -1\n"
	"1 \"arm\" 0\n"
	"end\n"
	"skeleton\n"
	"time 0\n"
	"0 0 0 0 0 0 0\n"
	"1 1 0 0 0 0 0\n"
	"time 1\n"
	"0 0 0 0 0 0 0\n"
	"time 2\n"
	"0 0 0 0 0 0 0\n"
	"1 1 0 0 0 0 1.5707963267948966\n"
	"end\n"
	"triangles\n"
	"mat\n"
	"0 0 0 0 0 0 1 0 0\n"
	"0 1 0 0 0 0 1 0 0\n"
	"0 0 1 0 0 0 1 0 0\n"
	"mat\n"
	"1 1 0 0 0 0 1 0 0\n"
	"1 2 0 0 0 0 1 0 0\n"
	"1 1 1 0 0 0 1 0 0\n"
	"mat\n"
	"1 2 0 0 0 0 1 0 0 2 0 0.5 1 0.5\n"
	"1 3 0 0 0 0 1 0 0\n"
	"1 2 -1 0 0 0 1 0 0\n"
	"end\n";

static const float arm_frames[3][9][3] = {
	{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 0, 0}, {2, 0, 0}, {1, 1, 0},
	 {2, 0, 0}, {3, 0, 0}, {2, -1, 0}},
	{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 0, 0}, {1.70710678f, 0.70710678f, 0},
	 {0.29289322f, 0.70710678f, 0}, {1.85355339f, 0.35355339f, 0},
	 {2.41421356f, 1.41421356f, 0}, {2.41421356f, 0, 0}},
	{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 0, 0}, {1, 1, 0}, {0, 0, 0},
	 {1.5f, 0.5f, 0}, {1, 2, 0}, {2, 1, 0}},
};

/* text into a new file named like "/tmp/vdt-assimp-XXXXXX.smd" (or with
 * another suffix); the name */
static char *
write_temp_as(const char *text, const char *suffix)
{
	static char name[64];
	snprintf(name, sizeof(name), "/tmp/vdt-assimp-XXXXXX%s", suffix);
	int fd = mkstemps(name, (int)strlen(suffix));
	assert_true(fd >= 0);
	size_t n = strlen(text);
	assert_int_equal(write(fd, text, n), (ssize_t)n);
	close(fd);
	return name;
}

static char *
write_temp(const char *text)
{
	return write_temp_as(text, ".smd");
}

/* Frame f of fr is want, to float rounding. */
static void
expect_frame(const struct vdt_frames *fr, size_t f, const float want[9][3])
{
	for (size_t v = 0; v < 9; v++)
		for (int k = 0; k < 3; k++) {
			float got = fr->positions[3 * (9 * f + v) + k];
			if (fabsf(got - want[v][k]) > 1e-5f)
				fail_msg("frame %zu vertex %zu axis %d: %g, not %g", f, v, k, got,
				         want[v][k]);
		}
}

static void
arm_bends_at_its_joint(void **state)
{
	(void)state;
	struct vdt_mesh m;
	struct vdt_frames fr;
	struct vdt_err err = {0};
	char *path = write_temp(arm_smd);

	assert_int_equal(vdt_assimp_read(path, NULL, &m, &fr, &err), 0);
	unlink(path);
	assert_int_equal(m.vertex_count, 9);
	assert_int_equal(m.triangle_count, 3);
	for (uint32_t i = 0; i < 9; i++)
		assert_int_equal(m.triangles[i], i);
	assert_int_equal(fr.frame_count, 3);
	assert_int_equal(fr.vertex_count, 9);
	for (size_t f = 0; f < 3; f++)
		expect_frame(&fr, f, arm_frames[f]);
	/* the mesh is frame 0 */
	assert_memory_equal(m.positions, fr.positions, 27 * sizeof(float));
	vdt_mesh_free(&m);
	vdt_frames_free(&fr);
}

/*
 * --fps: frames evenly in time, from the first key to the last. The SMD's
 * rate is 25 ticks a second (one per key time here), so 50 frames a
 * second take a frame every half key: the arm at 0, 22.5, 45, 67.5 and 90
 * degrees, the keys' frames among them.
 */
static void
fps_samples_evenly(void **state)
{
	(void)state;
	struct vdt_bake_opts bo = {NULL, 50};
	struct vdt_mesh m;
	struct vdt_frames fr;
	char *path = write_temp(arm_smd);

	assert_int_equal(vdt_assimp_read(path, &bo, &m, &fr, NULL), 0);
	unlink(path);
	assert_int_equal(fr.frame_count, 5);
	expect_frame(&fr, 2, arm_frames[1]);
	expect_frame(&fr, 4, arm_frames[2]);
	/* vertex 4, (2,0,0) on the arm, at 22.5 degrees about (1,0,0) */
	const float *p = fr.positions + 1 * 27 + 3 * 4;
	assert_true(fabsf(p[0] - 1.92387953f) < 1e-5f && fabsf(p[1] - 0.38268343f) < 1e-5f);
	vdt_mesh_free(&m);
	vdt_frames_free(&fr);
}

/* --animation by number; one not there is named, with those there. */
static void
animation_by_number(void **state)
{
	(void)state;
	struct vdt_bake_opts zero = {"0", 0}, one = {"1", 0}, walk = {"walk", 0};
	struct vdt_mesh m;
	struct vdt_frames fr;
	struct vdt_err err = {0};
	char *path = write_temp(arm_smd);

	assert_int_equal(vdt_assimp_read(path, &zero, &m, &fr, NULL), 0);
	assert_int_equal(fr.frame_count, 3);
	vdt_mesh_free(&m);
	vdt_frames_free(&fr);
	assert_int_equal(vdt_assimp_read(path, &one, &m, &fr, &err), VDT_EINVAL);
	assert_string_equal(err.msg, "has no animation '1' (1: 0 '')");
	assert_int_equal(vdt_assimp_read(path, &walk, &m, &fr, &err), VDT_EINVAL);
	assert_string_equal(err.msg, "has no animation 'walk' (1: 0 '')");
	unlink(path);
}

/* A model with one key pose is one frame. */
static void
one_key_is_one_frame(void **state)
{
	(void)state;
	static const char smd[] = "version 1\nnodes\n0 \"root\" -1\nend\n"
	                          "skeleton\ntime 0\n0 0 0 5 0 0 0\nend\n"
	                          "triangles\nmat\n0 0 0 0 0 0 1 0 0\n0 1 0 0 0 0 1 0 0\n"
	                          "0 0 1 0 0 0 1 0 0\nend\n";
	struct vdt_mesh m;
	struct vdt_frames fr;
	char *path = write_temp(smd);

	assert_int_equal(vdt_assimp_read(path, NULL, &m, &fr, NULL), 0);
	unlink(path);
	assert_int_equal(fr.frame_count, 1);
	assert_int_equal(m.vertex_count, 3);
	assert_true(fabsf(fr.positions[3 * 1 + 0] - 1) < 1e-6f);
	assert_true(fabsf(fr.positions[3 * 2 + 1] - 1) < 1e-6f);
	vdt_mesh_free(&m);
	vdt_frames_free(&fr);
}

static void
expect_error(const char *text, int code, const char *message)
{
	struct vdt_mesh m;
	struct vdt_frames fr;
	struct vdt_err err = {0};
	char *path = write_temp(text);

	assert_int_equal(vdt_assimp_read(path, NULL, &m, &fr, &err), code);
	unlink(path);
	assert_string_equal(err.msg, message);
	assert_null(m.positions);
	assert_null(fr.positions);
}

static void
refuses_what_is_no_animated_mesh(void **state)
{
	(void)state;
	char nan_smd[sizeof(arm_smd) + 8];
	const char *at = strstr(arm_smd, "1 2 0 0 0 0 1 0 0\n1 1 1");

	/* vertex 4 at x = nan */
	assert_non_null(at);
	memcpy(nan_smd, arm_smd, (size_t)(at - arm_smd));
	strcpy(nan_smd + (at - arm_smd), "1 nan");
	strcat(nan_smd, at + 3);
	expect_error(nan_smd, VDT_EINVAL, "frame 0: vertex 4 has a non-finite coordinate");
	/* 10000 frames a second over 5000 ticks at 25 a second: 2 million */
	struct vdt_bake_opts fast = {NULL, 10000};
	struct vdt_mesh m;
	struct vdt_frames fr;
	struct vdt_err err = {0};
	char *path = write_temp("version 1\nnodes\n0 \"root\" -1\nend\nskeleton\ntime 0\n"
	                        "0 0 0 0 0 0 0\ntime 5000\n0 1 0 0 0 0 0\nend\ntriangles\nmat\n"
	                        "0 0 0 0 0 0 1 0 0\n0 1 0 0 0 0 1 0 0\n0 0 1 0 0 0 1 0 0\nend\n");
	assert_int_equal(vdt_assimp_read(path, &fast, &m, &fr, &err), VDT_EINVAL);
	unlink(path);
	assert_string_equal(err.msg, "10000 frames a second of animation '' make 2e+06 frames, "
	                             "more than a million");
	/* a glTF of three points */
	path = write_temp_as("{\"asset\": {\"version\": \"2.0\"}, \"scene\": 0, \"scenes\": [{\"nodes\": [0]}], \"nodes\": [{\"mesh\": 0}], \"meshes\": [{\"primitives\": [{\"attributes\": {\"POSITION\": 0}, \"mode\": 0}]}], \"buffers\": [{\"byteLength\": 36, \"uri\": \"data:application/octet-stream;base64,AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAA\"}], \"bufferViews\": [{\"buffer\": 0, \"byteLength\": 36}], \"accessors\": [{\"bufferView\": 0, \"componentType\": 5126, \"count\": 3, \"type\": \"VEC3\", \"min\": [0, 0, 0], \"max\": [1, 1, 0]}]}", ".gltf");
	assert_int_equal(vdt_assimp_read(path, NULL, &m, &fr, &err), VDT_EINVAL);
	unlink(path);
	assert_string_equal(err.msg, "has no triangles");
	assert_null(m.positions);
	/* a skeleton alone, which Assimp would draw as a mesh of its own */
	expect_error("version 1\nnodes\n0 \"root\" -1\nend\nskeleton\ntime 0\n0 0 0 0 0 0 0\nend\n",
	             VDT_EINVAL, "has no mesh");
}

/*
 * A glTF of one triangle and no animation, (0,0,0) (1,0,0) (0,1,0), with
 * the indices given (an accessor of three uint16) or none (drawn in order).
 */
static char *
triangle_gltf(const char *indices)
{
	static char text[1024];
	snprintf(
	        text, sizeof(text),
	        "{\"asset\": {\"version\": \"2.0\"}, \"scene\": 0, \"scenes\": [{\"nodes\": [0]}], "
	        "\"nodes\": [{\"mesh\": 0}], \"meshes\": [{\"primitives\": [{\"attributes\": "
	        "{\"POSITION\": 0}%s}]}], \"buffers\": [{\"byteLength\": 44, \"uri\": "
	        "\"data:application/octet-stream;base64,"
	        "AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAAAAABAAUAAAA=\"}], "
	        "\"bufferViews\": [{\"buffer\": 0, \"byteLength\": 36}, "
	        "{\"buffer\": 0, \"byteOffset\": 36, \"byteLength\": 6}], "
	        "\"accessors\": [{\"bufferView\": 0, \"componentType\": 5126, \"count\": 3, "
	        "\"type\": \"VEC3\", \"min\": [0, 0, 0], \"max\": [1, 1, 0]}, "
	        "{\"bufferView\": 1, \"componentType\": 5123, \"count\": 3, \"type\": "
	        "\"SCALAR\"}]}",
	        indices ? indices : "");
	return write_temp_as(text, ".gltf");
}

/* A still model is one frame, as posed; an animation asked of it is
 * refused, with "none" for the list. */
static void
still_model_is_one_frame(void **state)
{
	(void)state;
	struct vdt_bake_opts first = {"0", 0};
	struct vdt_mesh m;
	struct vdt_frames fr;
	struct vdt_err err = {0};
	char *path = triangle_gltf(NULL);

	assert_int_equal(vdt_assimp_read(path, NULL, &m, &fr, &err), 0);
	assert_int_equal(fr.frame_count, 1);
	assert_int_equal(m.vertex_count, 3);
	assert_int_equal(m.triangle_count, 1);
	assert_true(fabsf(fr.positions[3 * 1 + 0] - 1) < 1e-6f);
	vdt_mesh_free(&m);
	vdt_frames_free(&fr);
	assert_int_equal(vdt_assimp_read(path, &first, &m, &fr, &err), VDT_EINVAL);
	unlink(path);
	assert_string_equal(err.msg, "has no animation '0' (0: none)");
	assert_null(m.positions);
	assert_null(fr.positions);
}

/* A face's vertex out of range is Assimp's to refuse (here its glTF reader
 * drops the face, then ValidateDataStructure the mesh without faces): a
 * format error, in Assimp's words; the baking checks no index. */
static void
index_out_of_range_is_a_format_error(void **state)
{
	(void)state;
	struct vdt_mesh m;
	struct vdt_frames fr;
	struct vdt_err err = {0};
	char *path = triangle_gltf(", \"indices\": 1");

	assert_int_equal(vdt_assimp_read(path, NULL, &m, &fr, &err), VDT_EFORMAT);
	unlink(path);
	assert_true(err.msg[0] != '\0');
	assert_null(m.positions);
	assert_null(fr.positions);
}

static void
missing_file_is_an_io_error(void **state)
{
	(void)state;
	struct vdt_mesh m;
	struct vdt_frames fr;
	struct vdt_err err = {0};

	assert_int_equal(vdt_assimp_read("/nonexistent/walk.fbx", NULL, &m, &fr, &err), VDT_EIO);
	assert_string_equal(err.msg, "No such file or directory");
}

static void
formats_by_extension(void **state)
{
	(void)state;
	assert_true(vdt_assimp_handles("walk.fbx"));
	assert_true(vdt_assimp_handles("dir.obj/Walk.GLB"));
	assert_true(vdt_assimp_handles("a.x"));
	assert_false(vdt_assimp_handles(".x"));
	assert_false(vdt_assimp_handles("models/.x"));
	assert_true(vdt_assimp_handles("models/walk.tar.X"));
	assert_false(vdt_assimp_handles("bunny.obj"));
	assert_false(vdt_assimp_handles("frames.vdt"));
	assert_false(vdt_assimp_handles("sydney.md2"));
}

int
main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(arm_bends_at_its_joint),
		cmocka_unit_test(fps_samples_evenly),
		cmocka_unit_test(animation_by_number),
		cmocka_unit_test(one_key_is_one_frame),
		cmocka_unit_test(refuses_what_is_no_animated_mesh),
		cmocka_unit_test(still_model_is_one_frame),
		cmocka_unit_test(index_out_of_range_is_a_format_error),
		cmocka_unit_test(missing_file_is_an_io_error),
		cmocka_unit_test(formats_by_extension),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
