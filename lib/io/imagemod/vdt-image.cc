/*
 * vdt-image.cc - vdt-image.so, the module that holds OpenImageIO (see
 * imagemod.h): 8-bit images encoded in memory or read whole, the format
 * from the file name's extension.
 */
#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <new>
#include <string>
#include <vector>

extern "C" {
#include "../imagemod.h"
#include "../modcxx.h"
}

namespace {

int
say(int code, const std::string &what, char *msg, size_t cap)
{
	std::snprintf(msg, cap, "%s", what.c_str());
	return code;
}

int
no_writer(char *msg, size_t cap)
{
	std::string e = OIIO::geterror();
	return say(VDT_IMG_NO_WRITER, "no image writer for this file name" + (e.empty() ? "" : ": " + e),
	           msg, cap);
}

/*
 * TIFF and OpenEXR writers stamp the image with the time of writing
 * (DateTime, capDate) unless the spec has one: give them a fixed one so
 * that the same input makes the same bytes. Other formats would add a
 * date they do not write now (a PNG tIME chunk), so they get none. The
 * SGI writer leaves the image name it has none for as the memory held
 * (bytes 24 to 103 of the header): give it one, which it pads with zeros.
 */
OIIO::ImageSpec
spec_for(OIIO::ImageOutput &out, int w, int h, int c)
{
	OIIO::ImageSpec spec(w, h, c, OIIO::TypeDesc::UINT8);
	std::string f = out.format_name();
	if (f == "tiff" || f == "openexr")
		spec.attribute("DateTime", "1970:01:01 00:00:00");
	if (f == "sgi")
		spec.attribute("ImageDescription", "vdt");
	return spec;
}

/*
 * The RLA writer dates its header (DateCreated, 20 bytes at 528) with the
 * time of writing, whatever the spec says: the date goes back to the
 * fixed one of the other formats. An error message or "".
 */
std::string
undate_rla(const char *file)
{
	static const char date[20] = "JAN 01 00:00 1970";
	std::FILE *f = std::fopen(file, "r+b");

	if (f == nullptr)
		return std::strerror(errno);
	bool ok = std::fseek(f, 528, SEEK_SET) == 0 && std::fwrite(date, 1, 20, f) == 20;
	int e = errno;
	if (std::fclose(f) != 0 && ok) {
		ok = false;
		e = errno;
	}
	return ok ? "" : std::strerror(e);
}

/* Write px through out, opened on name: an error message or "". */
std::string
write_all(OIIO::ImageOutput &out, const char *name, const OIIO::ImageSpec &spec,
          const unsigned char *px)
{
	if (!out.open(name, spec))
		return out.geterror();
	bool ok = out.write_image(OIIO::TypeDesc::UINT8, px);
	std::string e = ok ? "" : out.geterror();
	if (!out.close() && ok)
		e = out.geterror();
	return e.empty() && !ok ? "cannot write the image" : e;
}

} // namespace

extern "C" int
vdt_img_abi(void)
{
	vdt_cxx_thread_ready();
	return VDT_IMG_ABI;
}

/*
 * Writers that refuse an image for its size or channels only once they
 * have it, after the whole render: their rules, to refuse it before.
 * (WebP's refuses more than 16383 pixels a side as it encodes.)
 */
const struct {
	const char *format;
	int side;     /* at most this many pixels a side, or 0 */
	int channels; /* only this many channels, or 0 */
} rules[] = {{"ico", 256, 0}, {"webp", 16383, 0}, {"zfile", 0, 1}};

extern "C" int
vdt_img_writer(const char *name, int w, int h, int c, char *msg, size_t cap)
{
	try {
		auto o = OIIO::ImageOutput::create(name);
		if (!o)
			return no_writer(msg, cap);
		std::string f = o->format_name();
		for (const auto &r : rules) {
			if (w <= 0 || f != r.format)
				continue;
			if (r.side > 0 && (w > r.side || h > r.side))
				return say(VDT_IMG_REFUSED,
				           f + " images are at most " + std::to_string(r.side) +
				                   " pixels a side, not " + std::to_string(w) +
				                   "x" + std::to_string(h),
				           msg, cap);
			if (r.channels > 0 && c != r.channels)
				return say(VDT_IMG_REFUSED,
				           f + " images have " + std::to_string(r.channels) +
				                   " channel, not " + std::to_string(c),
				           msg, cap);
		}
		return VDT_IMG_OK;
	} catch (const std::bad_alloc &) {
		return say(VDT_IMG_NOMEM, "out of memory", msg, cap);
	} catch (...) {
		return say(VDT_IMG_FAIL, "cannot write the image", msg, cap);
	}
}

/*
 * The writers' own file output loses errors (the PNG writer leaves a
 * cut-short file on a full disk and says nothing): encoded in memory, the
 * bytes are written by the caller as any other output.
 */
extern "C" int
vdt_img_encode(const char *name, int w, int h, int c, const unsigned char *px,
               unsigned char **out, size_t *len, char *msg, size_t cap)
{
	*out = nullptr;
	*len = 0;
	try {
		auto o = OIIO::ImageOutput::create(name);
		if (!o)
			return no_writer(msg, cap);
		if (!o->supports("ioproxy"))
			return VDT_IMG_OWN_FILE;
		OIIO::Filesystem::IOVecOutput mem;
		if (!o->set_ioproxy(&mem))
			return say(VDT_IMG_FAIL, o->geterror(), msg, cap);
		std::string e = write_all(*o, name, spec_for(*o, w, h, c), px);
		if (!e.empty())
			return say(VDT_IMG_FAIL, e, msg, cap);
		const std::vector<unsigned char> &b = mem.buffer();
		*out = static_cast<unsigned char *>(std::malloc(b.size() + 1));
		if (*out == nullptr)
			return say(VDT_IMG_NOMEM, "out of memory", msg, cap);
		if (!b.empty())
			std::memcpy(*out, b.data(), b.size());
		*len = b.size();
		return VDT_IMG_OK;
	} catch (const std::bad_alloc &) {
		return say(VDT_IMG_NOMEM, "out of memory", msg, cap);
	} catch (...) {
		return say(VDT_IMG_FAIL, "cannot write the image", msg, cap);
	}
}

extern "C" int
vdt_img_write_file(const char *name, const char *file, int w, int h, int c,
                   const unsigned char *px, char *msg, size_t cap)
{
	try {
		auto o = OIIO::ImageOutput::create(name);
		if (!o)
			return no_writer(msg, cap);
		std::string e = write_all(*o, file, spec_for(*o, w, h, c), px);
		if (e.empty() && std::string(o->format_name()) == "rla")
			e = undate_rla(file);
		return e.empty() ? VDT_IMG_OK : say(VDT_IMG_FAIL, e, msg, cap);
	} catch (const std::bad_alloc &) {
		return say(VDT_IMG_NOMEM, "out of memory", msg, cap);
	} catch (...) {
		return say(VDT_IMG_FAIL, "cannot write the image", msg, cap);
	}
}

extern "C" int
vdt_img_read(const char *path, int *w, int *h, int *c, unsigned char **px, char *msg, size_t cap)
{
	*px = nullptr;
	try {
		auto in = OIIO::ImageInput::open(path);
		if (!in) {
			std::string e = OIIO::geterror();
			return say(VDT_IMG_FAIL, e.empty() ? "cannot open the image" : e, msg, cap);
		}
		const OIIO::ImageSpec &spec = in->spec();
		if (spec.width <= 0 || spec.height <= 0 || spec.nchannels <= 0 ||
		    size_t(spec.width) * size_t(spec.height) > (size_t(1) << 31) / size_t(spec.nchannels))
			return say(VDT_IMG_BAD, "image of " + std::to_string(spec.width) + "x" +
			           std::to_string(spec.height) + " with " + std::to_string(spec.nchannels) +
			           " channels is unusable", msg, cap);
		size_t n = size_t(spec.width) * size_t(spec.height) * size_t(spec.nchannels);
		unsigned char *p = static_cast<unsigned char *>(std::malloc(n));
		if (p == nullptr)
			return say(VDT_IMG_NOMEM, "out of memory", msg, cap);
		if (!in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::UINT8, p)) {
			std::string e = in->geterror();
			std::free(p);
			in->close();
			return say(VDT_IMG_BAD, e, msg, cap);
		}
		in->close();
		*w = spec.width;
		*h = spec.height;
		*c = spec.nchannels;
		*px = p;
		return VDT_IMG_OK;
	} catch (const std::bad_alloc &) {
		return say(VDT_IMG_NOMEM, "out of memory", msg, cap);
	} catch (...) {
		return say(VDT_IMG_FAIL, "cannot read the image", msg, cap);
	}
}
