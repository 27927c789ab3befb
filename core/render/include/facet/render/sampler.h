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

#include <cstddef>
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
// v_1 = 2^31, v_{k+1} = v_k ^ (v_k >> 1), so no table of direction numbers is needed. This is
// the reference definition (a loop over the index bits); sobol_dim1_reversed is the fast one.
inline constexpr std::uint32_t sobol_dim1_slow(std::uint32_t i) {
    std::uint32_t r = 0, v = 0x80000000u;
    for (; i != 0; i >>= 1, v ^= v >> 1)
        if (i & 1u) r ^= v;
    return r;
}

// reverse_bits(sobol_dim1(i)), without tables. v_{k+1} = (1 + S)^k 2^31 (S: shift right by 1), so
// bit 31 - j of v_{k+1} is binom(k, j) mod 2, which by Lucas' theorem is 1 exactly when the bits
// of j are a subset of the bits of k. Bit-reversed, output bit j is then the XOR of the index
// bits k that are supersets of j: the superset (Moebius) transform over GF(2) of the 5-bit bit
// positions, five masked shift-XOR steps (one per bit of j). Branch- and load-free, so the
// lane sampler below vectorises it; equal to the recurrence on every index (test).
FACET_SAMPLER_INLINE std::uint32_t sobol_dim1_reversed(std::uint32_t i) {
    i ^= (i >> 1) & 0x55555555u;
    i ^= (i >> 2) & 0x33333333u;
    i ^= (i >> 4) & 0x0F0F0F0Fu;
    i ^= (i >> 8) & 0x00FF00FFu;
    i ^= (i >> 16) & 0x0000FFFFu;
    return i;
}

FACET_SAMPLER_INLINE std::uint32_t sobol_dim1(std::uint32_t i) {
    return reverse_bits(sobol_dim1_reversed(i));
}

// 32-bit fixed point -> float in [0,1): keep 24 bits so the result is exact in float.
FACET_SAMPLER_INLINE float fixed_to_float(std::uint32_t v) {
    return float(v >> 8) * 0x1p-24f;
}

// One sample value of a pixel (seed `pixel_seed`) at sample index i (`index_reversed` =
// reverse_bits(i)) in dimension `dimension`: a 1D Owen-scrambled van der Corput sequence over
// the sample indices, with its own index shuffle per dimension. Sampler::get_1d and the lane
// sampler below are this function.
// Both getters use owen_scramble(sobol(i), seed) = reverse(laine_karras(reverse(sobol(i))))
// with reverse(sobol_dim0(i)) = i, which saves most bit reversals; the index shuffle
// owen_scramble(index, s) = reverse(laine_karras(reverse(index), s)) starts from the reversed
// index.
FACET_SAMPLER_INLINE std::uint32_t dimension_seed(std::uint32_t pixel_seed,
                                                  std::uint32_t dimension) {
    return hash_combine(pixel_seed, dimension);
}
FACET_SAMPLER_INLINE std::uint32_t shuffled_index(std::uint32_t index_reversed,
                                                  std::uint32_t dim_seed) {
    return reverse_bits(laine_karras(index_reversed, dim_seed));
}
// The Owen-scrambled first Sobol dimension at shuffled index i.
FACET_SAMPLER_INLINE float first_coordinate(std::uint32_t dim_seed, std::uint32_t i) {
    return fixed_to_float(reverse_bits(laine_karras(i, hash_u32(dim_seed ^ 0xa511e9b3u))));
}
FACET_SAMPLER_INLINE float sample_1d(std::uint32_t pixel_seed, std::uint32_t index_reversed,
                                     std::uint32_t dimension) {
    const std::uint32_t dim_seed = dimension_seed(pixel_seed, dimension);
    return first_coordinate(dim_seed, shuffled_index(index_reversed, dim_seed));
}
// The 2D sample of the dimension pair: x is sample_1d, y the (0,2)-sequence's second dimension
// at the same shuffled index with its own Owen scramble.
FACET_SAMPLER_INLINE void sample_2d(std::uint32_t pixel_seed, std::uint32_t index_reversed,
                                    std::uint32_t dimension, float& x, float& y) {
    const std::uint32_t dim_seed = dimension_seed(pixel_seed, dimension);
    const std::uint32_t i = shuffled_index(index_reversed, dim_seed);
    x = first_coordinate(dim_seed, i);
    y = fixed_to_float(
        reverse_bits(laine_karras(sobol_dim1_reversed(i), hash_u32(dim_seed ^ 0x63d83595u))));
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
        return pixel_seed_hashed(x, y, render_seed_hash(seed));
    }
    // The same in two steps, for loops over many pixels of one render: the render seed's part
    // of the hash once, then pixel_seed_hashed(x, y, render_seed_hash(seed)) per pixel (the
    // same value as pixel_seed(x, y, seed)).
    static std::uint32_t render_seed_hash(std::uint64_t seed) {
        return hash_combine(hash_u32(std::uint32_t(seed) ^ 0x5bd1e995u), std::uint32_t(seed >> 32));
    }
    static std::uint32_t pixel_seed_hashed(int x, int y, std::uint32_t render_seed_hash) {
        return pixel_seed_of_column(column_seed_hash(x, render_seed_hash), y);
    }
    // pixel_seed_hashed's two steps, for loops that reuse a column's part over many rows (the
    // tile loop): pixel_seed_of_column(column_seed_hash(x, h), y) == pixel_seed_hashed(x, y, h).
    static std::uint32_t column_seed_hash(int x, std::uint32_t render_seed_hash) {
        return hash_combine(render_seed_hash, std::uint32_t(x));
    }
    static std::uint32_t pixel_seed_of_column(std::uint32_t column_seed_hash, int y) {
        return hash_combine(column_seed_hash, std::uint32_t(y));
    }

    // One value in [0,1) (sample_1d).
    FACET_SAMPLER_INLINE float get_1d() {
        return sample_1d(m_pixel_seed, m_index_reversed, m_dimension++);
    }

    // A pair in [0,1)^2 from the (0,2)-sequence, shuffled and Owen-scrambled per dimension pair.
    FACET_SAMPLER_INLINE Vec2 get_2d() {
        Vec2 u;
        sample_2d(m_pixel_seed, m_index_reversed, m_dimension++, u.x, u.y);
        return u;
    }

    // A 64-bit seed for a generator of its own (a tracking loop that needs an unbounded number of
    // values), consuming one dimension: a hash of the pixel, the sample index and the dimension.
    std::uint64_t get_seed() {
        const std::uint32_t a =
            hash_combine(hash_combine(m_pixel_seed, m_index_reversed), m_dimension);
        const std::uint32_t b = hash_combine(a, 0x2545f491u ^ m_dimension++);
        return (std::uint64_t(a) << 32) | b;
    }

    std::uint32_t dimension() const { return m_dimension; }
    void set_dimension(std::uint32_t d) { m_dimension = d; }

  private:
    std::uint32_t m_pixel_seed;
    std::uint32_t m_index_reversed;  // reverse_bits(sample index)
    std::uint32_t m_dimension;
};

// The samples of kSamplerLanes pixels at one sample index and dimension, computed together:
// lane k is Sampler(seeds[k], index, dimension).get_1d() / get_2d() bit for bit (test). The
// path integrator's packets (8 neighbouring pixels, one path each) draw every dimension of a
// depth for all their paths at once; the loops over the lanes vectorise (an AVX2 clone is
// chosen at load time where the CPU has it), where one pixel at a time the hashing cost ~300
// instructions per path vertex. Every lane is computed; seeds of unused lanes may be anything.
inline constexpr std::size_t kSamplerLanes = 8;
void sample_1d_lanes(const std::uint32_t* seeds, std::uint32_t index, std::uint32_t dimension,
                     float* out);
void sample_2d_lanes(const std::uint32_t* seeds, std::uint32_t index, std::uint32_t dimension,
                     float* x, float* y);

#undef FACET_SAMPLER_INLINE

}  // namespace facet::render
