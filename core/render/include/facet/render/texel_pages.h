// Paged images: a texture's MIP pyramid in a tiled spill file, read through a shared tile cache
// bounded in bytes (texel_image.h, "Memory bound"; docs/textures.md, "Texture memory").
//
// Conventions:
//  - Tiles are kTileSize x kTileSize texels of one MIP level (narrower at the right and bottom
//    edges), float, row-major within the tile, channels interleaved: the same values as the
//    whole image's `texels` and build_mip_levels, bit for bit (MipChain).
//  - Spill file: one per paged image, created in $FACET_TEXTURE_CACHE_DIR or else the system's
//    temporary directory and unlinked at once, so it disappears with the process. Level l's
//    tiles follow level l - 1's; within a level, bands of kTileSize rows top to bottom, each
//    band its tiles left to right.
//  - TileCache: a thread-safe LRU cache split into shards by a hash of (image, level, tile),
//    each with capacity / shards bytes, so the bytes resident never pass the capacity. A
//    look-up copies the texel out under its shard's lock: no tile is pinned while a thread
//    filters, so eviction never waits and never frees memory in use. A tile larger than a
//    shard is read from the file per texel, uncached.
//  - Reading the spill file can only fail on an I/O error of the machine (the file is ours);
//    then the process reports it and aborts (a render never returns wrong texels).
#pragma once

#include <atomic>
#include <cstdint>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "facet/render/texel_image.h"

namespace facet::render {

constexpr int kTileSize = 64;
// Paged images have at most this many channels (more stay whole or are an error).
constexpr int kMaxPagedChannels = 16;

class PagedImage;

class TileCache {
  public:
    explicit TileCache(std::uint64_t capacity);
    ~TileCache();
    TileCache(const TileCache&) = delete;
    TileCache& operator=(const TileCache&) = delete;
    // Copies texel (x, y) of `level` of `image` (all its channels) to `out`.
    void texel(const PagedImage& image, int level, int x, int y, float* out) const;
    std::uint64_t capacity() const { return m_capacity; }
    // tile_capacity, tile_bytes, tile_peak; adds hits, misses, evictions (TextureMemoryStats).
    void stats(TextureMemoryStats& s) const;
    std::uint32_t next_image_id() { return m_next_id++; }

  private:
    struct Shard;
    std::uint64_t m_capacity;
    std::vector<std::unique_ptr<Shard>> m_shards;
    mutable std::atomic<std::uint64_t> m_resident{0}, m_peak{0};
    std::atomic<std::uint32_t> m_next_id{0};
};

class PagedImage {
  public:
    struct Level {
        int width = 0, height = 0;
        std::uint64_t offset = 0;  // in floats, from the start of the spill file
    };
    ~PagedImage();
    PagedImage(const PagedImage&) = delete;
    PagedImage& operator=(const PagedImage&) = delete;
    int channels() const { return m_channels; }
    int levels() const { return int(m_levels.size()); }  // level 0 included
    const Level& level(int l) const { return m_levels[std::size_t(l)]; }
    // Texel (x, y) of level l (indices in range), all channels, to `out`.
    void texel(int l, int x, int y, float* out) const { m_cache->texel(*this, l, x, y, out); }
    // Every row of level 0 in order, each width * channels floats, read from the spill file
    // past the cache (a texture's value range, computed once when it is built).
    void for_each_row(const std::function<void(const float* row)>& fn) const;
    // Reads `count` floats at float offset `at` of the spill file (aborts on an I/O error).
    void read(std::uint64_t at, std::size_t count, float* out) const;
    std::uint32_t id() const { return m_id; }
    const std::string& path() const { return m_path; }

  private:
    friend class PagedImageWriter;
    PagedImage() = default;
    std::string m_path;
    int m_channels = 0;
    int m_fd = -1;
    std::uint32_t m_id = 0;
    std::vector<Level> m_levels;
    std::shared_ptr<const TileCache> m_cache;
};

// Builds a PagedImage from level 0's rows as a streaming reader delivers them (TexelRowSink):
// MipChain computes the levels, and each level's bands of kTileSize rows go to the spill file
// as tiles. Throws TexelImageError naming `where` and the image when the file cannot be made
// or written (e.g. the disk is full).
class PagedImageWriter {
  public:
    PagedImageWriter(const TexelImage& header, std::shared_ptr<TileCache> cache,
                     const std::string& where);
    ~PagedImageWriter();
    void add_rows(int first_row, int rows, const float* texels);
    std::shared_ptr<const PagedImage> finish();

  private:
    struct Band;
    void add_level_row(int level, const float* row);
    std::string m_where;
    std::shared_ptr<PagedImage> m_image;
    std::vector<Band> m_bands;
    std::unique_ptr<MipChain> m_chain;
};

}  // namespace facet::render
