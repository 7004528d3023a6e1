/*
 * text.h - number parsing shared by the native text readers (OFF, OBJ,
 * ASCII PLY). Internal to lib/io.
 *
 * Both parsers read one number starting at p and stop at the first byte that
 * cannot continue it, without looking further: what may follow a number (a
 * blank, a line break, a '/' between OBJ indices, a comment) is the caller's
 * format to decide. Neither depends on the locale, and neither reads at or
 * beyond end, so a buffer need not be NUL-terminated.
 */
#ifndef VDT_IO_TEXT_H
#define VDT_IO_TEXT_H

/* Integers saturate here, so that a huge count or index stays huge. */
#define VDT_TEXT_SATURATE 1000000000000000000LL /* 1e18 */

/*
 * An optionally signed decimal integer at p (digits only). Stores it in *out,
 * saturated at +-VDT_TEXT_SATURATE, and returns the byte after its last
 * digit, or NULL if there is no digit after the sign.
 */
const char *vdt_text_parse_int(const char *p, const char *end, long long *out);

/* Room for vdt_text_int_shown's text. */
#define VDT_TEXT_INT_SHOWN 48

/*
 * The integer v that vdt_text_parse_int read at p, for a message: v in
 * decimal, or, when it was saturated, the number as written (its sign and
 * digits, leading zeros dropped, at most 40 digits then "..."), so that no
 * message shows the saturation bound as the file's number. Returns out.
 */
const char *vdt_text_int_shown(const char *p, const char *end, long long v,
                               char out[VDT_TEXT_INT_SHOWN]);

/*
 * A decimal floating-point number at p ("-1.5e3", ".5", "7.", "nan", "inf",
 * "infinity", any case) as the nearest float, correctly rounded. Returns the
 * byte after it, or NULL if there is no number there ("-", ".", "1e" and
 * "1e+" are not numbers).
 */
const char *vdt_text_parse_float(const char *p, const char *end, float *out);

/*
 * Whether f, read by vdt_text_parse_float from p to end, is an infinity only
 * because the number written there is beyond a float's range ("1e39",
 * "-4e38"): 1, or 0 for anything else, "inf" included. Such a number is
 * finite: the readers name it as out of range, not as not finite.
 */
int vdt_text_beyond_float(const char *p, const char *end, float f);

#endif
