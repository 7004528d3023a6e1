/*
 * image.cc - the extern "C" face of OpenImageIO: 8-bit images in and out,
 * the format from the file name's extension. Output is atomic: written to a
 * temporary name with the same extension (so that OpenImageIO picks the same
 * writer) and renamed over the target on success; through a symbolic link
 * to what it names, and in place to a device or FIFO (vdt_output_target).
 */
#include <OpenImageIO/imageio.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <string>
#include <unistd.h>

extern "C" {
#include "meshio.h"
}

namespace {

std::string
temp_name(const std::string &path)
{
	size_t slash = path.rfind('/');
	std::string dir = slash == std::string::npos ? "" : path.substr(0, slash + 1);
	std::string base = slash == std::string::npos ? path : path.substr(slash + 1);
	size_t dot = base.rfind('.');
	std::string ext = dot == std::string::npos ? "" : base.substr(dot);
	return dir + "." + base + "." + std::to_string(long(getpid())) + ".tmp" + ext;
}

int
write_image(const char *path, int w, int h, int c, const unsigned char *px, struct vdt_err *err)
{
	if (w <= 0 || h <= 0 || c <= 0 || c > 4)
		return vdt_err_set(err, VDT_EINVAL, "bad image size %dx%d with %d channels", w, h, c);
	int special = 0;
	char *target = vdt_output_target(path, &special);
	if (target == nullptr)
		return vdt_err_set(err, VDT_ENOMEM, "out of memory");
	std::string dst(target);
	std::free(target);
	std::string tmp = special ? dst : temp_name(dst);
	auto out = OIIO::ImageOutput::create(path);
	if (!out) {
		std::string e = OIIO::geterror();
		return vdt_err_set(err, VDT_EINVAL, "no image writer for this file name%s%s",
		                   e.empty() ? "" : ": ", e.c_str());
	}
	OIIO::ImageSpec spec(w, h, c, OIIO::TypeDesc::UINT8);
	if (!out->open(tmp, spec)) {
		std::string e = out->geterror();
		if (!special)
			std::remove(tmp.c_str());
		return vdt_err_set(err, VDT_EIO, "%s", e.c_str());
	}
	bool ok = out->write_image(OIIO::TypeDesc::UINT8, px);
	std::string e = ok ? "" : out->geterror();
	if (!out->close() && ok) {
		ok = false;
		e = out->geterror();
	}
	if (!ok) {
		if (!special)
			std::remove(tmp.c_str());
		return vdt_err_set(err, VDT_EIO, "%s", e.c_str());
	}
	if (!special && std::rename(tmp.c_str(), dst.c_str()) != 0) {
		int en = errno;
		std::remove(tmp.c_str());
		return vdt_err_set(err, VDT_EIO, "cannot rename the temporary file: %s", std::strerror(en));
	}
	return 0;
}

int
read_image(const char *path, int *w, int *h, int *c, unsigned char **px, struct vdt_err *err)
{
	auto in = OIIO::ImageInput::open(path);
	if (!in) {
		std::string e = OIIO::geterror();
		return vdt_err_set(err, VDT_EIO, "%s", e.empty() ? "cannot open the image" : e.c_str());
	}
	const OIIO::ImageSpec &spec = in->spec();
	if (spec.width <= 0 || spec.height <= 0 || spec.nchannels <= 0 ||
	    size_t(spec.width) * size_t(spec.height) > (size_t(1) << 31) / size_t(spec.nchannels))
		return vdt_err_set(err, VDT_EFORMAT, "image of %dx%d with %d channels is unusable",
		                   spec.width, spec.height, spec.nchannels);
	size_t n = size_t(spec.width) * size_t(spec.height) * size_t(spec.nchannels);
	unsigned char *p = static_cast<unsigned char *>(std::malloc(n));
	if (p == nullptr)
		return vdt_err_set(err, VDT_ENOMEM, "out of memory");
	if (!in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::UINT8, p)) {
		std::string e = in->geterror();
		std::free(p);
		in->close();
		return vdt_err_set(err, VDT_EFORMAT, "%s", e.c_str());
	}
	in->close();
	*w = spec.width;
	*h = spec.height;
	*c = spec.nchannels;
	*px = p;
	return 0;
}

} // namespace

extern "C" int
vdt_image_write(const char *path, int width, int height, int channels,
                const unsigned char *pixels, struct vdt_err *err)
{
	try {
		return write_image(path, width, height, channels, pixels, err);
	} catch (const std::bad_alloc &) {
		return vdt_err_set(err, VDT_ENOMEM, "out of memory");
	} catch (...) {
		return vdt_err_set(err, VDT_EIO, "cannot write the image");
	}
}

extern "C" int
vdt_image_read(const char *path, int *width, int *height, int *channels,
               unsigned char **pixels, struct vdt_err *err)
{
	*pixels = nullptr;
	try {
		return read_image(path, width, height, channels, pixels, err);
	} catch (const std::bad_alloc &) {
		return vdt_err_set(err, VDT_ENOMEM, "out of memory");
	} catch (...) {
		return vdt_err_set(err, VDT_EIO, "cannot read the image");
	}
}
