/*
 * err.h - status codes and the error record every fallible call fills.
 *
 * The library never prints and never exits: a fallible function returns 0 or
 * a negative enum vdt_status and, when its last argument is non-NULL, writes
 * the code and a one-line message (no program name, no trailing newline)
 * into a caller-provided struct vdt_err.
 */
#ifndef VDT_ERR_H
#define VDT_ERR_H

enum vdt_status {
	VDT_OK = 0,
	VDT_EIO = -1,       /* cannot open, read or write */
	VDT_EFORMAT = -2,   /* malformed or unsupported content */
	VDT_EVERSION = -3,  /* stream of a newer major version */
	VDT_ECHECKSUM = -4, /* CRC mismatch */
	VDT_ENOMEM = -5,    /* allocation failed */
	VDT_EINVAL = -6,    /* invalid argument or invalid geometry */
	VDT_ELIMIT = -7,    /* a target or bound that cannot be met */
	VDT_ESYSTEM = -8,   /* the system refused what the work needs (temporary
	                       space, a mapping): not the input's fault */
};

#define VDT_ERR_MSG_MAX 512

struct vdt_err {
	int code;
	char msg[VDT_ERR_MSG_MAX];
};

/*
 * Record code and a printf-style message in err (if err is non-NULL) and
 * return code, so that callers can write `return vdt_err_set(err, ...)`.
 */
int vdt_err_set(struct vdt_err *err, int code, const char *fmt, ...)
	__attribute__((format(printf, 3, 4)));

/*
 * Prefix the message already in err with "prefix: " (for adding context such
 * as a chunk name on the way up). Returns err->code, or VDT_EINVAL if err is
 * NULL.
 */
int vdt_err_prefix(struct vdt_err *err, const char *fmt, ...)
	__attribute__((format(printf, 2, 3)));

/* A short constant description of a status code ("checksum mismatch"). */
const char *vdt_strstatus(int code);

#endif
