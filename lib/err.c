#include "err.h"

#include <stdarg.h>
#include <stdio.h>
#include <string.h>

int
vdt_err_set(struct vdt_err *err, int code, const char *fmt, ...)
{
	va_list ap;

	if (err == NULL)
		return code;
	err->code = code;
	va_start(ap, fmt);
	vsnprintf(err->msg, sizeof(err->msg), fmt, ap);
	va_end(ap);
	return code;
}

int
vdt_err_prefix(struct vdt_err *err, const char *fmt, ...)
{
	char head[VDT_ERR_MSG_MAX], old[VDT_ERR_MSG_MAX];
	va_list ap;

	if (err == NULL)
		return VDT_EINVAL;
	va_start(ap, fmt);
	vsnprintf(head, sizeof(head), fmt, ap);
	va_end(ap);
	memcpy(old, err->msg, sizeof(old));
	/* Truncation is acceptable: the message is for people. */
	size_t n = strlen(head);
	if (n > sizeof(err->msg) - 3)
		n = sizeof(err->msg) - 3;
	memcpy(err->msg, head, n);
	memcpy(err->msg + n, ": ", 2);
	size_t rest = sizeof(err->msg) - n - 2;
	size_t m = strnlen(old, rest - 1);
	memcpy(err->msg + n + 2, old, m);
	err->msg[n + 2 + m] = '\0';
	return err->code;
}

const char *
vdt_strstatus(int code)
{
	switch (code) {
	case VDT_OK: return "success";
	case VDT_EIO: return "input/output error";
	case VDT_EFORMAT: return "bad format";
	case VDT_EVERSION: return "unsupported version";
	case VDT_ECHECKSUM: return "checksum mismatch";
	case VDT_ENOMEM: return "out of memory";
	case VDT_EINVAL: return "invalid argument";
	case VDT_ELIMIT: return "limit cannot be met";
	case VDT_ESYSTEM: return "system error";
	}
	return "unknown error";
}
