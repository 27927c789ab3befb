// Low-discrepancy sample generation: Owen-scrambled Sobol points with no direction-number
// tables, after Burley 2020, "Practical Hash-based Owen Scrambling" (JCGT 9(4)).
//
// Conventions:
//  - Every sample value is a pure function of (pixel, sample index, dimension, seed): no state
//    is shared between pixels or threads, so images do not depend on the thread count or on the
//    order in which tiles are rendered.
//  - Dimensions are consumed in order by get_1d() / get_2d(); each call uses one dimension
//    (get_2d uses one *pair*). Integrators must consume dimensions in the same order for a given
//    path vertex so that a vertex's samples stay stratified across the pixel's sample indices.
//  - 2D samples come from the first two Sobol dimensions, which form a (0,2)-sequence: every
//    power-of-two prefix of the sample indices is stratified in every elementary interval.
//    Each dimension pair gets its own index shuffle (a nested uniform scramble of the index)
//    and its own Owen scramble of the point, both seeded by hashing pixel, dimension and seed.
//    This "padding" of independent 2D sequences avoids the correlation of high Sobol dimensions.
//  - Values lie in [0, 1): they are 24-bit fixed-point, so 1 - 2^-24 is the largest value.
#pragma once

#include <array>
#include <cstdint>

#include "facet/types.h"

namespace facet::render {

// The sample generator runs several times per path vertex; GCC declines to inline these small
// functions into the large integrator kernels without being told (they showed up as 20% of a
// Cornell-box profile as out-of-line calls).
#define FACET_SAMPLER_INLINE [[gnu::always_inline]] inline

// Bit reversal of a 32-bit word (byte swap, then the bits within each byte).
FACET_SAMPLER_INLINE std::uint32_t reverse_bits(std::uint32_t x) {
    x = __builtin_bswap32(x);
    x = ((x >> 1) & 0x55555555u) | ((x & 0x55555555u) << 1);
    x = ((x >> 2) & 0x33333333u) | ((x & 0x33333333u) << 2);
    return ((x >> 4) & 0x0F0F0F0Fu) | ((x & 0x0F0F0F0Fu) << 4);
}

// A 32-bit integer hash with good avalanche (the "lowbias32" constants of C. Wellons' hash
// prospector); used to derive per-pixel/per-dimension seeds.
FACET_SAMPLER_INLINE std::uint32_t hash_u32(std::uint32_t x) {
    x ^= x >> 16;
    x *= 0x7feb352du;
    x ^= x >> 15;
    x *= 0x846ca68bu;
    x ^= x >> 16;
    return x;
}

FACET_SAMPLER_INLINE std::uint32_t hash_combine(std::uint32_t seed, std::uint32_t v) {
    return hash_u32(seed ^ (v + 0x9e3779b9u + (seed << 6) + (seed >> 2)));
}

// Owen (nested uniform) scrambling of a fixed-point number in [0,1) stored MSB-first:
// flipping bit k depends only on the bits above it. In the bit-reversed domain this becomes
// "each bit depends only on lower bits", which a multiply-xor hash with even multipliers
// provides (Laine & Karras 2011, with the improved constants of Burley 2020 §3).
FACET_SAMPLER_INLINE std::uint32_t laine_karras(std::uint32_t x, std::uint32_t seed) {
    x += seed;
    x ^= x * 0x6c50b47cu;
    x ^= x * 0xb82f1e52u;
    x ^= x * 0xc7afe638u;
    x ^= x * 0x8d22f6e6u;
    return x;
}
FACET_SAMPLER_INLINE std::uint32_t owen_scramble(std::uint32_t v, std::uint32_t seed) {
    return reverse_bits(laine_karras(reverse_bits(v), seed));
}

// First Sobol dimension: the van der Corput sequence in base 2.
FACET_SAMPLER_INLINE std::uint32_t sobol_dim0(std::uint32_t i) {
    return reverse_bits(i);
}

// Second Sobol dimension (primitive polynomial x + 1, all m_k = 1): the direction numbers are
// v_1 = 2^31, v_{k+1} = v_k ^ (v_k >> 1), so no table of direction numbers is needed. The
// generator-matrix product is evaluated a byte at a time from four 256-entry tables computed at
// compile time from that recurrence (a bit loop would run 32 times for shuffled indices).
inline constexpr std::uint32_t sobol_dim1_slow(std::uint32_t i) {
    std::uint32_t r = 0, v = 0x80000000u;
    for (; i != 0; i >>= 1, v ^= v >> 1)
        if (i & 1u) r ^= v;
    return r;
}

inline constexpr std::uint32_t reverse_bits_constexpr(std::uint32_t x) {
    std::uint32_t r = 0;
    for (int k = 0; k < 32; ++k) r |= ((x >> k) & 1u) << (31 - k);
    return r;
}

// Tables of the generator-matrix columns, stored bit-reversed (reversal is linear over XOR),
// because the Owen scramble below works in the bit-reversed domain.
inline constexpr std::array<std::array<std::uint32_t, 256>, 4> kSobolDim1ReversedTables = [] {
    std::array<std::array<std::uint32_t, 256>, 4> t{};
    for (int b = 0; b < 4; ++b)
        for (std::uint32_t x = 0; x < 256; ++x)
            t[b][x] = reverse_bits_constexpr(sobol_dim1_slow(x << (8 * b)));
    return t;
}();

// reverse_bits(sobol_dim1(i)).
FACET_SAMPLER_INLINE std::uint32_t sobol_dim1_reversed(std::uint32_t i) {
    const auto& t = kSobolDim1ReversedTables;
    return t[0][i & 0xffu] ^ t[1][(i >> 8) & 0xffu] ^ t[2][(i >> 16) & 0xffu] ^ t[3][i >> 24];
}

FACET_SAMPLER_INLINE std::uint32_t sobol_dim1(std::uint32_t i) {
    return reverse_bits(sobol_dim1_reversed(i));
}

// 32-bit fixed point -> float in [0,1): keep 24 bits so the result is exact in float.
FACET_SAMPLER_INLINE float fixed_to_float(std::uint32_t v) {
    return float(v >> 8) * 0x1p-24f;
}

// Per-pixel sample generator (a small value type: create one per pixel sample).
class Sampler {
  public:
    // `pixel_seed` identifies the pixel (see pixel_seed()); `index` is the sample index within
    // the pixel; `dimension` is where to start consuming dimensions (0 for a camera sample).
    Sampler(std::uint32_t pixel_seed, std::uint32_t index, std::uint32_t dimension = 0)
        : m_pixel_seed(pixel_seed), m_index_reversed(reverse_bits(index)), m_dimension(dimension) {}

    // Seed of pixel (x, y) for a render seed: every pixel gets an independent randomisation.
    static std::uint32_t pixel_seed(int x, int y, std::uint64_t seed) {
        std::uint32_t h = hash_u32(std::uint32_t(seed) ^ 0x5bd1e995u);
        h = hash_combine(h, std::uint32_t(seed >> 32));
        h = hash_combine(h, std::uint32_t(x));
        return hash_combine(h, std::uint32_t(y));
    }

    // One value in [0,1): a 1D Owen-scrambled van der Corput sequence over the sample indices,
    // with its own index shuffle per dimension.
    // Both getters use owen_scramble(sobol(i), seed) = reverse(laine_karras(reverse(sobol(i))))
    // with reverse(sobol_dim0(i)) = i, which saves most bit reversals; the index shuffle
    // owen_scramble(index, s) = reverse(laine_karras(reverse(index), s)) starts from the
    // reversed index the constructor stores.
    FACET_SAMPLER_INLINE float get_1d() {
        const std::uint32_t dim_seed = hash_combine(m_pixel_seed, m_dimension++);
        const std::uint32_t i = reverse_bits(laine_karras(m_index_reversed, dim_seed));  // shuffle
        return fixed_to_float(reverse_bits(laine_karras(i, hash_u32(dim_seed ^ 0xa511e9b3u))));
    }

    // A pair in [0,1)^2 from the (0,2)-sequence, shuffled and Owen-scrambled per dimension pair.
    FACET_SAMPLER_INLINE Vec2 get_2d() {
        const std::uint32_t dim_seed = hash_combine(m_pixel_seed, m_dimension++);
        const std::uint32_t i = reverse_bits(laine_karras(m_index_reversed, dim_seed));  // shuffle
        const float x =
            fixed_to_float(reverse_bits(laine_karras(i, hash_u32(dim_seed ^ 0xa511e9b3u))));
        const float y = fixed_to_float(
            reverse_bits(laine_karras(sobol_dim1_reversed(i), hash_u32(dim_seed ^ 0x63d83595u))));
        return {x, y};
    }

    std::uint32_t dimension() const { return m_dimension; }
    void set_dimension(std::uint32_t d) { m_dimension = d; }

  private:
    std::uint32_t m_pixel_seed;
    std::uint32_t m_index_reversed;  // reverse_bits(sample index)
    std::uint32_t m_dimension;
};

#undef FACET_SAMPLER_INLINE

}  // namespace facet::render
