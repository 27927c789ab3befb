// Image files as rendering data (texel_image.h): the cache, and load_texel_image, which calls
// the OpenImageIO module (texel_image_oiio.cpp, libfacet_oiio.so) loaded on first use, so that
// scenes without images never load OpenImageIO and its ~250 libraries.
#include "facet/render/texel_image.h"

#include <dlfcn.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <mutex>

namespace facet::render {

namespace {

using LoadFn = bool (*)(const std::string&, const TexelImageOptions&, const std::string&,
                        TexelImage&, std::string&);
using LoadMemoryFn = bool (*)(const std::string&, const unsigned char*, std::size_t,
                              const TexelImageOptions&, const std::string&, TexelImage&,
                              std::string&);

// The module's entry points, looked up once.
struct Module {
    LoadFn load = nullptr;
    LoadMemoryFn load_memory = nullptr;
    std::string tried;
};

constexpr const char* kModuleName = "libfacet_oiio.so";

// The module, searched in order: $FACET_OIIO_MODULE; beside the binary that holds this code (the
// Python extension's folder, also inside the Blender addon); the build tree's copy.
void* load_module(std::string& tried) {
    std::vector<std::string> candidates;
    if (const char* env = std::getenv("FACET_OIIO_MODULE"); env && *env) candidates.push_back(env);
    Dl_info info{};
    if (dladdr(reinterpret_cast<void*>(&load_module), &info) && info.dli_fname) {
        std::error_code ec;
        const auto dir = std::filesystem::weakly_canonical(info.dli_fname, ec).parent_path();
        if (!ec) candidates.push_back((dir / kModuleName).string());
    }
#ifdef FACET_OIIO_MODULE
    candidates.push_back(FACET_OIIO_MODULE);
#endif
    for (const std::string& c : candidates) {
        if (!std::filesystem::exists(c)) {
            tried += "\n  " + c + ": not found";
            continue;
        }
        void* h = dlopen(c.c_str(), RTLD_NOW | RTLD_LOCAL);
        if (!h) {
            tried += "\n  " + c + ": " + dlerror();
            continue;
        }
        if (dlsym(h, "facet_oiio_load_texel_image")) return h;
        tried += "\n  " + c + ": no entry point facet_oiio_load_texel_image";
    }
    return nullptr;
}

const Module& module() {
    static const Module m = [] {
        Module r;
        if (void* h = load_module(r.tried)) {
            r.load = reinterpret_cast<LoadFn>(dlsym(h, "facet_oiio_load_texel_image"));
            r.load_memory =
                reinterpret_cast<LoadMemoryFn>(dlsym(h, "facet_oiio_load_texel_image_memory"));
        }
        return r;
    }();
    return m;
}

[[noreturn]] void unavailable(const std::string& where, const std::string& path) {
    throw TexelImageError(where + ": " + path + ": image support (OpenImageIO, " + kModuleName +
                          ") is not available; tried:" + module().tried);
}

}  // namespace

TexelImage load_texel_image(const std::string& path, const TexelImageOptions& options,
                            const std::string& where) {
    const LoadFn fn = module().load;
    if (!fn) unavailable(where, path);
    TexelImage out;
    std::string error;
    if (!fn(path, options, where, out, error)) throw TexelImageError(error);
    return out;
}

namespace {

// One axis of the box resample from n to m < n texels: output i covers input [i s, (i + 1) s)
// with s = n / m; each input texel j weighs its overlap with that interval, divided by s.
struct BoxTap {
    int first = 0;
    std::vector<float> weights;
};

std::vector<BoxTap> box_taps(int n, int m) {
    std::vector<BoxTap> taps(static_cast<std::size_t>(m));
    const double s = double(n) / double(m);
    for (int i = 0; i < m; ++i) {
        const double a = double(i) * s, b = double(i + 1) * s;
        const int j0 = int(std::floor(a)), j1 = std::min(n, int(std::ceil(b)));
        BoxTap& t = taps[std::size_t(i)];
        t.first = j0;
        for (int j = j0; j < j1; ++j)
            t.weights.push_back(float((std::min(b, double(j + 1)) - std::max(a, double(j))) / s));
    }
    return taps;
}

// `src` resampled to w x h (each no larger than src's) by the separable box filter.
TexelImage box_downsample(const TexelImage& src, int w, int h) {
    const int c = src.channels;
    const std::vector<BoxTap> tx = box_taps(src.width, w), ty = box_taps(src.height, h);
    // Along x first (src.height rows of w texels), then along y.
    std::vector<float> rows(std::size_t(src.height) * std::size_t(w) * std::size_t(c), 0.f);
    for (int y = 0; y < src.height; ++y)
        for (int x = 0; x < w; ++x) {
            const BoxTap& t = tx[std::size_t(x)];
            float* out = &rows[(std::size_t(y) * std::size_t(w) + std::size_t(x)) * std::size_t(c)];
            for (std::size_t k = 0; k < t.weights.size(); ++k)
                for (int ch = 0; ch < c; ++ch)
                    out[ch] += t.weights[k] * src.at(t.first + int(k), y, ch);
        }
    TexelImage dst;
    dst.path = src.path;
    dst.width = w;
    dst.height = h;
    dst.channels = c;
    dst.alpha_channel = src.alpha_channel;
    dst.float_format = src.float_format;
    dst.color_space = src.color_space;
    dst.texels.assign(std::size_t(w) * std::size_t(h) * std::size_t(c), 0.f);
    for (int y = 0; y < h; ++y) {
        const BoxTap& t = ty[std::size_t(y)];
        float* out = &dst.texels[std::size_t(y) * std::size_t(w) * std::size_t(c)];
        for (std::size_t k = 0; k < t.weights.size(); ++k) {
            const float* in =
                &rows[std::size_t(t.first + int(k)) * std::size_t(w) * std::size_t(c)];
            for (std::size_t i = 0; i < std::size_t(w) * std::size_t(c); ++i)
                out[i] += t.weights[k] * in[i];
        }
    }
    return dst;
}

std::uint64_t texel_bytes(const TexelImage& image) {
    return std::uint64_t(image.texels.size()) * sizeof(float);
}

std::string mib(std::uint64_t bytes) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.1f MiB", double(bytes) / double(1 << 20));
    return buf;
}

}  // namespace

TexelImage texel_image_from_memory(const std::uint8_t* codes, const float* floats, int w, int h,
                                   int c, const TexelImageOptions& options, const std::string& name,
                                   const std::string& where) {
    if (w <= 0 || h <= 0 || c < 1 || c > 4)
        throw TexelImageError(where + ": " + name + ": image of size " + std::to_string(w) + "x" +
                              std::to_string(h) + " with " + std::to_string(c) +
                              " channels (expected at least 1 x 1 with 1 to 4 channels)");
    TexelImage image;
    image.path = name;
    image.width = w;
    image.height = h;
    image.channels = c;
    image.alpha_channel = c == 2 ? 1 : c == 4 ? 3 : -1;
    image.float_format = codes == nullptr;
    const std::size_t n = std::size_t(w) * std::size_t(h) * std::size_t(c);
    image.texels.resize(n);
    ColorSpace cs = options.color_space;
    if (cs == ColorSpace::Auto) cs = codes ? ColorSpace::Srgb : ColorSpace::Linear;
    if (!codes) {
        image.texels.assign(floats, floats + n);
        check_and_decode_texels(image, cs, options.reject_negative, where);
        return image;
    }
    // 8-bit codes decode from the exact code / 255 (in double), as the file reader does.
    for (std::size_t i = 0; i < n; ++i) {
        const double e = double(codes[i]) / 255.0;
        const bool colour = int(i % std::size_t(c)) != image.alpha_channel;
        image.texels[i] = cs == ColorSpace::Srgb && colour ? srgb_decode_exact(e) : float(e);
    }
    image.color_space = cs;
    return image;
}

std::vector<TexelImage> build_mip_levels(const TexelImage& image) {
    std::vector<TexelImage> levels;
    const TexelImage* prev = &image;
    while (prev->width > 1 || prev->height > 1) {
        levels.push_back(
            box_downsample(*prev, std::max(1, prev->width / 2), std::max(1, prev->height / 2)));
        prev = &levels.back();
    }
    return levels;
}

void TexelImageCache::reserve(std::uint64_t add, const std::string& where,
                              const std::string& path) {
    if (m_bytes + add > m_limit) {
        throw TexelImageError(where + ": " + path + ": texture memory would reach " +
                              mib(m_bytes + add) + " (" + mib(add) +
                              " more for this file), above the limit of " + mib(m_limit) +
                              " (raise it with `facet render --texture-memory MIB` or "
                              "SceneLimits::texture_memory)");
    }
    m_bytes += add;
}

TexelImage load_texel_image_memory(const std::string& name, std::span<const unsigned char> bytes,
                                   const TexelImageOptions& options, const std::string& where) {
    const LoadMemoryFn fn = module().load_memory;
    if (!fn) unavailable(where, name);
    TexelImage out;
    std::string error;
    if (!fn(name, bytes.data(), bytes.size(), options, where, out, error))
        throw TexelImageError(error);
    return out;
}

std::shared_ptr<const TexelImage> TexelImageCache::get_memory(const std::string& name,
                                                              std::span<const unsigned char> bytes,
                                                              const TexelImageOptions& options,
                                                              const std::string& where) {
    const auto key = std::make_tuple(name, int(options.color_space), options.reject_negative);
    std::lock_guard lock(m_mutex);
    auto it = m_images.find(key);
    if (it != m_images.end()) return it->second;
    auto image =
        std::make_shared<const TexelImage>(load_texel_image_memory(name, bytes, options, where));
    reserve(texel_bytes(*image), where, name);
    m_images.emplace(key, image);
    return image;
}

std::shared_ptr<const TexelImage> TexelImageCache::get(const std::string& path,
                                                       const TexelImageOptions& options,
                                                       const std::string& where) {
    std::error_code ec;
    std::string key_path = std::filesystem::weakly_canonical(path, ec).string();
    if (ec) key_path = path;
    const auto key = std::make_tuple(key_path, int(options.color_space), options.reject_negative);
    std::lock_guard lock(m_mutex);
    auto it = m_images.find(key);
    if (it != m_images.end()) return it->second;
    auto image = std::make_shared<const TexelImage>(load_texel_image(path, options, where));
    reserve(texel_bytes(*image), where, path);
    m_images.emplace(key, image);
    return image;
}

std::shared_ptr<const TexelImage> TexelImageCache::adopt(std::shared_ptr<const TexelImage> image,
                                                         const std::string& where) {
    std::lock_guard lock(m_mutex);
    if (m_adopted.count(image.get())) return image;
    reserve(texel_bytes(*image), where, image->path);
    m_adopted.emplace(image.get(), image);
    return image;
}

std::shared_ptr<const std::vector<TexelImage>> TexelImageCache::mip_levels(
    const std::shared_ptr<const TexelImage>& image, const std::string& where) {
    std::lock_guard lock(m_mutex);
    auto it = m_mips.find(image.get());
    if (it != m_mips.end()) return it->second;
    // Checked before building: the levels take a third of the image (1/4 + 1/16 + ...).
    std::uint64_t add = 0;
    for (int w = image->width, h = image->height; w > 1 || h > 1;) {
        w = std::max(1, w / 2);
        h = std::max(1, h / 2);
        add += std::uint64_t(w) * std::uint64_t(h) * std::uint64_t(image->channels) * sizeof(float);
    }
    reserve(add, where, image->path);
    auto levels = std::make_shared<const std::vector<TexelImage>>(build_mip_levels(*image));
    m_mips.emplace(image.get(), levels);
    return levels;
}

std::size_t TexelImageCache::size() const {
    std::lock_guard lock(m_mutex);
    return m_images.size();
}

std::size_t TexelImageCache::bytes() const {
    std::lock_guard lock(m_mutex);
    return std::size_t(m_bytes);
}

}  // namespace facet::render
