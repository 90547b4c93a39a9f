#pragma once
// What every secchi header shares: the instruction-set tag of secchi's namespace.
//
// secchi is header-only, so its inline functions are compiled into each translation unit with
// that unit's flags. A program whose units are built for different instruction sets (some with
// -mavx2 or -march=native, some without) would otherwise hold two compilations of one inline
// function under one name, and the linker keeps either: code for AVX2 could run on a machine
// without it, or lanes of four doubles meet lanes of two (a violation of the one-definition
// rule). Every declaration therefore lives in an inline namespace named after the instruction
// sets the unit is compiled for, e.g. secchi::isa_sse42_avx_avx2_fma: `secchi::X` names it
// as before, while units built for different targets get distinct symbols. Written in each
// header as `namespace secchi::SECCHI_ISA { ... }` (C++20's `namespace a::inline b`).
//
// The tag covers the x86 extensions secchi's code paths depend on (SSE4.2, AVX, AVX2, FMA,
// AVX-512 F, DQ, VL, BW); elsewhere it is `isa`. Other flags that change generated code
// (-ffast-math, -ffp-contract) are not part of it: build the units that share secchi's types
// with the same ones. Objects of secchi's types cannot be passed between units of different
// tags (they are different types): keep each renderer-facing object within one target.

#if defined(__SSE4_2__)
#define SECCHI_ISA_SSE42 _sse42
#else
#define SECCHI_ISA_SSE42
#endif
#if defined(__AVX__)
#define SECCHI_ISA_AVX _avx
#else
#define SECCHI_ISA_AVX
#endif
#if defined(__AVX2__)
#define SECCHI_ISA_AVX2 _avx2
#else
#define SECCHI_ISA_AVX2
#endif
#if defined(__FMA__)
#define SECCHI_ISA_FMA _fma
#else
#define SECCHI_ISA_FMA
#endif
#if defined(__AVX512F__)
#define SECCHI_ISA_AVX512F _avx512f
#else
#define SECCHI_ISA_AVX512F
#endif
#if defined(__AVX512DQ__)
#define SECCHI_ISA_AVX512DQ _dq
#else
#define SECCHI_ISA_AVX512DQ
#endif
#if defined(__AVX512VL__)
#define SECCHI_ISA_AVX512VL _vl
#else
#define SECCHI_ISA_AVX512VL
#endif
#if defined(__AVX512BW__)
#define SECCHI_ISA_AVX512BW _bw
#else
#define SECCHI_ISA_AVX512BW
#endif

#define SECCHI_ISA_PASTE(a, b, c, d, e, f, g, h) isa##a##b##c##d##e##f##g##h
#define SECCHI_ISA_NAME_OF(a, b, c, d, e, f, g, h) SECCHI_ISA_PASTE(a, b, c, d, e, f, g, h)
/// The inline namespace's name for this unit's target, e.g. isa_sse42_avx_avx2_fma.
#define SECCHI_ISA_NAME                                                                                   \
    SECCHI_ISA_NAME_OF(SECCHI_ISA_SSE42, SECCHI_ISA_AVX, SECCHI_ISA_AVX2, SECCHI_ISA_FMA, SECCHI_ISA_AVX512F, \
                       SECCHI_ISA_AVX512DQ, SECCHI_ISA_AVX512VL, SECCHI_ISA_AVX512BW)
/// What a header writes after `namespace secchi::`.
#define SECCHI_ISA inline SECCHI_ISA_NAME

#define SECCHI_ISA_STRING_OF(x) #x
#define SECCHI_ISA_STRING(x) SECCHI_ISA_STRING_OF(x)

namespace secchi::SECCHI_ISA {
/// The tag of the namespace this unit's secchi lives in (e.g. "isa_sse42_avx_avx2_fma").
inline constexpr const char* isa_tag = SECCHI_ISA_STRING(SECCHI_ISA_NAME);
}  // namespace secchi::SECCHI_ISA
