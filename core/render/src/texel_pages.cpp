// Paged images and the tile cache (conventions in facet/render/texel_pages.h).
#include "facet/render/texel_pages.h"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <list>
#include <unordered_map>

namespace facet::render {

namespace {

// Tile key: image id (16 bits), level (6), tile row (21), tile column (21).
std::uint64_t tile_key(std::uint32_t image, int level, int tx, int ty) {
    return (std::uint64_t(image) << 48) | (std::uint64_t(level) << 42) | (std::uint64_t(ty) << 21) |
           std::uint64_t(tx);
}

// splitmix64's finaliser: spreads neighbouring tiles over the shards.
std::uint64_t mix(std::uint64_t z) {
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
}

// Shards of at least 256 KiB (four 64^2 RGBA tiles), at most 64.
constexpr std::uint64_t kMinShardBytes = std::uint64_t(256) << 10;
constexpr std::size_t kMaxShards = 64;

// Where tile (tx, ty) of a level starts (floats from the level's start) and its size.
struct TileSpan {
    std::uint64_t at;
    int width, height;
};

TileSpan tile_span(const PagedImage::Level& lv, int channels, int tx, int ty) {
    const int th = std::min(kTileSize, lv.height - ty * kTileSize);
    const int tw = std::min(kTileSize, lv.width - tx * kTileSize);
    const std::uint64_t band = std::uint64_t(ty) * kTileSize * std::uint64_t(lv.width);
    return {(band + std::uint64_t(th) * std::uint64_t(tx) * kTileSize) * std::uint64_t(channels),
            tw, th};
}

}  // namespace

struct TileCache::Shard {
    struct Entry {
        std::uint64_t key;
        std::unique_ptr<float[]> texels;
        std::uint64_t bytes;
    };
    std::mutex mutex;
    std::uint64_t capacity = 0, bytes = 0, hits = 0, misses = 0, evictions = 0;
    std::list<Entry> lru;  // most recently used first
    std::unordered_map<std::uint64_t, std::list<Entry>::iterator> index;
};

TileCache::TileCache(std::uint64_t capacity) : m_capacity(capacity) {
    const std::size_t n =
        std::clamp<std::size_t>(std::size_t(capacity / kMinShardBytes), 1, kMaxShards);
    for (std::size_t i = 0; i < n; ++i) {
        m_shards.push_back(std::make_unique<Shard>());
        m_shards.back()->capacity = capacity / n;
    }
}

TileCache::~TileCache() = default;

void TileCache::texel(const PagedImage& image, int level, int x, int y, float* out) const {
    const int c = image.channels();
    const int tx = x / kTileSize, ty = y / kTileSize;
    const PagedImage::Level& lv = image.level(level);
    const TileSpan span = tile_span(lv, c, tx, ty);
    const std::uint64_t bytes =
        std::uint64_t(span.width) * std::uint64_t(span.height) * std::uint64_t(c) * sizeof(float);
    const std::size_t in_tile = (std::size_t(y - ty * kTileSize) * std::size_t(span.width) +
                                 std::size_t(x - tx * kTileSize)) *
                                std::size_t(c);
    const std::uint64_t key = tile_key(image.id(), level, tx, ty);
    Shard& s = *m_shards[mix(key) % m_shards.size()];
    std::lock_guard lock(s.mutex);
    if (auto it = s.index.find(key); it != s.index.end()) {
        ++s.hits;
        s.lru.splice(s.lru.begin(), s.lru, it->second);
        std::memcpy(out, it->second->texels.get() + in_tile, std::size_t(c) * sizeof(float));
        return;
    }
    ++s.misses;
    if (bytes > s.capacity) {  // larger than the shard: this texel alone, uncached
        image.read(lv.offset + span.at + in_tile, std::size_t(c), out);
        return;
    }
    while (s.bytes + bytes > s.capacity) {
        Shard::Entry& victim = s.lru.back();
        s.bytes -= victim.bytes;
        m_resident.fetch_sub(victim.bytes, std::memory_order_relaxed);
        s.index.erase(victim.key);
        s.lru.pop_back();
        ++s.evictions;
    }
    auto texels = std::make_unique<float[]>(bytes / sizeof(float));
    image.read(lv.offset + span.at, bytes / sizeof(float), texels.get());
    std::memcpy(out, texels.get() + in_tile, std::size_t(c) * sizeof(float));
    s.lru.push_front({key, std::move(texels), bytes});
    s.index.emplace(key, s.lru.begin());
    s.bytes += bytes;
    const std::uint64_t now = m_resident.fetch_add(bytes, std::memory_order_relaxed) + bytes;
    std::uint64_t peak = m_peak.load(std::memory_order_relaxed);
    while (now > peak && !m_peak.compare_exchange_weak(peak, now, std::memory_order_relaxed)) {
    }
}

void TileCache::stats(TextureMemoryStats& out) const {
    out.tile_capacity = m_capacity;
    out.tile_bytes = m_resident.load();
    out.tile_peak = m_peak.load();
    for (const auto& s : m_shards) {
        std::lock_guard lock(s->mutex);
        out.hits += s->hits;
        out.misses += s->misses;
        out.evictions += s->evictions;
    }
}

PagedImage::~PagedImage() {
    if (m_fd >= 0) ::close(m_fd);
}

void PagedImage::read(std::uint64_t at, std::size_t count, float* out) const {
    auto* dst = reinterpret_cast<char*>(out);
    std::size_t left = count * sizeof(float);
    off_t pos = off_t(at * sizeof(float));
    while (left > 0) {
        const ssize_t got = ::pread(m_fd, dst, left, pos);
        if (got <= 0) {
            if (got < 0 && errno == EINTR) continue;
            std::fprintf(stderr, "facet: texture cache: cannot read the spill file of %s: %s\n",
                         m_path.c_str(), got < 0 ? std::strerror(errno) : "end of file");
            std::abort();
        }
        dst += got;
        left -= std::size_t(got);
        pos += got;
    }
}

void PagedImage::for_each_row(const std::function<void(const float* row)>& fn) const {
    const Level& lv = m_levels[0];
    const std::size_t c = std::size_t(m_channels), w = std::size_t(lv.width);
    std::vector<float> band, rows;
    for (int ty = 0; ty * kTileSize < lv.height; ++ty) {
        const int th = std::min(kTileSize, lv.height - ty * kTileSize);
        band.resize(std::size_t(th) * w * c);
        read(lv.offset + tile_span(lv, m_channels, 0, ty).at, band.size(), band.data());
        rows.resize(band.size());
        // Tiles (band order) back to rows.
        for (int tx = 0; tx * kTileSize < lv.width; ++tx) {
            const TileSpan sp = tile_span(lv, m_channels, tx, ty);
            const float* tile = band.data() + (sp.at - tile_span(lv, m_channels, 0, ty).at);
            for (int y = 0; y < th; ++y)
                std::copy_n(tile + std::size_t(y) * std::size_t(sp.width) * c,
                            std::size_t(sp.width) * c,
                            rows.data() + (std::size_t(y) * w + std::size_t(tx) * kTileSize) * c);
        }
        for (int y = 0; y < th; ++y) fn(rows.data() + std::size_t(y) * w * c);
    }
}

// One level's band of kTileSize rows being filled, written out as tiles when full.
struct PagedImageWriter::Band {
    int rows = 0, next_row = 0;
    std::vector<float> texels;  // rows x width x channels, row-major
    std::vector<float> tiles;   // the same in tile order
};

PagedImageWriter::PagedImageWriter(const TexelImage& header, std::shared_ptr<TileCache> cache,
                                   const std::string& where)
    : m_where(where), m_image(std::shared_ptr<PagedImage>(new PagedImage())) {
    PagedImage& im = *m_image;
    im.m_path = header.path;
    im.m_channels = header.channels;
    im.m_id = cache->next_image_id();
    if (header.channels > kMaxPagedChannels || im.m_id >= (1u << 16) ||
        header.width / kTileSize >= (1 << 21) || header.height / kTileSize >= (1 << 21))
        throw TexelImageError(where + ": " + header.path +
                              ": this image cannot be paged (more than 16 channels, 2^27 texels "
                              "a side, or 65536 paged images) and does not fit the texture "
                              "memory bound");
    std::uint64_t at = 0;
    for (const auto& [w, h] : MipChain::level_sizes(header.width, header.height)) {
        im.m_levels.push_back({w, h, at});
        at += std::uint64_t(w) * std::uint64_t(h) * std::uint64_t(header.channels);
    }
    m_bands.resize(im.m_levels.size());
    im.m_cache = std::move(cache);
    const char* env = std::getenv("FACET_TEXTURE_CACHE_DIR");
    std::error_code ec;
    const std::string dir =
        env && *env ? std::string(env) : std::filesystem::temp_directory_path(ec).string();
    std::string name = dir + "/facet-texture-XXXXXX";
    im.m_fd = ::mkstemp(name.data());
    if (im.m_fd < 0)
        throw TexelImageError(where + ": " + header.path + ": cannot create a texture spill file " +
                              "in " + dir +
                              " (set FACET_TEXTURE_CACHE_DIR): " + std::strerror(errno));
    ::unlink(name.c_str());
    m_chain = std::make_unique<MipChain>(
        header.width, header.height, header.channels,
        [this](int level, int, const float* row) { add_level_row(level, row); });
}

PagedImageWriter::~PagedImageWriter() = default;

void PagedImageWriter::add_level_row(int level, const float* row) {
    PagedImage& im = *m_image;
    const PagedImage::Level& lv = im.m_levels[std::size_t(level)];
    const std::size_t c = std::size_t(im.m_channels), w = std::size_t(lv.width);
    Band& b = m_bands[std::size_t(level)];
    const int ty = b.next_row / kTileSize;
    const int th = std::min(kTileSize, lv.height - ty * kTileSize);
    if (b.rows == 0) b.texels.resize(std::size_t(th) * w * c);
    std::copy_n(row, w * c, b.texels.data() + std::size_t(b.rows) * w * c);
    ++b.rows;
    ++b.next_row;
    if (b.rows < th) return;
    // The band is complete: reorder into tiles and write it in one piece.
    const std::uint64_t band_at = tile_span(lv, im.m_channels, 0, ty).at;
    b.tiles.resize(b.texels.size());
    for (int tx = 0; tx * kTileSize < lv.width; ++tx) {
        const TileSpan sp = tile_span(lv, im.m_channels, tx, ty);
        float* tile = b.tiles.data() + (sp.at - band_at);
        for (int y = 0; y < th; ++y)
            std::copy_n(b.texels.data() + (std::size_t(y) * w + std::size_t(tx) * kTileSize) * c,
                        std::size_t(sp.width) * c,
                        tile + std::size_t(y) * std::size_t(sp.width) * c);
    }
    const char* src = reinterpret_cast<const char*>(b.tiles.data());
    std::size_t left = b.tiles.size() * sizeof(float);
    off_t pos = off_t((lv.offset + band_at) * sizeof(float));
    while (left > 0) {
        const ssize_t put = ::pwrite(im.m_fd, src, left, pos);
        if (put < 0 && errno == EINTR) continue;
        if (put <= 0)
            throw TexelImageError(m_where + ": " + im.m_path +
                                  ": cannot write the texture spill file (set "
                                  "FACET_TEXTURE_CACHE_DIR to a disk with room): " +
                                  std::strerror(put < 0 ? errno : ENOSPC));
        src += put;
        left -= std::size_t(put);
        pos += put;
    }
    b.rows = 0;
}

void PagedImageWriter::add_rows(int first_row, int rows, const float* texels) {
    (void)first_row;  // rows arrive in order (TexelRowSink)
    const std::size_t row =
        std::size_t(m_image->m_levels[0].width) * std::size_t(m_image->m_channels);
    for (int r = 0; r < rows; ++r) {
        const float* p = texels + std::size_t(r) * row;
        add_level_row(0, p);
        m_chain->push_row(p);
    }
}

std::shared_ptr<const PagedImage> PagedImageWriter::finish() {
    for (std::size_t l = 0; l < m_bands.size(); ++l)
        if (m_bands[l].next_row != m_image->m_levels[l].height)
            throw TexelImageError(m_where + ": " + m_image->m_path + ": the image ended after " +
                                  std::to_string(m_bands[l].next_row) + " rows of level " +
                                  std::to_string(l));
    m_chain.reset();
    return m_image;
}

}  // namespace facet::render
