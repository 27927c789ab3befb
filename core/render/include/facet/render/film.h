// The film: per-pixel sums of radiance samples and sample counts over a region of the image,
// resolved to an Image by a box filter; and render parts (a film saved with what it covers),
// which merge into exactly the image one render gives.
//
// Conventions:
//  - Sums are FIXED POINT: each sample's float RGB value is converted exactly (truncated below
//    2^-kFixedFracBits, ~8.7e-19) to a signed 128-bit integer with kFixedFracBits fraction bits
//    and added as an integer. Integer addition is associative, so a pixel's sum does not depend
//    on the order in which its samples, tiles, passes, threads or parts were added: splitting a
//    render by region or by sample range and merging the parts gives the single render's image
//    bit for bit. (Double-precision sums, as before, depend on the summation order.)
//  - A sample is accepted when it is finite and every channel is below kMaxSampleValue (2^46,
//    7.0e13 W sr^-1 m^-2); others are dropped and counted by the kernel (RenderStats::nonfinite).
//    With at most 2^20 samples per pixel a sum then stays below 2^66, far from overflow.
//  - The image is sum * 2^-kFixedFracBits (exact, in double) / count per pixel, rounded to float;
//    pixels with no samples are black.
//  - Alpha (film transparency and holdouts, integrator.h): a film made with alpha also sums each
//    sample's coverage (1 - the background's share, a float in [0, 1]) in the same fixed
//    point, so alpha splits and merges exactly as the colour does. The image's alpha is the
//    mean, clamped to [0, 1] (0 where no sample was taken). A film without alpha has no such
//    sums and costs nothing more.
//  - Shadow catcher (integrator.h, "Shadow catcher"; Cycles 3.4's approximate shadow catcher):
//    a film made for a scene with a catcher also sums, per pixel, kCatcherSums fixed-point
//    values (CatcherSums): the "matte" (each sample's radiance before its path met a catcher,
//    or all of it when it met none), the radiance of the catcher-only paths, the environment
//    the see-through camera paths see (where they escape, or straight behind the catcher: Cycles'
//    background pass), the transparency the split left to the matte, and the number of
//    samples that met a catcher. resolve() then gives Cycles' Combined pass: the ratio
//    r = (sum - matte) / catcher per channel (1 where the catcher sum is 0 or no sample met a
//    catcher) is the light the catcher kept; over a transparent film with combined coverage
//    a_c, r' = 1 - a_c + a_c r; the matte's alpha a_m = clamp(1 - T_m) (T_m: the split's share
//    plus the film's own transparency 1 - a_c) gives alpha (1 - a_m)(1 - clamp(mean r')) + a_m
//    with the matte's colour; an opaque film shows matte + background (1 - that alpha).
//  - The Shadow Catcher pass (Cycles 3.4's PASS_SHADOW_CATCHER, film_calculate_shadow_catcher;
//    Blender's View Layer > Passes > Light > Shadow Catcher): per channel r' above, unclamped
//    (1 in pixels no sample of which met a catcher, and in every pixel of a film without
//    catcher sums). With the pass, Cycles' Combined is no longer the approximation: it is the
//    matte with its own alpha a_m, over a transparent or an opaque film alike (a catcher seen
//    directly is a colourless hole); resolve(true) gives that (with an alpha channel).
//  - A Film covers `region` (half-open pixel rectangle of the full image), row-major inside it.
//    Each pixel is written by one tile at a time; no synchronisation is needed.
#pragma once

#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "facet/render/image.h"
#include "facet/types.h"

namespace facet::render {

__extension__ typedef __int128 FixedSum;  // GCC/Clang 128-bit integer

inline constexpr int kFixedFracBits = 60;
inline constexpr float kMaxSampleValue = 0x1p46f;

struct FixedRgb {
    FixedSum c[3] = {0, 0, 0};
    FixedRgb& operator+=(const FixedRgb& o) {
        c[0] += o.c[0];
        c[1] += o.c[1];
        c[2] += o.c[2];
        return *this;
    }
    bool operator==(const FixedRgb&) const = default;
};

// to_fixed by bit arithmetic: for every |v| < 2^(127 - kFixedFracBits) (see to_fixed).
inline FixedSum to_fixed_bits(float v) {
    std::uint32_t bits;
    __builtin_memcpy(&bits, &v, 4);
    const int e = int((bits >> 23) & 0xffu);
    const std::uint32_t m = (bits & 0x7fffffu) | (e != 0 ? 0x800000u : 0u);
    // v = m * 2^(max(e, 1) - 150); in fixed point m * 2^(max(e, 1) - 150 + kFixedFracBits).
    const int shift = (e != 0 ? e : 1) - 150 + kFixedFracBits;
    FixedSum r = 0;
    if (shift >= 0)
        r = FixedSum(m) << shift;
    else if (shift > -32)
        r = FixedSum(m >> -shift);
    return (bits >> 31) ? -r : r;
}

// Exact fixed-point value of a float with |v| < 2^(127 - kFixedFracBits), truncated toward zero
// below 2^-kFixedFracBits, with no float-to-int128 library call per sample. Below
// 2^(63 - kFixedFracBits) (the common case) v 2^kFixedFracBits fits an int64 and the double
// product is exact (a float times a power of two), so the hardware's truncating conversion gives
// the integer to_fixed_bits gives; larger values take the bit arithmetic.
inline FixedSum to_fixed(float v) {
    constexpr float kInt64Limit = float(std::int64_t(1) << (63 - kFixedFracBits));
    constexpr double kScale = double(std::int64_t(1) << kFixedFracBits);
    if (std::fabs(v) < kInt64Limit) [[likely]]
        return FixedSum(std::int64_t(double(v) * kScale));
    return to_fixed_bits(v);
}
double from_fixed(FixedSum s);  // s * 2^-kFixedFracBits, correctly rounded to double

// Is the sample accepted into the film (see conventions)?
inline bool film_accepts(const Rgb& v) {
    return std::fabs(v.x) < kMaxSampleValue && std::fabs(v.y) < kMaxSampleValue &&
           std::fabs(v.z) < kMaxSampleValue;  // false for NaN too
}

// Half-open pixel rectangle [x0, x1) x [y0, y1).
struct Region {
    int x0 = 0, y0 = 0, x1 = 0, y1 = 0;
    int width() const { return x1 - x0; }
    int height() const { return y1 - y0; }
    bool empty() const { return x1 <= x0 || y1 <= y0; }
    bool contains(int x, int y) const { return x >= x0 && x < x1 && y >= y0 && y < y1; }
    bool intersects(const Region& o) const {
        return x0 < o.x1 && o.x0 < x1 && y0 < o.y1 && o.y0 < y1;
    }
    bool operator==(const Region&) const = default;
};

// A pixel's shadow-catcher sums (see conventions): the film's layout, kCatcherSums values a
// pixel, and what the kernel adds per camera sample.
struct CatcherSums {
    static constexpr std::size_t kMatte = 0, kCatcher = 3, kBackground = 6, kSplitT = 9,
                                 kCount = 10;
};
inline constexpr std::size_t kCatcherSums = 11;

class Film {
  public:
    Film() = default;
    explicit Film(const Region& region, bool alpha = false, bool catcher = false)
        : m_region(region),
          m_sums(std::size_t(region.width()) * std::size_t(region.height())),
          m_counts(m_sums.size(), 0u),
          m_alpha(alpha ? m_sums.size() : 0u, FixedSum(0)),
          m_catcher(catcher ? m_sums.size() * kCatcherSums : 0u, FixedSum(0)) {}

    const Region& region() const { return m_region; }
    int width() const { return m_region.width(); }
    int height() const { return m_region.height(); }
    // Row-major over the region: index (y - y0) * width + (x - x0).
    FixedRgb* sums() { return m_sums.data(); }
    const std::vector<FixedRgb>& sum_values() const { return m_sums; }
    std::uint32_t* counts() { return m_counts.data(); }
    const std::vector<std::uint32_t>& count_values() const { return m_counts; }
    // The coverage sums (see conventions), same layout; null / empty without alpha.
    bool has_alpha() const { return !m_alpha.empty(); }
    FixedSum* alpha_sums() { return m_alpha.empty() ? nullptr : m_alpha.data(); }
    const std::vector<FixedSum>& alpha_values() const { return m_alpha; }
    // The shadow catcher's sums (see conventions), kCatcherSums a pixel in the same order;
    // null / empty for a scene without a catcher.
    bool has_catcher() const { return !m_catcher.empty(); }
    FixedSum* catcher_sums() { return m_catcher.empty() ? nullptr : m_catcher.data(); }
    const std::vector<FixedSum>& catcher_values() const { return m_catcher; }

    // Mean radiance per pixel of the region (black where no sample was taken). With
    // `shadow_catcher_pass` a film with catcher sums gives Cycles' Combined pass of a render
    // with the Shadow Catcher pass (the matte and its alpha, see conventions); other films
    // resolve the same either way.
    Image resolve(bool shadow_catcher_pass = false) const;
    // The Shadow Catcher pass (see conventions): RGB, no alpha.
    Image resolve_shadow_catcher_pass() const;
    // Adds another film's sums and counts over its region, which must lie inside this one's;
    // both have alpha or neither.
    void add(const Film& other);

  private:
    // The catcher's Combined pass (see conventions): the approximation, or with the pass the
    // matte and its alpha.
    void resolve_catcher(Image& img, bool shadow_catcher_pass) const;
    // Pixel i's light kept per channel, r' (see conventions); its combined coverage a_c in
    // `coverage` (unclamped; 1 without alpha).
    void catcher_ratio(std::size_t i, double r[3], double& coverage) const;

    Region m_region;
    std::vector<FixedRgb> m_sums;
    std::vector<std::uint32_t> m_counts;
    std::vector<FixedSum> m_alpha;
    std::vector<FixedSum> m_catcher;
};

// What a part covers and which render it belongs to; merge() checks these.
struct PartInfo {
    std::string scene;                     // scene name (for messages only)
    std::uint64_t fingerprint = 0;         // scene description + image-changing render settings
    int width = 0, height = 0;             // the full image
    Region region;                         // pixels covered
    int sample_begin = 0, sample_end = 0;  // samples [begin, end) of every pixel of the region
    std::uint64_t seed = 0;
};

struct RenderPart {
    PartInfo info;
    Film film;  // over info.region; every count == sample_end - sample_begin
};

// Part files ("facet-part" version 1, extension .fpart): the line "FACETPART 1", one line of
// JSON with the PartInfo fields, then per pixel of the region, row-major, three little-endian
// signed 128-bit sums (R, G, B; low 64 bits first) — counts are implied by the sample range.
// A film with alpha is written as version 2: the header adds "alpha": true and each pixel a
// fourth sum (the coverage) after B. Films without alpha are still written as version 1.
// A film with a shadow catcher's sums is written as version 3: the header has "alpha" (true or
// false) and "shadow_catcher": true, and each pixel, after its colour (and coverage) sums, its
// kCatcherSums catcher sums in CatcherSums order.
// Errors throw std::runtime_error naming the file.
void write_part(const RenderPart& part, const std::string& path);
RenderPart read_part(const std::string& path);

// Assembles parts into the full image. Every part must have the same fingerprint, seed and
// image size; no two parts may cover a sample of a pixel twice; every pixel must end up with
// samples [0, N) for one N. Violations throw std::runtime_error naming the part (by `names[i]`)
// or the pixel. The result equals the film of one render of samples [0, N), bit for bit.
Film merge_parts(const std::vector<RenderPart>& parts, const std::vector<std::string>& names);

}  // namespace facet::render
