/*
 * imageio.c - 8-bit images in and out through vdt-image.so (imagemod.h),
 * loaded at the first image: the tools that never touch one, and those
 * runs of vdt-render and vdt-silhouette that do not, never pay for
 * OpenImageIO. Output is atomic, as for meshes (vdt_output_open): written
 * to a hidden temporary file beside the target, .NAME.XXXXXX from mkstemp
 * with the target's permissions, and renamed over the target on success;
 * through a symbolic link to what it names, and in place to a device or
 * FIFO (vdt_output_target). The writer is picked by the target's
 * extension, so the temporary name needs none; standard output, and a
 * device or FIFO whose name has none, get PNG.
 */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <unistd.h>

#include "imagemod.h"
#include "meshio.h"
#include "module.h"

static struct {
	vdt_img_writer_fn *writer;
	vdt_img_encode_fn *encode;
	vdt_img_write_file_fn *write_file;
	vdt_img_read_fn *read;
} fn;

/*
 * Address space the module takes as it loads. OpenImageIO's static
 * initialisers throw when an address-space limit (ulimit -v) leaves less,
 * and the process aborts inside dlopen (measured on vdt-render, which
 * has 31 MB mapped by then: limits of 400-460 MB crashed, from 465 MB it
 * worked, so about 425 MB of room); with a margin, such a limit is
 * refused before dlopen instead. (What an image then takes fails as any
 * allocation does, cleanly.)
 */
#define MODULE_ROOM_MB 448

/* Whether an address-space limit leaves room to load the module; else
 * the reason, into why. */
static int
room_to_load(char *why, size_t n)
{
	struct rlimit rl;
	unsigned long pages = 0;
	FILE *f;

	if (getrlimit(RLIMIT_AS, &rl) != 0 || rl.rlim_cur == RLIM_INFINITY)
		return 1;
	if ((f = fopen("/proc/self/statm", "r")) != NULL) {
		if (fscanf(f, "%lu", &pages) != 1)
			pages = 0;
		fclose(f);
	}
	unsigned long long used = (unsigned long long)pages * (unsigned long long)sysconf(_SC_PAGESIZE);
	unsigned long long limit = (unsigned long long)rl.rlim_cur;
	if (limit > used && (limit - used) >> 20 >= MODULE_ROOM_MB)
		return 1;
	snprintf(why, n, "cannot load the image module %s: the address-space limit (ulimit -v) "
	         "leaves %llu MB, and it takes about %d", VDT_IMAGE_MODULE,
	         limit > used ? (limit - used) >> 20 : 0, MODULE_ROOM_MB);
	return 0;
}

static const char *const names[] = {VDT_IMG_WRITER, VDT_IMG_ENCODE, VDT_IMG_WRITE_FILE,
                                    VDT_IMG_READ};
static void **const fns[] = {(void **)&fn.writer, (void **)&fn.encode, (void **)&fn.write_file,
                             (void **)&fn.read};
static struct vdt_module mod = {.file = VDT_IMAGE_MODULE, .what = "image",
                                .abi_name = VDT_IMG_ABI_FN, .abi = VDT_IMG_ABI,
                                .names = names, .fns = fns, .n = 4, .room = room_to_load};

static int
from_module(int code, const char *msg, struct vdt_err *err)
{
	switch (code) {
	case VDT_IMG_OK: return 0;
	case VDT_IMG_NO_WRITER:
	case VDT_IMG_REFUSED: return vdt_err_set(err, VDT_EINVAL, "%s", msg);
	case VDT_IMG_BAD: return vdt_err_set(err, VDT_EFORMAT, "%s", msg);
	case VDT_IMG_NOMEM: return vdt_err_set(err, VDT_ENOMEM, "out of memory");
	default: return vdt_err_set(err, VDT_EIO, "%s", msg[0] ? msg : "cannot use the image");
	}
}

/*
 * The name a writer is picked by (the module loaded): path's own
 * extension, or PNG, which is encoded in memory, for standard output
 * ("-") and for a device, FIFO or socket whose name has no extension a
 * writer knows (/dev/null, /dev/stdout on a pipe): written in place,
 * its name is no file type to keep. A regular file, or a name with
 * nothing there yet, keeps its own: an unknown extension stays an error
 * there, not a PNG under a name that says otherwise.
 */
static const char *
writer_name(const char *path)
{
	char msg[512], *target;
	int special = 0;

	if (strcmp(path, "-") == 0)
		return "-.png";
	/* (and /dev/stdout to a regular file: written in place, as "-") */
	free(target = vdt_output_target(path, &special));
	if (target != NULL && special &&
	    fn.writer(path, 0, 0, 0, msg, sizeof(msg)) == VDT_IMG_NO_WRITER)
		return "-.png";
	return path;
}

/* Bytes of an image are no more for a terminal than a binary mesh is. */
static int
refuse_terminal(const char *path, struct vdt_err *err)
{
	if (strcmp(path, "-") == 0 && isatty(STDOUT_FILENO))
		return vdt_err_set(err, VDT_EINVAL, "refusing to write a binary image to a terminal");
	return 0;
}

/*
 * A writer of its own file (SGI here), by name: never "-". It writes the
 * temporary file, which is then renamed over the target, or staged as
 * vdt_output_stage stages (renamed at once, the frames of a run that
 * failed later were taken back, and the user's files they replaced with
 * them).
 */
static int
write_own_file(const char *path, int w, int h, int c, const unsigned char *px,
               struct vdt_written *stage, struct vdt_err *err)
{
	char msg[512] = "", *tmp = NULL;
	int special = 0, rc;
	char *dst = vdt_output_target(path, &special);
	struct stat st;

	if (dst == NULL)
		return vdt_err_set(err, VDT_ENOMEM, "out of memory");
	/* (said now, as vdt_output_open says it, not at the commit) */
	if (!special && stat(dst, &st) == 0 && S_ISDIR(st.st_mode)) {
		free(dst);
		return vdt_err_set(err, VDT_EIO, "%s", strerror(EISDIR));
	}
	if (!special) {
		int fd = vdt_output_temp(dst, &tmp, err);
		if (fd < 0) {
			free(dst);
			return fd;
		}
		close(fd); /* the writer opens it again by name */
	}
	/* (a device or FIFO is written in place: nothing to stage or take back) */
	rc = from_module(fn.write_file(writer_name(path), special ? dst : tmp, w, h, c, px, msg,
	                                sizeof(msg)), msg, err);
	if (rc == 0 && !special && stage != NULL)
		rc = vdt_written_stage(stage, tmp, dst, err);
	else if (rc == 0 && !special && rename(tmp, dst) != 0) {
		int e = errno;
		rc = vdt_err_set(err, VDT_EIO, "cannot rename the temporary file: %s", strerror(e));
	}
	if (rc != 0 && !special)
		remove(tmp);
	/* (gone, renamed or staged by now: its own note goes) */
	if (!special)
		vdt_output_temp_done(tmp);
	free(tmp);
	free(dst);
	return rc;
}

int
vdt_image_writable(const char *path, int width, int height, int channels, struct vdt_err *err)
{
	char msg[512] = "";
	int rc;

	if ((rc = refuse_terminal(path, err)) != 0 || (rc = vdt_module_ready(&mod, err)) != 0)
		return rc;
	return from_module(fn.writer(writer_name(path), width, height, channels, msg, sizeof(msg)),
	                   msg, err);
}

int
vdt_image_write(const char *path, int width, int height, int channels,
                const unsigned char *pixels, struct vdt_err *err)
{
	return vdt_image_write_staged(path, width, height, channels, pixels, NULL, err);
}

int
vdt_image_write_staged(const char *path, int width, int height, int channels,
                       const unsigned char *pixels, struct vdt_written *stage,
                       struct vdt_err *err)
{
	char msg[512] = "";
	unsigned char *bytes = NULL;
	size_t len = 0;
	struct vdt_output o;
	int rc;

	if (width <= 0 || height <= 0 || channels <= 0 || channels > 4)
		return vdt_err_set(err, VDT_EINVAL, "bad image size %dx%d with %d channels", width,
		                   height, channels);
	if ((rc = refuse_terminal(path, err)) != 0 || (rc = vdt_module_ready(&mod, err)) != 0)
		return rc;
	rc = fn.encode(writer_name(path), width, height, channels, pixels, &bytes, &len, msg,
	                sizeof(msg));
	if (rc == VDT_IMG_OWN_FILE)
		return write_own_file(path, width, height, channels, pixels, stage, err);
	if ((rc = from_module(rc, msg, err)) != 0)
		return rc;
	if ((rc = vdt_output_open(&o, path, err)) != 0) {
		free(bytes);
		return rc;
	}
	if (len > 0 && fwrite(bytes, 1, len, o.f) != len) {
		int e = errno;
		free(bytes);
		vdt_output_abort(&o);
		return vdt_err_set(err, VDT_EIO, "write error: %s", strerror(e));
	}
	free(bytes);
	return stage ? vdt_output_stage(&o, stage, err) : vdt_output_commit(&o, err);
}

int
vdt_image_read(const char *path, int *width, int *height, int *channels,
               unsigned char **pixels, struct vdt_err *err)
{
	char msg[512] = "";
	int rc;

	*pixels = NULL;
	if ((rc = vdt_module_ready(&mod, err)) != 0)
		return rc;
	return from_module(fn.read(path, width, height, channels, pixels, msg, sizeof(msg)), msg,
	                   err);
}
