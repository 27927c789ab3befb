// The lane sampler (facet/render/sampler.h): the scalar sample functions over 8 lanes, in loops
// that GCC vectorises (integer multiplies, shifts, byte swaps). Lanes are independent and each
// runs exactly the scalar function, so every clone returns the same bits.
#include "facet/render/sampler.h"

#include "facet/target_clones.h"

namespace facet::render {

FACET_TARGET_CLONES
void sample_1d_lanes(const std::uint32_t* seeds, std::uint32_t index, std::uint32_t dimension,
                     float* out) {
    const std::uint32_t ir = reverse_bits(index);
    for (std::size_t k = 0; k < kSamplerLanes; ++k) out[k] = sample_1d(seeds[k], ir, dimension);
}

FACET_TARGET_CLONES
void sample_2d_lanes(const std::uint32_t* seeds, std::uint32_t index, std::uint32_t dimension,
                     float* x, float* y) {
    const std::uint32_t ir = reverse_bits(index);
    for (std::size_t k = 0; k < kSamplerLanes; ++k) sample_2d(seeds[k], ir, dimension, x[k], y[k]);
}

}  // namespace facet::render
