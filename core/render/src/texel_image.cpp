// Image files as rendering data (texel_image.h): the cache, and load_texel_image, which calls
// the OpenImageIO module (texel_image_oiio.cpp, libfacet_oiio.so) loaded on first use, so that
// scenes without images never load OpenImageIO and its ~250 libraries.
#include "facet/render/texel_image.h"

#include <dlfcn.h>

#include "facet/render/texel_pages.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <deque>
#include <filesystem>
#include <mutex>

namespace facet::render {

namespace {

using LoadFn = bool (*)(const std::string&, const TexelImageOptions&, const std::string&,
                        TexelImage&, std::string&);
using LoadMemoryFn = bool (*)(const std::string&, const unsigned char*, std::size_t,
                              const TexelImageOptions&, const std::string&, TexelImage&,
                              std::string&);
using LoadRowsFn = bool (*)(const std::string&, const unsigned char*, std::size_t, bool,
                            const TexelImageOptions&, const std::string&, const TexelRowSink&,
                            TexelImage&, std::string&);

// The module's entry points, looked up once.
struct Module {
    LoadFn load = nullptr;
    LoadMemoryFn load_memory = nullptr;
    LoadRowsFn load_rows = nullptr;
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
            r.load_rows =
                reinterpret_cast<LoadRowsFn>(dlsym(h, "facet_oiio_load_texel_image_rows"));
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

TexelImage load_texel_image_rows(const std::string& path, std::span<const unsigned char>* bytes,
                                 const TexelImageOptions& options, const std::string& where,
                                 const TexelRowSink& sink) {
    const LoadRowsFn fn = module().load_rows;
    if (!fn) unavailable(where, path);
    TexelImage out;
    std::string error;
    if (!fn(path, bytes ? bytes->data() : nullptr, bytes ? bytes->size() : 0, bytes != nullptr,
            options, where, sink, out, error))
        throw TexelImageError(error);
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

// One level transition of MipChain: the separable box filter from src_w x src_h to
// dst_w x dst_h, along x per incoming row, then along y over a window of x-filtered rows.
struct MipChain::Stage {
    int dst_w = 0, dst_h = 0;
    std::vector<BoxTap> tx, ty;
    int next_in = 0, next_out = 0;
    int window_first = 0;  // source row of window[0]
    std::deque<std::vector<float>> window;
    std::vector<float> out;
};

std::vector<std::pair<int, int>> MipChain::level_sizes(int width, int height) {
    std::vector<std::pair<int, int>> sizes{{width, height}};
    while (width > 1 || height > 1) {
        width = std::max(1, width / 2);
        height = std::max(1, height / 2);
        sizes.emplace_back(width, height);
    }
    return sizes;
}

MipChain::MipChain(int width, int height, int channels, Emit emit)
    : m_channels(channels), m_emit(std::move(emit)) {
    const auto sizes = level_sizes(width, height);
    for (std::size_t l = 0; l + 1 < sizes.size(); ++l) {
        auto s = std::make_unique<Stage>();
        s->dst_w = sizes[l + 1].first;
        s->dst_h = sizes[l + 1].second;
        s->tx = box_taps(sizes[l].first, s->dst_w);
        s->ty = box_taps(sizes[l].second, s->dst_h);
        m_stages.push_back(std::move(s));
    }
}

MipChain::~MipChain() = default;

void MipChain::push_row(const float* row) {
    push(0, row);
}

void MipChain::push(std::size_t k, const float* row) {
    if (k >= m_stages.size()) return;
    Stage& s = *m_stages[k];
    const std::size_t c = std::size_t(m_channels), n = std::size_t(s.dst_w) * c;
    // Along x: each output texel sums its weighted source texels in order, from 0.
    std::vector<float> xr(n, 0.f);
    for (int x = 0; x < s.dst_w; ++x) {
        const BoxTap& t = s.tx[std::size_t(x)];
        float* out = &xr[std::size_t(x) * c];
        for (std::size_t j = 0; j < t.weights.size(); ++j)
            for (std::size_t ch = 0; ch < c; ++ch)
                out[ch] += t.weights[j] * row[(std::size_t(t.first) + j) * c + ch];
    }
    s.window.push_back(std::move(xr));
    const int y = s.next_in++;
    // Along y: every output row whose source rows have all arrived, in order.
    while (s.next_out < s.dst_h) {
        const BoxTap& t = s.ty[std::size_t(s.next_out)];
        if (t.first + int(t.weights.size()) - 1 > y) break;
        s.out.assign(n, 0.f);
        for (std::size_t j = 0; j < t.weights.size(); ++j) {
            const float* in = s.window[std::size_t(t.first - s.window_first) + j].data();
            for (std::size_t i = 0; i < n; ++i) s.out[i] += t.weights[j] * in[i];
        }
        const int emitted = s.next_out++;
        const int keep = s.next_out < s.dst_h ? s.ty[std::size_t(s.next_out)].first : y + 1;
        while (s.window_first < keep && !s.window.empty()) {
            s.window.pop_front();
            ++s.window_first;
        }
        m_emit(int(k) + 1, emitted, s.out.data());
        push(k + 1, s.out.data());
    }
}

std::uint64_t pyramid_bytes(int width, int height, int channels) {
    std::uint64_t n = 0;
    for (const auto& [w, h] : MipChain::level_sizes(width, height))
        n += std::uint64_t(w) * std::uint64_t(h) * std::uint64_t(channels) * sizeof(float);
    return n;
}

std::vector<TexelImage> build_mip_levels(const TexelImage& image) {
    const auto sizes = MipChain::level_sizes(image.width, image.height);
    std::vector<TexelImage> levels(sizes.size() - 1);
    const std::size_t c = std::size_t(image.channels);
    for (std::size_t l = 0; l < levels.size(); ++l) {
        TexelImage& d = levels[l];
        d.path = image.path;
        d.width = sizes[l + 1].first;
        d.height = sizes[l + 1].second;
        d.channels = image.channels;
        d.alpha_channel = image.alpha_channel;
        d.float_format = image.float_format;
        d.color_space = image.color_space;
        d.texels.resize(std::size_t(d.width) * std::size_t(d.height) * c);
    }
    MipChain chain(image.width, image.height, image.channels,
                   [&](int level, int y, const float* row) {
                       TexelImage& d = levels[std::size_t(level - 1)];
                       const std::size_t n = std::size_t(d.width) * c;
                       std::copy_n(row, n, d.texels.data() + std::size_t(y) * n);
                   });
    const std::size_t row = std::size_t(image.width) * c;
    for (int y = 0; y < image.height; ++y)
        chain.push_row(image.texels.data() + std::size_t(y) * row);
    return levels;
}

void TexelImageCache::reserve(std::uint64_t add, const std::string& where,
                              const std::string& path) {
    if (m_bytes + add > m_limit) {
        throw TexelImageError(where + ": " + path + ": texture memory would reach " +
                              mib(m_bytes + add) + " (" + mib(add) +
                              " more for this file), above the limit of " + mib(m_limit) +
                              " (an in-memory image cannot be paged; raise it with "
                              "`facet render --texture-memory MIB` or "
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

// Whole while the whole images fit limit - reserve; else paged (texel_image.h conventions).
std::shared_ptr<const TexelImage> TexelImageCache::load(const std::string& path,
                                                        std::span<const unsigned char>* bytes,
                                                        const TexelImageOptions& options,
                                                        const std::string& where) {
    constexpr std::uint64_t kMaxTileReserve = std::uint64_t(64) << 20;
    std::unique_ptr<PagedImageWriter> writer;
    TexelRowSink sink;
    sink.stream = [&](const TexelImage& header) {
        const std::uint64_t need = pyramid_bytes(header.width, header.height, header.channels);
        const std::uint64_t reserve = std::min(m_limit / 4, kMaxTileReserve);
        if (!m_paging && m_bytes + need <= m_limit - reserve) {
            m_bytes += need;
            return false;
        }
        if (!m_tiles) m_tiles = std::make_shared<TileCache>(m_limit - m_bytes);
        writer = std::make_unique<PagedImageWriter>(header, m_tiles, where);
        m_paging = true;
        return true;
    };
    sink.rows = [&](int first_row, int rows, const float* texels) {
        writer->add_rows(first_row, rows, texels);
    };
    TexelImage image = load_texel_image_rows(path, bytes, options, where, sink);
    if (writer) {
        image.paged = writer->finish();
        ++m_paged;
    }
    return std::make_shared<const TexelImage>(std::move(image));
}

std::shared_ptr<const TexelImage> TexelImageCache::get_memory(const std::string& name,
                                                              std::span<const unsigned char> bytes,
                                                              const TexelImageOptions& options,
                                                              const std::string& where) {
    const auto key = std::make_tuple(name, int(options.color_space), options.reject_negative);
    std::lock_guard lock(m_mutex);
    auto it = m_images.find(key);
    if (it != m_images.end()) return it->second;
    auto image = load(name, &bytes, options, where);
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
    auto image = load(path, nullptr, options, where);
    m_images.emplace(key, image);
    return image;
}

std::shared_ptr<const TexelImage> TexelImageCache::adopt(std::shared_ptr<const TexelImage> image,
                                                         const std::string& where) {
    std::lock_guard lock(m_mutex);
    if (m_adopted.count(image.get())) return image;
    reserve(pyramid_bytes(image->width, image->height, image->channels), where, image->path);
    m_adopted.emplace(image.get(), image);
    return image;
}

std::shared_ptr<const std::vector<TexelImage>> TexelImageCache::mip_levels(
    const std::shared_ptr<const TexelImage>& image, const std::string& where) {
    (void)where;  // counted when the image was loaded or adopted
    std::lock_guard lock(m_mutex);
    auto it = m_mips.find(image.get());
    if (it != m_mips.end()) return it->second;
    auto levels = std::make_shared<const std::vector<TexelImage>>(
        image->paged ? std::vector<TexelImage>{} : build_mip_levels(*image));
    m_mips.emplace(image.get(), levels);
    return levels;
}

TextureMemoryStats TexelImageCache::stats() const {
    std::lock_guard lock(m_mutex);
    TextureMemoryStats s;
    s.limit = m_limit;
    s.whole_bytes = m_bytes;
    s.paged_images = m_paged;
    if (m_tiles) m_tiles->stats(s);
    return s;
}

std::shared_ptr<const TileCache> TexelImageCache::tile_cache() const {
    std::lock_guard lock(m_mutex);
    return m_tiles;
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
