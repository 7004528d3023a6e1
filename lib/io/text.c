/*
 * text.c - correctly rounded decimal to float, and saturating integers.
 *
 * The float parser is Clinger's fast path ("How to Read Floating Point
 * Numbers Accurately", PLDI 1990, section 4) with strtof as the exact
 * fallback for what the fast path cannot decide. It exists because strtof
 * alone is several times slower, depends on the locale's decimal point and
 * needs a NUL-terminated string, which a mapped file is not.
 */
#include "text.h"

#include <float.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static int
is_digit(char c)
{
	return c >= '0' && c <= '9';
}

const char *
vdt_text_parse_int(const char *p, const char *end, long long *out)
{
	long long v = 0;
	int neg = 0;

	if (p < end && (*p == '-' || *p == '+'))
		neg = *p++ == '-';
	if (p == end || !is_digit(*p))
		return NULL;
	for (; p < end && is_digit(*p); p++)
		v = v < VDT_TEXT_SATURATE / 10 ? v * 10 + (*p - '0') : VDT_TEXT_SATURATE;
	*out = neg ? -v : v;
	return p;
}

const char *
vdt_text_int_shown(const char *p, const char *end, long long v, char out[VDT_TEXT_INT_SHOWN])
{
	size_t n = 0;

	if (v != VDT_TEXT_SATURATE && v != -VDT_TEXT_SATURATE) {
		snprintf(out, VDT_TEXT_INT_SHOWN, "%lld", v);
		return out;
	}
	if (v < 0)
		out[n++] = '-';
	if (p < end && (*p == '-' || *p == '+'))
		p++;
	while (p + 1 < end && *p == '0' && is_digit(p[1]))
		p++;
	for (size_t d = 0; p < end && is_digit(*p) && d < 40; p++, d++)
		out[n++] = *p;
	if (p < end && is_digit(*p)) {
		memcpy(out + n, "...", 3);
		n += 3;
	}
	out[n] = '\0';
	return out;
}

/*
 * "nan", "inf" or "infinity", any case, already past the sign. The longer
 * word is tried first, so that "infinity" is not read as "inf" + "inity".
 */
static const char *
parse_special(const char *p, const char *end, int neg, float *out)
{
	static const char *const words[] = {"infinity", "inf", "nan"};

	for (size_t w = 0; w < sizeof(words) / sizeof(words[0]); w++) {
		size_t l = strlen(words[w]), i = 0;

		while (i < l && p + i < end && (p[i] | 0x20) == words[w][i])
			i++;
		if (i == l) {
			*out = w == 2 ? NAN : neg ? -INFINITY : INFINITY;
			return p + l;
		}
	}
	return NULL;
}

/*
 * The exact path for what the fast path cannot decide: the significant
 * digits and the exponent are rewritten as "DDDDe-NN", without a decimal
 * point so that the locale cannot matter, and given to strtof, which rounds
 * correctly. Beyond 200 digits a nonzero tail only needs to be known to
 * exist (a float's halfway points have fewer than 120 significant digits),
 * so it becomes one sticky digit.
 */
static float
slow_float(const char *p, const char *end)
{
	char s[256];
	size_t n = 0, sig = 0;
	long long exp10 = 0, e = 0;
	int sticky = 0, frac = 0, eneg = 0;

	if (*p == '-')
		s[n++] = '-';
	if (*p == '-' || *p == '+')
		p++;
	for (; p < end && (is_digit(*p) || *p == '.'); p++) {
		if (*p == '.')
			frac = 1;
		else if (sig == 0 && *p == '0')
			exp10 -= frac; /* a leading zero */
		else if (sig < 200) {
			s[n++] = *p;
			sig++;
			exp10 -= frac;
		} else {
			sticky |= *p != '0';
			exp10 += !frac;
		}
	}
	if (sticky) {
		s[n++] = '1';
		exp10--;
	}
	if (p < end && (*p == 'e' || *p == 'E')) {
		p++;
		if (p < end && (*p == '-' || *p == '+'))
			eneg = *p++ == '-';
		for (; p < end && is_digit(*p); p++)
			if (e < 1000000000)
				e = e * 10 + (*p - '0');
	}
	exp10 += eneg ? -e : e;
	if (exp10 > 100000)
		exp10 = 100000;
	if (exp10 < -100000)
		exp10 = -100000;
	snprintf(s + n, sizeof(s) - n, "e%lld", exp10);
	return strtof(s, NULL);
}

static const double pow10_exact[] = {
	1e0,  1e1,  1e2,  1e3,  1e4,  1e5,  1e6,  1e7,  1e8,  1e9,  1e10, 1e11,
	1e12, 1e13, 1e14, 1e15, 1e16, 1e17, 1e18, 1e19, 1e20, 1e21, 1e22,
};

/*
 * The common case (at most 19 significant digits, a mantissa below 2^53, a
 * power of ten below 10^23) is Clinger's fast path: the double is exact or
 * correctly rounded, and rounding it again to float can only go wrong when
 * it landed exactly on a halfway point between two floats, which is tested
 * for. Everything else goes to slow_float, as does every number where double
 * arithmetic is carried out in wider registers (FLT_EVAL_METHOD != 0, the
 * x87).
 */
const char *
vdt_text_parse_float(const char *p, const char *end, float *out)
{
	const char *start = p;
	uint64_t mant = 0;
	long long exp10 = 0;
	int neg = 0, digits = 0, any = 0, exact = 1;

	if (p < end && (*p == '-' || *p == '+'))
		neg = *p++ == '-';
	for (; p < end && is_digit(*p); p++) {
		any = 1;
		if (digits < 19) {
			mant = mant * 10 + (uint64_t)(*p - '0');
			digits += mant != 0;
		} else {
			exact &= *p == '0';
			exp10++;
		}
	}
	if (p < end && *p == '.')
		for (p++; p < end && is_digit(*p); p++) {
			any = 1;
			if (digits < 19) {
				mant = mant * 10 + (uint64_t)(*p - '0');
				digits += mant != 0;
				exp10--;
			} else {
				exact &= *p == '0';
			}
		}
	if (!any) {
		/* No digit: a word after the sign at most ("-." is junk). */
		if (p != start && (p[-1] == '.' || p - start > 1))
			return NULL;
		return parse_special(p, end, neg, out);
	}
	if (p < end && (*p == 'e' || *p == 'E')) {
		const char *q = p + 1;
		long long e = 0;
		int eneg = 0;

		if (q < end && (*q == '-' || *q == '+'))
			eneg = *q++ == '-';
		if (q == end || !is_digit(*q))
			return NULL;
		for (; q < end && is_digit(*q); q++)
			if (e < 1000000000)
				e = e * 10 + (*q - '0');
		exp10 += eneg ? -e : e;
		p = q;
	}
	if (mant == 0) {
		*out = neg ? -0.0f : 0.0f;
		return p;
	}
	if (FLT_EVAL_METHOD == 0 && exact && mant <= (1ull << 53) && exp10 >= -22 &&
	    exp10 <= 22) {
		double d = (double)mant;
		uint64_t bits;

		d = exp10 < 0 ? d / pow10_exact[-exp10] : d * pow10_exact[exp10];
		memcpy(&bits, &d, sizeof(bits));
		/* In the normal float range a halfway point has 29 low bits 1000...0. */
		if (d >= 0x1p-126 && d < 0x1p127 && (bits & 0x1fffffff) != 0x10000000) {
			*out = neg ? -(float)d : (float)d;
			return p;
		}
	}
	*out = slow_float(start, p);
	return p;
}

int
vdt_text_beyond_float(const char *p, const char *end, float f)
{
	if (!isinf(f))
		return 0;
	if (p < end && (*p == '-' || *p == '+'))
		p++;
	/* a number has a digit or a point first; "inf" a letter */
	return p < end && (is_digit(*p) || *p == '.');
}
