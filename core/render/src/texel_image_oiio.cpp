// Image files as rendering data through OpenImageIO (texel_image.h): the body of
// load_texel_image, built as its own shared module (libfacet_oiio.so) that texel_image.cpp
// loads on the first image a scene reads. OpenImageIO brings ~250 shared libraries; linked into
// the renderer they cost every process start ~0.4 s of CPU (the dynamic loader's relocations;
// measured: `facet scene-format` 0.007 s -> 0.41 s), textures or not.
#include "facet/render/texel_image.h"

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>

#include <fmt/format.h>
#include <cmath>
#include <filesystem>

namespace facet::render {

TexelImage load_texel_image_oiio(const std::string& path, const TexelImageOptions& options,
                                 const std::string& where,
                                 OIIO::Filesystem::IOProxy* memory = nullptr,
                                 const TexelRowSink* sink = nullptr);

namespace {

[[noreturn]] void fail(const std::string& where, const std::string& path, const std::string& what) {
    throw TexelImageError(fmt::format("{}: {}: {}", where, path, what));
}

bool is_float(const OIIO::TypeDesc& t) {
    return t.basetype == OIIO::TypeDesc::FLOAT || t.basetype == OIIO::TypeDesc::HALF ||
           t.basetype == OIIO::TypeDesc::DOUBLE;
}

}  // namespace

// `memory`: the encoded file's bytes (an image inside a .glb or a data: URI), read through
// OpenImageIO's IOProxy without a temporary file; `path` then only names it (its extension picks
// the format) in messages. `sink`: stream the rows when sink->stream(header) says so (bands of
// kRowBand rows through read_scanlines, decoded as the whole image is), texels left empty.
TexelImage load_texel_image_oiio(const std::string& path, const TexelImageOptions& options,
                                 const std::string& where, OIIO::Filesystem::IOProxy* memory,
                                 const TexelRowSink* sink) {
    std::error_code ec;
    if (!memory && !std::filesystem::is_regular_file(path, ec))
        fail(where, path, "no such image file");
    // Colour as stored: OpenImageIO otherwise multiplies the colour of PNG/TGA files with
    // unassociated alpha by alpha on reading (in the encoded values, before any decoding).
    OIIO::ImageSpec config;
    config.attribute("oiio:UnassociatedAlpha", 1);
    // OpenImageIO 2.4's readers take the proxy from this attribute (its open()'s own proxy
    // argument is not passed on to the PNG reader: "Could not open file").
    if (memory) config.attribute("oiio:ioproxy", OIIO::TypeDesc::PTR, &memory);
    auto in = OIIO::ImageInput::open(path, &config);
    if (!in) fail(where, path, "cannot read image: " + OIIO::geterror());
    const OIIO::ImageSpec& spec = in->spec();
    TexelImage image;
    image.path = path;
    image.width = spec.width;
    image.height = spec.height;
    image.channels = spec.nchannels;
    image.alpha_channel = spec.alpha_channel;
    if (image.width <= 0 || image.height <= 0 || image.channels <= 0)
        fail(where, path,
             fmt::format("image of size {}x{} with {} channels", image.width, image.height,
                         image.channels));
    // Every channel of one format, or the file's largest (spec.format) when they differ.
    image.float_format = is_float(spec.format);
    for (const OIIO::TypeDesc& t : spec.channelformats) image.float_format |= is_float(t);
    ColorSpace cs = options.color_space;
    if (cs == ColorSpace::Auto) cs = image.float_format ? ColorSpace::Linear : ColorSpace::Srgb;
    image.color_space = cs;
    const std::size_t nc = std::size_t(image.channels);
    const bool streamed = sink && sink->stream(image);
    // Rows per read: all of them, or bands of kRowBand when streaming.
    constexpr int kRowBand = 64;
    const int band = streamed ? std::min(kRowBand, image.height) : image.height;
    const std::size_t n = std::size_t(image.width) * std::size_t(band) * nc;
    image.texels.resize(n);
    // Reads rows [y0, y0 + rows) as `type` into `data` (the whole image when not streaming).
    auto read_rows = [&](int y0, int rows, OIIO::TypeDesc type, void* data) {
        const bool ok = streamed ? in->read_scanlines(0, 0, spec.y + y0, spec.y + y0 + rows, 0, 0,
                                                      image.channels, type, data)
                                 : in->read_image(0, 0, 0, image.channels, type, data);
        if (!ok) fail(where, path, "cannot read image: " + in->geterror());
    };
    // Every band in order: read, decode into image.texels, hand over when streaming.
    auto for_each_band = [&](const auto& decode_band) {
        for (int y0 = 0; y0 < image.height; y0 += band) {
            const int rows = std::min(band, image.height - y0);
            decode_band(y0, rows, std::size_t(image.width) * std::size_t(rows) * nc);
            if (streamed) sink->rows(y0, rows, image.texels.data());
        }
        in->close();
        if (streamed) image.texels = {};
        return std::move(image);
    };

    // 8- and 16-bit files are decoded from their integer codes through a table of the curve
    // evaluated in double (code / (2^bits - 1), then sRGB or not, rounded once to float): exact,
    // and one look-up per texel. Everything else is read as float.
    const bool bits8 = !image.float_format && spec.format.basetype == OIIO::TypeDesc::UINT8;
    const bool bits16 = !image.float_format && !bits8;
    if (bits8 || bits16) {
        const std::size_t levels = bits8 ? 256 : 65536;
        std::vector<float> srgb_table(levels), linear_table(levels);
        for (std::size_t k = 0; k < levels; ++k) {
            const double e = double(k) / double(levels - 1);
            linear_table[k] = float(e);
            srgb_table[k] = cs == ColorSpace::Srgb ? srgb_decode_exact(e) : float(e);
        }
        auto decode = [&](const auto* codes, std::size_t count) {
            for (std::size_t i = 0; i < count; ++i) {
                const bool alpha = int(i % nc) == image.alpha_channel;
                image.texels[i] = (alpha ? linear_table : srgb_table)[codes[i]];
            }
        };
        if (bits8) {
            std::vector<std::uint8_t> codes(n);
            return for_each_band([&](int y0, int rows, std::size_t count) {
                read_rows(y0, rows, OIIO::TypeDesc::UINT8, codes.data());
                decode(codes.data(), count);
            });
        }
        std::vector<std::uint16_t> codes(n);
        return for_each_band([&](int y0, int rows, std::size_t count) {
            read_rows(y0, rows, OIIO::TypeDesc::UINT16, codes.data());
            decode(codes.data(), count);
        });
    }
    return for_each_band([&](int y0, int rows, std::size_t count) {
        read_rows(y0, rows, OIIO::TypeDesc::FLOAT, image.texels.data());
        // A short last band: check only its rows (the rest is the previous band's).
        image.texels.resize(count);
        const int h = image.height;
        image.height = rows;
        check_and_decode_texels(image, cs, options.reject_negative, where, y0);
        image.height = h;
    });
}

}  // namespace facet::render

// The module's one entry point (C linkage: looked up by name with dlsym). Never throws: an
// error's message goes to `error` and the result is false.
extern "C" bool facet_oiio_load_texel_image(const std::string& path,
                                            const facet::render::TexelImageOptions& options,
                                            const std::string& where,
                                            facet::render::TexelImage& out, std::string& error) {
    try {
        out = facet::render::load_texel_image_oiio(path, options, where);
        return true;
    } catch (const std::exception& e) {
        error = e.what();
        return false;
    }
}

// The same from an encoded image in memory (texel_image.h, load_texel_image_memory).
extern "C" bool facet_oiio_load_texel_image_memory(const std::string& name,
                                                   const unsigned char* bytes, std::size_t size,
                                                   const facet::render::TexelImageOptions& options,
                                                   const std::string& where,
                                                   facet::render::TexelImage& out,
                                                   std::string& error) {
    try {
        OIIO::Filesystem::IOMemReader reader(bytes, size);
        out = facet::render::load_texel_image_oiio(name, options, where, &reader);
        return true;
    } catch (const std::exception& e) {
        error = e.what();
        return false;
    }
}

// Streaming (texel_image.h, load_texel_image_rows): from the file, or from `bytes` when
// `in_memory`.
extern "C" bool facet_oiio_load_texel_image_rows(
    const std::string& path, const unsigned char* bytes, std::size_t size, bool in_memory,
    const facet::render::TexelImageOptions& options, const std::string& where,
    const facet::render::TexelRowSink& sink, facet::render::TexelImage& out, std::string& error) {
    try {
        OIIO::Filesystem::IOMemReader reader(bytes, size);
        out = facet::render::load_texel_image_oiio(path, options, where,
                                                   in_memory ? &reader : nullptr, &sink);
        return true;
    } catch (const std::exception& e) {
        error = e.what();
        return false;
    }
}
