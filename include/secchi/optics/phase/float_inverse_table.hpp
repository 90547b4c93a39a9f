#pragma once
// A phase function's inverse CDF, cos psi as a function of the uniform u, tabulated for photons
// in float lanes (transport/lane_tracer.hpp with Real = float): one table row and one cubic
// per lane, in place of the phase function's own inverse (for a table, a root per photon:
// tabulated.hpp). Float lanes keep directions in float, so cos psi is wanted to float
// resolution; the table gives it within 2^-23 of the exact inverse at the same u (below).
//
// Cells. Let s = u on the forward half (u <= 1/2) and s = 1 - u on the backward half (exact in
// float). A cell holds the floats s in [2^-25, 1/2] that share their exponent and their
// leading mantissa_bits bits of mantissa: its width is 2^-mantissa_bits of s, so the cells
// are finest at both ends of the distribution. There cos psi has a square-root singularity
// in u: near 180 deg the mass beyond psi goes as (pi - psi)^2, so pi - psi ~ sqrt(1 - u), and
// where p is linear in psi cos psi gains a (1 - u)^(3/2) term (likewise near 0 deg without a
// power law); cells of equal width in u interpolate it to only ~1e-6 with 2^13 of them. A
// float's cell is its bits shifted right, its place t in the cell its low bits scaled: both
// exact, so the only roundings are the cubic's. s = 0 (u = 0 or 1: a float lane's uniform is 1
// once in 2^24 draws, core/rng.hpp's uniform_float_from_bits) has a row of its own, the exact
// value; so has every s in (0, 2^-25), which no float lane's uniform takes.
//
// Interpolation. On each cell the cubic Hermite interpolant of cos psi between its ends, with
// the slopes d(cos psi)/du = -1 / (2 pi p(cos psi)) (the CDF's definition: du = 2 pi p d(-mu)),
// from the phase function's own exact inverse (sample_direction(u, 0).cos_psi) and density
// (eval). In float: mu(t) = c0 + t (a1 + t (a2 + t a3)), c0 the nearest float to cos psi at
// the cell's start and the other coefficients fitted to that c0.
//
// Accuracy. When built, each cell's cubic is compared with the exact inverse at the cell's
// middle, where the Hermite remainder f''''(xi) h^4 t^2 (1 - t)^2 / 24 peaks; the table is
// used (usable()) only where the largest difference, max_error(), is at most 2^-24 (c0's
// rounding, up to 2^-25 at the cell's start, carries half into the middle; a phase function
// with finer structure than the cells is refused, and its float lanes take its double
// sampler). Adding the float evaluation's rounding (half an ulp of |mu| <= 1, 2^-25, and the
// small terms' own), cos psi lies within 2^-23 of the exact inverse's at the same float u
// (tests/test_lane_tracer.cpp checks it at every float uniform for Petzold's canonical table,
// and at every cell's ends).
//
// Memory: 2 x (24 x 2^mantissa_bits + 2) rows of 16 bytes (192 kB with 8 bits), shared by the
// copies of the phase function that holds it; built in about 2 ms (Petzold's table).
#include "secchi/core/config.hpp"
#include "secchi/core/lanes.hpp"
#include "secchi/core/math.hpp"
#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <vector>

#if SECCHI_HAS_LANES
namespace secchi::SECCHI_ISA {

class FloatInverseTable {
public:
    /// Leading mantissa bits that select a cell within a binade of s.
    static constexpr int mantissa_bits = 8;
    /// The largest midpoint error (absolute, in cos psi) at which the table is used.
    static constexpr double error_limit = 0x1p-24;

    /// The table of `phase` (anything with sample_direction(u1, u2).cos_psi, monotone in u1,
    /// and eval(cos_psi), its density per steradian).
    template <class Phase>
    explicit FloatInverseTable(const Phase& phase) {
        const auto inverse = [&](double u) { return phase.sample_direction(u, 0.0).cos_psi; };
        const auto slope = [&](double mu) {  // d(cos psi)/du; 0 where p is infinite (a power law at 0 deg)
            const double p = phase.eval(mu);
            return std::isfinite(p) && p > 0.0 ? -1.0 / (two_pi * p) : 0.0;
        };
        rows_.reserve(2 * rows_per_side);
        for (int side = 0; side < 2; ++side) {  // 0: u = s, 1: u = 1 - s
            const auto u_of = [&](double s) { return side == 0 ? s : 1.0 - s; };
            const double du_ds = side == 0 ? 1.0 : -1.0;
            rows_.push_back({static_cast<float>(inverse(u_of(0.0))), 0.0f, 0.0f, 0.0f});  // s = 0
            double s0 = start_of(0), mu0 = inverse(u_of(s0)), slope0 = slope(mu0);
            for (std::uint32_t c = 0; c < cells_per_side; ++c) {
                const double s1 = start_of(c + 1), h = s1 - s0;  // exact
                const double mu1 = inverse(u_of(s1)), slope1 = slope(mu1);
                const Row row = hermite(mu0, mu1, h * du_ds * slope0, h * du_ds * slope1);
                const double mid = inverse(u_of(s0 + 0.5 * h));
                max_error_ = std::max(max_error_, std::abs(evaluate(row, 0.5) - mid));
                rows_.push_back(row);
                s0 = s1, mu0 = mu1, slope0 = slope1;
            }
        }
        if (!(max_error_ <= error_limit)) rows_ = std::vector<Row>();  // refused (a NaN too)
    }

    /// Whether the table meets error_limit (else it holds no rows and must not be used).
    [[nodiscard]] bool usable() const { return !rows_.empty(); }
    /// The largest difference from the exact inverse at the cells' middles.
    [[nodiscard]] double max_error() const { return max_error_; }
    [[nodiscard]] std::size_t memory_bytes() const { return rows_.capacity() * sizeof(Row); }
    /// The uniforms where the cells begin and end (for tests): u = s and u = 1 - s for every
    /// cell boundary s in [2^-25, 1/2].
    [[nodiscard]] std::vector<float> cell_boundaries() const {
        std::vector<float> u;
        for (std::uint32_t c = 0; c <= cells_per_side; ++c) {
            const float s = static_cast<float>(start_of(c));
            if (s <= 0.5f) u.insert(u.end(), {s, 1.0f - s});
        }
        return u;
    }

    /// cos psi for a vector of float uniforms u in [0, 1] (usable() only).
    [[nodiscard]] SECCHI_KERNEL lanes::Floats cos_psi(const lanes::Floats& u) const {
        using lanes::Floats, lanes::stdx::max;
        using Words32 = lanes::stdx::rebind_simd_t<std::uint32_t, Floats>;
        constexpr int width = static_cast<int>(Floats::size());
        const auto backward = u > 0.5f;
        const Floats s = select(backward, Floats(1.0f) - u, u);  // 1 - u exact for u > 1/2
        const Words32 bits = lanes::stdx::__proposed::simd_bit_cast<Words32>(s);
        const Words32 side = lanes::stdx::static_simd_cast<Words32>(select(backward, Floats(float(rows_per_side)), Floats(0.0f)));
        const Words32 cell = max(bits >> shift, Words32(first_cell - 1)) - Words32(first_cell - 1) + side;  // row 0: s < 2^-25
        const Floats t = lanes::stdx::static_simd_cast<Floats>(bits & Words32(low_mask)) * Floats(t_scale);
        alignas(64) std::uint32_t index[width];
        alignas(64) float c0[width], a1[width], a2[width], a3[width];
        cell.copy_to(index, lanes::aligned);
        for (int l = 0; l < width; ++l) {
            const Row& r = rows_[index[l]];
            c0[l] = r.c0, a1[l] = r.a1, a2[l] = r.a2, a3[l] = r.a3;
        }
        const Floats mu = Floats(c0, lanes::aligned) +
                          t * (Floats(a1, lanes::aligned) + t * (Floats(a2, lanes::aligned) + t * Floats(a3, lanes::aligned)));
        return clamp_cosine(mu);
    }

private:
    struct Row {
        float c0, a1, a2, a3;
    };
    static constexpr int shift = 23 - mantissa_bits;
    static constexpr float t_scale = 1.0f / static_cast<float>(1u << shift);  // 2^-shift, exact
    static constexpr float smallest_s = 0x1p-25f;
    static constexpr std::uint32_t low_mask = (1u << shift) - 1u;
    static constexpr std::uint32_t first_cell = std::bit_cast<std::uint32_t>(smallest_s) >> shift;
    /// Cells from 2^-25 up to and including the one that starts at 1/2 (where s = 1/2 falls).
    static constexpr std::uint32_t cells_per_side = (std::bit_cast<std::uint32_t>(0.5f) >> shift) - first_cell + 1;
    static constexpr std::uint32_t rows_per_side = cells_per_side + 1;  // and the row of s = 0 first
    static_assert(first_cell > 0 && rows_per_side < (1u << 24), "the side's offset is exact in float");

    /// Where cell c of a side begins (s, exactly; c = cells_per_side: where the last one ends).
    static double start_of(std::uint32_t c) { return std::bit_cast<float>((first_cell + c) << shift); }

    /// The cubic through mu0 and mu1 with slopes d0 and d1 per unit t, constant term in float.
    static Row hermite(double mu0, double mu1, double d0, double d1) {
        const float c0 = static_cast<float>(mu0);
        const double delta = mu1 - c0;
        return {c0, static_cast<float>(d0), static_cast<float>(3.0 * delta - 2.0 * d0 - d1),
                static_cast<float>(d0 + d1 - 2.0 * delta)};
    }
    /// A row's cubic at t, in double (the interpolation alone, without the lanes' rounding).
    static double evaluate(const Row& r, double t) {
        return r.c0 + t * (r.a1 + t * (r.a2 + t * static_cast<double>(r.a3)));
    }

    std::vector<Row> rows_;
    double max_error_ = 0.0;
};

}  // namespace secchi::SECCHI_ISA
#endif
