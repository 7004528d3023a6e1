/*
 * imagemod.h - the face of vdt-image.so, the module that holds
 * OpenImageIO. Its libraries (some 250, with their own) cost a third of a
 * second and ~130 MB of resident memory at start-up, so the tools load it
 * (imageio.c) only when an image is read or written. The module knows
 * nothing of libvdt: bytes in memory and a message out; imageio.c writes
 * them as any other output.
 *
 * Each function returns VDT_IMG_OK or one of the codes below, with a
 * message in msg (cap bytes) on failure.
 */
#ifndef VDT_IMAGEMOD_H
#define VDT_IMAGEMOD_H

#include <stddef.h>

enum {
	VDT_IMG_OK = 0,
	VDT_IMG_NO_WRITER = 1, /* no writer for the name's extension */
	VDT_IMG_OWN_FILE = 2,  /* the writer writes only a file of its own */
	VDT_IMG_FAIL = 3,      /* the message says why */
	VDT_IMG_BAD = 4,       /* not an image we can use (reading) */
	VDT_IMG_NOMEM = 5,
	VDT_IMG_REFUSED = 6, /* the writer takes no image of this size */
};

/* Raised when a function's arguments change: a module of another build
 * is refused, not called (module.h). */
#define VDT_IMG_ABI 2

/* The module's functions, and their names in it. */
typedef int vdt_img_writer_fn(const char *name, int w, int h, int c, char *msg, size_t cap);
typedef int vdt_img_encode_fn(const char *name, int w, int h, int c, const unsigned char *px,
                              unsigned char **out, size_t *len, char *msg, size_t cap);
typedef int vdt_img_write_file_fn(const char *name, const char *file, int w, int h, int c,
                                  const unsigned char *px, char *msg, size_t cap);
typedef int vdt_img_read_fn(const char *path, int *w, int *h, int *c, unsigned char **px,
                            char *msg, size_t cap);

/* int (void): VDT_IMG_ABI. */
#define VDT_IMG_ABI_FN "vdt_img_abi"
/* Whether a writer exists for name (its extension picks it) and, for
 * w > 0, takes a w x h image of c channels (VDT_IMG_REFUSED if not). */
#define VDT_IMG_WRITER "vdt_img_writer"
/* The image encoded in memory (*out malloc'ed), by name's writer; or
 * VDT_IMG_OWN_FILE when it writes only files of its own. */
#define VDT_IMG_ENCODE "vdt_img_encode"
/* The image written to file, by name's writer (for VDT_IMG_OWN_FILE). */
#define VDT_IMG_WRITE_FILE "vdt_img_write_file"
/* An image read whole, as 8-bit (*px malloc'ed). */
#define VDT_IMG_READ "vdt_img_read"

/* The module's file name, found as module.h says. */
#define VDT_IMAGE_MODULE "vdt-image.so"

#endif
