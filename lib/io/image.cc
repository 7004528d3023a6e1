/*
 * image.cc - the extern "C" face of OpenImageIO: 8-bit images in and out,
 * the format from the file name's extension. Output is atomic, as for
 * meshes (vdt_output_open): written to a hidden temporary file beside the
 * target, .NAME.XXXXXX from mkstemp with the target's permissions, and
 * renamed over the target on success; through a symbolic link to what it
 * names, and in place to a device or FIFO (vdt_output_target). The writer
 * is picked by the target's extension, so the temporary name needs none.
 */
#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>
#include <unistd.h>

extern "C" {
#include "meshio.h"
}

namespace {

/* The error when OpenImageIO has no writer for a file name. */
int
no_writer(struct vdt_err *err)
{
	std::string e = OIIO::geterror();
	return vdt_err_set(err, VDT_EINVAL, "no image writer for this file name%s%s",
	                   e.empty() ? "" : ": ", e.c_str());
}

/*
 * TIFF and OpenEXR writers stamp the image with the time of writing
 * (DateTime, capDate) unless the spec has one: give them a fixed one so
 * that the same input makes the same bytes. Other formats would add a
 * date they do not write now (a PNG tIME chunk), so they get none.
 */
void
fix_date(OIIO::ImageOutput &out, OIIO::ImageSpec &spec)
{
	std::string f = out.format_name();
	if (f == "tiff" || f == "openexr")
		spec.attribute("DateTime", "1970:01:01 00:00:00");
}

/* The name OpenImageIO picks a writer by: "-" (standard output) is PNG,
 * whose writer goes through memory (write_through_memory). */
const char *
writer_name(const char *path)
{
	return std::strcmp(path, "-") == 0 ? "-.png" : path;
}

/* Bytes of an image are no more for a terminal than a binary mesh is. */
int
refuse_terminal(const char *path, struct vdt_err *err)
{
	if (std::strcmp(path, "-") == 0 && isatty(STDOUT_FILENO))
		return vdt_err_set(err, VDT_EINVAL, "refusing to write a binary image to a terminal");
	return 0;
}

/*
 * Encode into memory, then write the bytes as any other output
 * (vdt_output_open: standard output, atomic replacement, and every write
 * error reported). The writers' own file output loses errors: the PNG
 * writer leaves a cut-short file on a full disk and says nothing.
 */
int
write_through_memory(OIIO::ImageOutput &out, const char *path, const OIIO::ImageSpec &spec,
                     const unsigned char *px, struct vdt_written *stage, struct vdt_err *err)
{
	OIIO::Filesystem::IOVecOutput mem;
	if (!out.set_ioproxy(&mem) || !out.open(writer_name(path), spec))
		return vdt_err_set(err, VDT_EIO, "%s", out.geterror().c_str());
	bool ok = out.write_image(OIIO::TypeDesc::UINT8, px);
	std::string e = ok ? "" : out.geterror();
	if (!out.close() && ok) {
		ok = false;
		e = out.geterror();
	}
	if (!ok)
		return vdt_err_set(err, VDT_EIO, "%s", e.c_str());
	const std::vector<unsigned char> &b = mem.buffer();
	struct vdt_output o;
	int rc = vdt_output_open(&o, path, err);
	if (rc != 0)
		return rc;
	if (!b.empty() && std::fwrite(b.data(), 1, b.size(), o.f) != b.size()) {
		int en = errno;
		vdt_output_abort(&o);
		return vdt_err_set(err, VDT_EIO, "write error: %s", std::strerror(en));
	}
	return stage ? vdt_output_stage(&o, stage, err) : vdt_output_commit(&o, err);
}

int
write_image(const char *path, int w, int h, int c, const unsigned char *px,
            struct vdt_written *stage, struct vdt_err *err)
{
	if (w <= 0 || h <= 0 || c <= 0 || c > 4)
		return vdt_err_set(err, VDT_EINVAL, "bad image size %dx%d with %d channels", w, h, c);
	if (int rc = refuse_terminal(path, err))
		return rc;
	auto out = OIIO::ImageOutput::create(writer_name(path));
	if (!out)
		return no_writer(err);
	OIIO::ImageSpec spec(w, h, c, OIIO::TypeDesc::UINT8);
	fix_date(*out, spec);
	if (out->supports("ioproxy"))
		return write_through_memory(*out, path, spec, px, stage, err);
	/* A writer of its own file (SGI here), by name: never "-". */
	int special = 0;
	char *target = vdt_output_target(path, &special);
	if (target == nullptr)
		return vdt_err_set(err, VDT_ENOMEM, "out of memory");
	std::string dst(target);
	std::free(target);
	std::string tmp = dst;
	/* Whichever way this returns, the temporary file is gone or renamed
	 * by then: a signal need not remove it any more. */
	struct done_guard {
		const std::string &tmp;
		bool on;
		~done_guard()
		{
			if (on)
				vdt_output_temp_done(tmp.c_str());
		}
	} done{tmp, false};
	if (!special) {
		char *t = nullptr;
		int fd = vdt_output_temp(dst.c_str(), &t);
		if (fd == -2)
			return vdt_err_set(err, VDT_ENOMEM, "out of memory");
		if (fd < 0)
			return vdt_err_set(err, VDT_EIO, "cannot create a temporary file: %s",
			                   std::strerror(errno));
		close(fd); /* OpenImageIO opens it again by name */
		tmp = t;
		std::free(t);
		done.on = true;
	}
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
	/* (a writer of its own file cannot be staged: what it replaced is
	 * gone, and what it wrote goes with a failed run) */
	return stage ? vdt_written_add(stage, path, err) : 0;
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
vdt_image_writable(const char *path, struct vdt_err *err)
{
	if (int rc = refuse_terminal(path, err))
		return rc;
	try {
		auto out = OIIO::ImageOutput::create(writer_name(path));
		return out ? 0 : no_writer(err);
	} catch (const std::bad_alloc &) {
		return vdt_err_set(err, VDT_ENOMEM, "out of memory");
	} catch (...) {
		return vdt_err_set(err, VDT_EIO, "cannot write the image");
	}
}

extern "C" int
vdt_image_write(const char *path, int width, int height, int channels,
                const unsigned char *pixels, struct vdt_err *err)
{
	return vdt_image_write_staged(path, width, height, channels, pixels, nullptr, err);
}

extern "C" int
vdt_image_write_staged(const char *path, int width, int height, int channels,
                       const unsigned char *pixels, struct vdt_written *stage,
                       struct vdt_err *err)
{
	try {
		return write_image(path, width, height, channels, pixels, stage, err);
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
