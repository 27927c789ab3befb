// FACET_TARGET_CLONES: compile a function twice, for the baseline x86-64 ISA and for AVX2, and
// let the loader pick the AVX2 copy where the CPU has it (GCC target_clones, an ifunc). Only for
// functions whose every clone returns the same bits (integer code, or floating point built
// with -ffp-contract=off), so that images do not depend on the machine. Off under
// AddressSanitizer and off elsewhere than GCC on x86-64: one baseline copy.
#pragma once

#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__) && \
    !defined(__SANITIZE_ADDRESS__)
#define FACET_TARGET_CLONES __attribute__((target_clones("avx2", "default")))
#else
#define FACET_TARGET_CLONES
#endif
